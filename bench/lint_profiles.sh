#!/usr/bin/env bash
# How many files the material rules warn on under each lint profile: every metal-rough file of
# ../shared/assets as it is, and every spec-gloss file after `gltf-pbr convert`. Prints, per file,
# the warnings and errors of the material step (count and codes) under tolerant and strict.
#   bench/lint_profiles.sh GLTF_PBR_CLI
set -euo pipefail
cli=$1
root=$(cd "$(dirname "$0")/.." && pwd)
assets="$root/../shared/assets"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

mkdir -p "$work/specgloss"
for folder in "$assets"/*/specgloss; do
  asset=$(basename "$(dirname "$folder")")
  cp -r "$folder" "$work/specgloss/$asset"
done
"$cli" convert "$work/specgloss" -o "$work/converted" -q >/dev/null 2>&1 || true

name_of() {  # a file's name relative to the shared assets or to the converted folder
  local name=${1#"$assets/"}
  echo "${name#"$work/converted/specgloss/"}"
}

table() {  # table LABEL FILE...
  local label=$1
  shift
  for profile in tolerant strict; do
    for file in "$@"; do
      "$cli" validate --only materials --profile "$profile" -f json "$file" 2>/dev/null |
        python3 -c '
import json, sys
report = json.load(sys.stdin)
problems = [m for m in report["issues"]["messages"] if m["severity"] <= 1]
print(sys.argv[1], sys.argv[2], len(problems), ",".join(sorted({m["code"] for m in problems})) or "-")
' "$profile" "$(name_of "$file")" || true
    done
  done | python3 -c '
import collections, sys
label = sys.argv[1]
rows = collections.OrderedDict()
for line in sys.stdin:
    profile, name, count, codes = line.split()
    rows.setdefault(name, {})[profile] = (int(count), codes)
print(f"\n{label}: {len(rows)} files")
print(f"| file | tolerant | strict |\n|---|---|---|")
for name, by in rows.items():
    cells = [f"{by[p][0]} ({by[p][1]})" if by[p][0] else "0" for p in ("tolerant", "strict")]
    print(f"| {name} | {cells[0]} | {cells[1]} |")
for profile in ("tolerant", "strict"):
    warned = sum(1 for by in rows.values() if by[profile][0])
    print(f"{profile}: {warned} of {len(rows)} files warn")
' "$label"
}

mapfile -t metal_rough < <(find "$assets" -path '*/metalrough*/*' \( -name '*.gltf' -o -name '*.glb' \) | sort)
table "metal-rough files of ../shared/assets" "${metal_rough[@]}"
mapfile -t converted < <(find "$work/converted" \( -name '*.gltf' -o -name '*.glb' \) | sort)
table "spec-gloss files after gltf-pbr convert" "${converted[@]}"
