#!/usr/bin/env bash
# Converts every spec-gloss asset in ../shared/assets with the gltf-pbr CLI, in both targets, and
# checks each output with the Khronos glTF-Validator (npm `gltf-validator`): no output may have an
# Error or Warning code more often than its input already had it.
#   converted_assets_validate.sh GLTF_PBR_CLI SHARED_DIR
set -euo pipefail
cli=$1
shared=$2
here=$(cd "$(dirname "$0")" && pwd)

source "$here/npm_validator.sh"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mapfile -t inputs < <(find "$shared/assets" -path '*specgloss*' \( -name '*.gltf' -o -name '*.glb' \) | sort)
[ "${#inputs[@]}" -ge 13 ] || { echo "expected at least 13 spec-gloss inputs, found ${#inputs[@]}" >&2; exit 1; }

pairs=()
for target in metalness specular; do
  for i in "${!inputs[@]}"; do
    input=${inputs[$i]}
    output="$work/$target/$i/$(basename "$input")"
    "$cli" convert "$input" -o "$output" --target "$target" -q
    pairs+=("$input" "$output")
  done
done

node "$here/validate.mjs" "${pairs[@]}" > "$work/reports.json"
node - "$work/reports.json" "${pairs[@]}" <<'JS'
const fs = require('fs');
const [reportsPath, ...files] = process.argv.slice(2);
const reports = JSON.parse(fs.readFileSync(reportsPath, 'utf8'));
let failures = 0, checked = 0;
for (let i = 0; i < files.length; i += 2) {
  const before = reports[files[i]].codes, after = reports[files[i + 1]].codes;
  const added = Object.entries(after)
    .filter(([code, n]) => /^(Error|Warning):/.test(code) && n > (before[code] || 0))
    .map(([code, n]) => `${code} ${before[code] || 0} -> ${n}`);
  checked++;
  const r = reports[files[i + 1]];
  console.log(`${added.length ? 'FAIL' : 'ok  '} ${files[i + 1].split('/').slice(-3).join('/')}: ` +
              `${r.numErrors} errors, ${r.numWarnings} warnings, ${r.numInfos} infos, ${r.numHints} hints` +
              (added.length ? ` (new: ${added.join(', ')})` : ''));
  if (added.length) failures++;
}
console.log(`${checked - failures} passed, ${failures} failed`);
process.exit(failures ? 1 : 0);
JS
