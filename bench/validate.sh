#!/usr/bin/env bash
# Benchmark of `gltf-pbr validate` against the Khronos glTF-Validator (npm gltf-validator, installed
# into a cache folder by peers.sh), in one run on this machine:
#   - the whole ../shared/validator-suite in one process,
#   - every file in ../shared/assets,
#   - synthetic GLBs of 1M vertices / 2M triangles and 4M / 8M (generated into the cache folder),
#   - a glTF with a million issues (one per vertex), listed as we do by default and in full.
# Prints markdown: median wall time of RUNS runs, peak memory, and our / peer ratios; then every
# step (ours) against structure only (the peer) on Avocado and the 1M grid.
#   bench/validate.sh [SHARED_DIR]        (RUNS=3 by default; BENCH_BINARY, ONLY: see below)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$here/.."
shared="$(cd "${1:-$root/../shared}" && pwd)"
command -v /usr/bin/time >/dev/null || { apt-get install -y -qq time >/dev/null; }
eval "$("$here/peers.sh")"
# BENCH_BINARY=path: time that gltf-pbr instead of building build-bench (Release); ONLY=million: only
# the million-issue section.
binary="${BENCH_BINARY:-$root/build-bench/gltf-pbr}"
if [ -z "${BENCH_BINARY:-}" ]; then
  cmake -S "$root" -B "$root/build-bench" -G Ninja -DCMAKE_BUILD_TYPE=Release -DGLTF_PBR_TESTS=OFF >/dev/null
  cmake --build "$root/build-bench" >/dev/null
fi
large="${GLTF_PBR_CACHE:-$HOME/.cache/gltf-pbr}/bench"
mkdir -p "$large"
[ -f "$large/grid-1M.glb" ] || node "$here/make_grid_glb.mjs" 1000 "$large/grid-1M.glb"
[ -f "$large/grid-4M.glb" ] || node "$here/make_grid_glb.mjs" 2000 "$large/grid-4M.glb"
[ -f "$large/million-issues.gltf" ] || node "$here/make_million_issues.mjs" 1000000 "$large/million-issues.gltf"
GLTF_PBR="$binary" ONLY="${ONLY:-}" GLTF_PBR_NODE_MODULES="$GLTF_PBR_NODE_MODULES" \
  GLTF_VALIDATOR_VERSION="$GLTF_VALIDATOR_VERSION" RUNS="${RUNS:-3}" \
  node "$here/validate.mjs" "$shared" "$large"
