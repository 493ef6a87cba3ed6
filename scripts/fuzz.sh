#!/usr/bin/env bash
# Fuzzes load + validate for a bounded time, seeded from ../shared/validator-suite (read in place,
# never copied). Usage: scripts/fuzz.sh FUZZ_BINARY SECONDS
# Crashing inputs land in fuzz-artifacts/; each one found becomes a regression test by copying it
# into tests/fuzz_regressions/ (ValidateHostileInput.FuzzRegressionsGiveReports runs them all
# under the sanitizers).
set -euo pipefail
binary=$1
seconds=${2:-60}
root="$(cd "$(dirname "$0")/.." && pwd)"
suite="$root/../shared/validator-suite/test"
corpus=$(mktemp -d)
trap 'rm -rf "$corpus"' EXIT
mkdir -p "$root/fuzz-artifacts"
seeds=()
while IFS= read -r dir; do seeds+=("$dir"); done < <(find "$suite" -type d)
# EXT_meshopt_compression seeds, which the suite has none of: two shared assets packed by gltfpack
# (npm), every mode and filter between them, into the scratch corpus.
source "$root/tests/peer/gltfpack.sh"
for asset in Box RiggedSimple; do
  "$GLTF_PBR_GLTFPACK" -cc -i "$root/../shared/assets/$asset/specgloss/$asset.gltf" -o "$corpus/$asset-meshopt.glb" >/dev/null
done
# New inputs go to the scratch corpus (the first folder); the suite folders are only read. Leaks are
# left to the sanitizer test build (OpenImageIO leaks on truncated PNGs, see tests/lsan.supp).
ASAN_OPTIONS=detect_leaks=0 "$binary" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -artifact_prefix="$root/fuzz-artifacts/" -print_final_stats=1 "$corpus" "${seeds[@]}" "$root/tests/fuzz_regressions"
