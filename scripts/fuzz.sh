#!/usr/bin/env bash
# Fuzzes one libFuzzer target for a bounded time. Usage: scripts/fuzz.sh FUZZ_BINARY SECONDS
#   fuzz-validate: load + validate, seeded from ../shared/validator-suite (read in place, never
#                  copied) and two meshopt-packed assets;
#   fuzz-convert:  convert with its preview, seeded with the small spec-gloss assets of
#                  ../shared/assets packed as GLB and constructed odd textures (scripts/fuzz_seeds.py).
# Crashing inputs land in fuzz-artifacts/; each one found becomes a regression test by copying it
# into tests/fuzz_regressions/ (ValidateHostileInput.FuzzRegressionsGiveReports validates them all
# under the sanitizers, and HostileCorpus runs every command on them).
set -euo pipefail
binary=$1
seconds=${2:-60}
root="$(cd "$(dirname "$0")/.." && pwd)"
shared="$root/../shared"
corpus=$(mktemp -d)
trap 'rm -rf "$corpus"' EXIT
mkdir -p "$root/fuzz-artifacts"
seeds=()
case "$(basename "$binary")" in
  fuzz-validate)
    while IFS= read -r dir; do seeds+=("$dir"); done < <(find "$shared/validator-suite/test" -type d)
    # EXT_meshopt_compression seeds, which the suite has none of: two shared assets packed by
    # gltfpack (npm), every mode and filter between them, into the scratch corpus.
    source "$root/tests/peer/gltfpack.sh"
    for asset in Box RiggedSimple; do
      "$GLTF_PBR_GLTFPACK" -cc -i "$shared/assets/$asset/specgloss/$asset.gltf" -o "$corpus/$asset-meshopt.glb" >/dev/null
    done
    ;;
  fuzz-convert)
    # Debian's interpreter, whose Pillow (python3-pil) the test set-up installs; another python3
    # on the PATH may have none.
    /usr/bin/python3 "$root/scripts/fuzz_seeds.py" "$corpus" "$shared/assets" 65536
    ;;
  *) echo "fuzz.sh: no seeds known for $binary" >&2; exit 2 ;;
esac
# New inputs go to the scratch corpus (the first folder); the seed folders are only read. Leaks are
# left to the sanitizer test build (OpenImageIO leaks on truncated PNGs, see tests/lsan.supp).
ASAN_OPTIONS=detect_leaks=0 "$binary" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -artifact_prefix="$root/fuzz-artifacts/" -print_final_stats=1 "$corpus" "${seeds[@]}" "$root/tests/fuzz_regressions"
