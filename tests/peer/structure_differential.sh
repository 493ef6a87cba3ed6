#!/usr/bin/env bash
# A bounded sample of the structure differential (bench/structure/differential.sh runs 10,000):
# inputs made by bench/structure/generate.py from a seed other than the one the rules were
# studied on, validated by our structure step and by the npm gltf-validator as a black box. The
# ordered (code, pointer or offset, severity) lists must agree on at least MIN_AGREEMENT percent.
# NEW_SHARE of the inputs are generate.py's SHAPES (documents built around one feature each), from
# its set SHAPES_SET (1, 2 or 3: both).
#   structure_differential.sh STRUCTURE_BENCH_BINARY [COUNT=600] [SEED=15] [MIN_AGREEMENT=95] [NEW_SHARE=0] [SHAPES_SET=1]
set -euo pipefail
bench_binary=$1 count=${2:-600} seed=${3:-15} minimum=${4:-95} new_share=${5:-0} shapes_set=${6:-1}
here=$(cd "$(dirname "$0")" && pwd)

source "$here/npm_validator.sh"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$here/../../bench/structure/differential.sh" "$bench_binary" "$GLTF_PBR_NODE_MODULES" "$work/run" "$count" "$seed" "$new_share" "$shapes_set" > "$work/summary.txt"
head -25 "$work/summary.txt"
agreement=$(sed -n 's/^agree [0-9]* of [0-9]* (\([0-9.]*\)%.*/\1/p' "$work/summary.txt")
[ -n "$agreement" ] || { echo "no agreement figure in the comparison's output" >&2; exit 1; }
if ! awk -v a="$agreement" -v m="$minimum" 'BEGIN { exit !(a >= m) }'; then
  echo "agreement $agreement% is below $minimum% (seed $seed, $count inputs)" >&2
  exit 1
fi
echo "agreement $agreement% (at least $minimum%) on $count generated inputs, seed $seed"
