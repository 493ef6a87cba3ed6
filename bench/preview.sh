#!/usr/bin/env bash
# Preview renderer against Blender 3.4 Cycles (GitHub issue 5), per asset and size:
#   - ours: `gltf-pbr preview IN -o DIR --size N` (Release build); render time = raster + G-buffer
#     resolve + lighting of both sides (+ tone mapping) from report.json "times_ms", with the
#     G-buffer pass (raster + resolve) and lighting per side in ms per megapixel; and the
#     whole process (load, in-memory conversion, scene, environment, PNGs) by wall clock;
#   - Blender: `blender -b --factory-startup --python bench/preview/blender_render.py` with our
#     report's camera and our built-in sky written out as .hdr (the sun as a small disc of the same
#     irradiance), Cycles on the CPU at 32 samples (16 leaves ΔE2000 1.6 of noise against 64, 32
#     leaves 0.9), no denoiser, whole process by wall clock;
#   - fidelity: LDR-FLIP mean of our "before" image against Blender's (the reference) over the
#     image, CIEDE2000 over the pixels the asset covers, and RMS-dB over the image. Blender
#     imports spec-gloss as Diffuse + Glossy added (no Fresnel, no energy split): a peer, not a
#     ground truth.
# Usage: bench/preview.sh [OUT_DIR]   (env: SAMPLES=32, SIZES="512 1024", ASSETS="Avocado ...", RUNS=3,
#        BUILD_DIR=build-preview-release)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-/tmp/gltf-pbr-preview-bench}
build=${BUILD_DIR:-$root/build-preview-release}
assets_dir=${ASSETS_DIR:-$root/../shared/assets}
samples=${SAMPLES:-32}
runs=${RUNS:-3}
sizes=${SIZES:-"512 1024"}
assets=${ASSETS:-"Avocado CesiumMilkTruck 2CylinderEngine VC"}
mkdir -p "$out"
# The peer (Debian's Blender 3.4) and GNU time for peak memory, installed when missing.
if ! command -v blender >/dev/null || [ ! -x /usr/bin/time ]; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq blender time >/dev/null
fi

cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DGLTF_PBR_TESTS=OFF >/dev/null
cmake --build "$build" -j2 --target gltf-pbr gltf-pbr-preview-peer >/dev/null
gltf_pbr=$build/gltf-pbr
peer=$build/preview/gltf-pbr-preview-peer

"$peer" sky "$out/sky.hdr"

wall_seconds() {  # wall_seconds LOG COMMAND...: runs COMMAND, prints its wall time in seconds
  local log=$1
  shift
  local start end
  start=$(date +%s.%N)
  /usr/bin/time -f %M -o "$log.peak-kb" "$@" >"$log" 2>&1  # peak RSS in KiB, beside the log
  end=$(date +%s.%N)
  echo "$start $end" | awk '{printf "%.2f", $2 - $1}'
}

median() { printf '%s\n' "$@" | sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

echo "load average: $(cut -d' ' -f1-3 /proc/loadavg); $(nproc) cores; Cycles CPU, $samples samples; medians of $runs runs"
printf '%-16s %5s | %9s %9s %9s %8s | %8s | %8s %8s | %6s %8s %8s\n' asset size "gbuf/MP" "light/MP" "render ms" \
  "ours s" "blender s" "x render" "x proc" "FLIP" "ΔE mean" "RMS dB"
for asset in $assets; do
  input=$assets_dir/$asset/specgloss/$asset.gltf
  for size in $sizes; do
    dir=$out/$asset-$size
    mkdir -p "$dir"
    ours_s=$(wall_seconds "$dir/ours.log" "$gltf_pbr" preview "$input" -o "$dir/ours" --size "$size")
    ours_runs=("$ours_s")
    # Our camera in the form blender_render.py reads. The automatic framing has no roll: its up
    # is world +Y (raster.cpp frame_camera), which the script maps to Blender's +Z.
    python3 - "$dir/ours/report.json" "$dir/camera.json" <<'EOF'
import json, math, sys
report = json.load(open(sys.argv[1]))
c = report["camera"]
eye, forward = c["eye"], c["forward"]
# near/far: blender_render.py's defaults (0.01, 1000) clip 2CylinderEngine (millimetres, eye 1.2 km
# away); a ray tracer needs no tight range, so span the eye's distance generously on both sides.
distance = math.sqrt(sum(e * e for e in eye)) or 1.0
json.dump({"position": eye, "target": [e + f for e, f in zip(eye, forward)], "up": [0, 1, 0],
           "yfovRadians": c["vertical_fov_degrees"] * math.pi / 180,
           "near": distance * 1e-4, "far": distance * 1e3}, open(sys.argv[2], "w"))
EOF
    # Ours and Blender's alternate, RUNS times each; the medians are compared.
    blender_runs=()
    for run in $(seq "$runs"); do
      [ "$run" -eq 1 ] || ours_runs+=("$(wall_seconds "$dir/ours.log" "$gltf_pbr" preview "$input" -o "$dir/ours" \
        --size "$size")")
      blender_runs+=("$(wall_seconds "$dir/blender.log" blender -b --factory-startup --python \
        "$root/bench/preview/blender_render.py" -- "$input" "$dir/blender.png" "$size" "$samples" \
        "$dir/camera.json" "$out/sky.hdr")")
    done
    ours_s=$(median "${ours_runs[@]}")
    blender_s=$(median "${blender_runs[@]}")
    echo "$asset $size: ours ${ours_runs[*]} s; blender ${blender_runs[*]} s" >&2
    fidelity=$("$peer" fidelity "$input" "$dir/ours/before.png" "$dir/blender.png")
    echo "$asset $size: peak RSS ours $(cat "$dir/ours.log.peak-kb") KiB, blender $(cat "$dir/blender.log.peak-kb") KiB" >&2
    python3 - "$dir/ours/report.json" "$asset" "$size" "$ours_s" "$blender_s" "$fidelity" <<'EOF'
import json, sys
report = json.load(open(sys.argv[1]))
asset, size, ours_s, blender_s = sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5])
fidelity = json.loads(sys.argv[6])
t, per_mp = report["times_ms"], report["ms_per_megapixel"]
render_ms = t["raster"] + t["gbuffer"] + t["lighting_both_sides"]
print("%-16s %5d | %9.1f %9.1f %9.1f %8.2f | %8.2f | %7.0fx %7.1fx | %6.3f %8.2f %8.1f" % (
    asset, size, per_mp["gbuffer_pass"], per_mp["lighting_per_side"], render_ms, ours_s, blender_s,
    blender_s * 1000 / render_ms, blender_s / ours_s, fidelity["flip_mean"], fidelity["delta_e_2000_mean"],
    fidelity["rms_db"]))
EOF
  done
done
echo "gbuf/MP, light/MP: ms per megapixel (report.json: G-buffer pass = raster + resolve; lighting per side)"
echo "render ms: raster + resolve + lighting both sides; ours s, blender s: whole process, wall clock"
echo "x render: Blender's whole process / our render time; x proc: / our whole process"
echo "images: $out/<asset>-<size>/{ours/before.png,blender.png}"
