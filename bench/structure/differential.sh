#!/usr/bin/env bash
# Differential test of the structure validator against the npm gltf-validator (the reference,
# run as a black box): mutates a copy of the Khronos suite, validates every mutant with both, and
# prints agreement and the most frequent differences. Nothing is written outside WORK.
#   bench/structure/differential.sh STRUCTURE_BENCH_BINARY NODE_MODULES [WORK=/tmp/structure-diff]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bench_binary="$1" node_modules="$2" work="${3:-/tmp/structure-diff}"
rm -rf "$work" && mkdir -p "$work"
cp -r "$here/../../../shared/validator-suite/test" "$work/"
cd "$work"
python3 "$here/mutate_suite.py" >/dev/null
M="$node_modules" node "$here/reference_reports.mjs" $(cat list.txt) > ref.jsonl
"$bench_binary" --runs 1 --json $(cat list.txt) | grep '^{' > ours.jsonl
python3 "$here/compare_reports.py"
