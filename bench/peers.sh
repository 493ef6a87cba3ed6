#!/usr/bin/env bash
# Installs the npm peers we benchmark and validate against into a cache folder
# (never into the repo) and prints where they are as shell assignments:
#
#   eval "$(bench/peers.sh)"
#   "$GLTF_TRANSFORM" metalrough in.gltf out.gltf
#   GLTF_PBR_NODE_MODULES="$GLTF_PBR_NODE_MODULES" node "$GLTF_VALIDATOR_JS" a.gltf
#
# Idempotent: a second run only checks installed versions. All progress goes to
# stderr so that stdout stays eval-able.
set -euo pipefail

cache="${GLTF_PBR_CACHE:-$HOME/.cache/gltf-pbr}/npm"
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

# Debian 12 ships node 18; everything else here (CI images, dev boxes) tends to
# have 20+. Only pull in the distro packages when node is absent altogether.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "peers.sh: installing nodejs and npm from apt" >&2
  $sudo apt-get update >&2
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y nodejs npm >&2
fi

# Exact pins so benchmark numbers are comparable between runs. The CLI's own
# dependencies use ^/~ ranges, so "overrides" also pins the @gltf-transform
# libraries that do the actual work to the CLI's version.
# @gltf-transform/cli 4.4.0+ declares node >= 20 (sharp 0.35 needs it), so on
# Debian's node 18 we fall back to 4.3.0, the last release that supports 18, and
# hold ndarray-pixels at 5.0.1: 5.2.0 pulls in sharp 0.35, which crashes on 18.
node_major="$(node -p 'process.versions.node.split(".")[0]')"
if [ "$node_major" -ge 20 ]; then
  cli_version="4.5.1"; pixels_version="5.2.0"
else
  cli_version="4.3.0"; pixels_version="5.0.1"
fi
validator_version="2.0.0-dev.3.10"

manifest="$(cat <<EOF
{
  "private": true,
  "dependencies": {
    "@gltf-transform/cli": "$cli_version",
    "gltf-validator": "$validator_version"
  },
  "overrides": {
    "@gltf-transform/core": "$cli_version",
    "@gltf-transform/extensions": "$cli_version",
    "@gltf-transform/functions": "$cli_version",
    "ndarray-pixels": "$pixels_version"
  }
}
EOF
)"

# Prints the installed version of package $1, or nothing if it is not installed.
installed_version() {
  local package_json="$cache/node_modules/$1/package.json"
  if [ -f "$package_json" ]; then node -p "require(process.argv[1]).version" "$package_json"; fi
}

if [ "$manifest" != "$(cat "$cache/package.json" 2>/dev/null)" ] ||
   [ "$(installed_version @gltf-transform/cli)" != "$cli_version" ] ||
   [ "$(installed_version gltf-validator)" != "$validator_version" ]; then
  echo "peers.sh: installing @gltf-transform/cli@$cli_version gltf-validator@$validator_version into $cache" >&2
  # Start clean: a lockfile left by the other node major would keep its versions.
  mkdir -p "$cache"
  rm -rf "$cache/node_modules" "$cache/package-lock.json"
  printf '%s\n' "$manifest" >"$cache/package.json"
  # --prefix keeps node_modules and the lockfile inside the cache folder.
  npm install --prefix "$cache" --no-audit --no-fund --loglevel=error >&2
fi

# %q quotes paths that contain spaces or shell metacharacters.
printf 'GLTF_TRANSFORM=%q\n' "$cache/node_modules/.bin/gltf-transform"
printf 'GLTF_PBR_NODE_MODULES=%q\n' "$cache/node_modules"
printf 'GLTF_VALIDATOR_JS=%q\n' "$repo_root/tests/peer/validate.mjs"
printf 'GLTF_TRANSFORM_VERSION=%q\n' "$cli_version"
printf 'GLTF_VALIDATOR_VERSION=%q\n' "$validator_version"
