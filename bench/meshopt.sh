#!/usr/bin/env bash
# What EXT_meshopt_compression costs `gltf-pbr validate` and `convert`: each shared asset packed by
# gltfpack (npm, tests/peer/gltfpack.sh) losslessly (-noq) with and without compression, then the
# two run alternately, RUNS times each, with medians, their ratio and peak memory.
#   bench/meshopt.sh GLTF_PBR_CLI [RUNS] [ASSET...]
set -euo pipefail
cli=$1
shift
runs=${1:-5}
[ $# -gt 0 ] && shift
if [ $# -gt 0 ]; then assets=("$@"); else assets=(VC 2CylinderEngine CesiumMilkTruck); fi
root=$(cd "$(dirname "$0")/.." && pwd)
source "$root/tests/peer/gltfpack.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# median of the numbers on stdin
median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# seconds and peak KiB of one run, as "s kib"
measure() { /usr/bin/time -f "%e %M" -o "$work/time" "$@" >/dev/null 2>&1 || true; cat "$work/time"; }

printf '%-16s %-8s %8s %10s %10s %8s %9s %9s\n' asset step "MiB in" "plain s" "packed s" ratio "plain MB" "packed MB"
for asset in "${assets[@]}"; do
  source_file="$root/../shared/assets/$asset/specgloss/$asset.gltf"
  mkdir -p "$work/$asset/plain" "$work/$asset/packed"
  "$GLTF_PBR_GLTFPACK" -noq -i "$source_file" -o "$work/$asset/plain/a.glb" >/dev/null
  "$GLTF_PBR_GLTFPACK" -noq -c -i "$source_file" -o "$work/$asset/packed/a.glb" >/dev/null
  for step in validate convert; do
    : > "$work/plain.t"; : > "$work/packed.t"
    for ((r = 0; r < runs; r++)); do
      for kind in plain packed; do
        if [ "$step" = validate ]; then
          measure "$cli" validate "$work/$asset/$kind/a.glb" >> "$work/$kind.t"
        else
          measure "$cli" convert "$work/$asset/$kind/a.glb" -o "$work/$asset/$kind-out/a.glb" -q >> "$work/$kind.t"
        fi
      done
    done
    plain_s=$(cut -d' ' -f1 "$work/plain.t" | median); packed_s=$(cut -d' ' -f1 "$work/packed.t" | median)
    plain_kb=$(cut -d' ' -f2 "$work/plain.t" | median); packed_kb=$(cut -d' ' -f2 "$work/packed.t" | median)
    awk -v a="$asset" -v s="$step" -v size="$(stat -c %s "$work/$asset/plain/a.glb")" -v ps="$plain_s" \
      -v cs="$packed_s" -v pk="$plain_kb" -v ck="$packed_kb" \
      'BEGIN { printf "%-16s %-8s %8.2f %10.3f %10.3f %8.2f %9.0f %9.0f\n", a, s, size / 1048576, ps, cs, cs / ps, pk / 1024, ck / 1024 }'
  done
  awk -v a="$asset" -v packed="$(stat -c %s "$work/$asset/packed/a.glb")" -v plain="$(stat -c %s "$work/$asset/plain/a.glb")" \
    'BEGIN { printf "%-16s packed file %.0f%% of the plain one\n", a, 100 * packed / plain }'
done
