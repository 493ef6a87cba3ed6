#!/usr/bin/env bash
# A/B of two gltf-pbr builds on the same machine in one run: each workload runs RUNS times, the two
# binaries alternating run by run; prints the median wall seconds, the ratio B / A and the median
# peak memory (MiB) of each. For "did this change make anything slower": build the commit before it
# into another folder (same CMAKE_BUILD_TYPE) and compare.
#   bench/ab.sh A_BINARY B_BINARY [SHARED_DIR]      (RUNS=5; ONLY="name ..." picks workloads)
set -euo pipefail
a=$1 b=$2
shared=${3:-$(cd "$(dirname "$0")/../../shared" && pwd)}
assets=$shared/assets
runs=${RUNS:-5}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
declare -A workloads=(
  [validate_avocado]="validate $assets/Avocado/specgloss/Avocado.gltf -f json -o $out/run/v.json"
  [validate_engine_draco]="validate $assets/2CylinderEngine/metalrough-draco/2CylinderEngine.gltf -f json -o $out/run/v.json"
  [validate_assets_structure]="validate $assets --only structure -f json -o $out/run/v"
  [validate_suite_structure]="validate $shared/validator-suite --only structure -f json -o $out/run/v"
  [validate_vc]="validate $assets/VC/specgloss/VC.gltf -f json -o $out/run/v.json"
  [convert_engine]="convert $assets/2CylinderEngine/specgloss/2CylinderEngine.gltf -o $out/run/2CylinderEngine.gltf"
  [convert_avocado]="convert $assets/Avocado/specgloss/Avocado.gltf -o $out/run/Avocado.gltf"
  [convert_vc]="convert $assets/VC/specgloss/VC.gltf -o $out/run/VC.gltf"
  [convert_avocado_appearance]="convert $assets/Avocado/specgloss/Avocado.gltf -o $out/run/Avocado.gltf --error-model appearance"
  [preview_avocado_512]="preview $assets/Avocado/specgloss/Avocado.gltf -o $out/run/p --size 512 --no-gallery"
)
order="validate_avocado validate_vc validate_engine_draco validate_assets_structure validate_suite_structure convert_engine convert_avocado convert_avocado_appearance convert_vc preview_avocado_512"
median() { sort -n | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }
echo "| workload | A s | B s | B / A | A MiB | B MiB |"
echo "|---|---|---|---|---|---|"
for name in ${ONLY:-$order}; do
  : > "$out/a.t"; : > "$out/b.t"
  for _ in $(seq "$runs"); do
    for side in a b; do
      binary=$a; [ "$side" = b ] && binary=$b
      rm -rf "$out/run"; mkdir -p "$out/run"
      # Exit 1 (issues found) is a result here, not a failure; time's last line is "seconds KiB".
      /usr/bin/time -f "%e %M" -o "$out/one" $binary ${workloads[$name]} > /dev/null 2>&1 || true
      tail -1 "$out/one" >> "$out/$side.t"
    done
  done
  ta=$(cut -d' ' -f1 "$out/a.t" | median); tb=$(cut -d' ' -f1 "$out/b.t" | median)
  ma=$(cut -d' ' -f2 "$out/a.t" | median); mb=$(cut -d' ' -f2 "$out/b.t" | median)
  ratio=$(awk -v a="$ta" -v b="$tb" 'BEGIN { printf "%.2f", (a > 0 ? b / a : 0) }')
  printf "| %s | %s | %s | %s | %d | %d |\n" "$name" "$ta" "$tb" "$ratio" $((ma / 1024)) $((mb / 1024))
done
