#!/usr/bin/env bash
# Differential test of the structure validator against the npm gltf-validator (the reference, run
# as a black box) on inputs made by generate.py from a fixed seed: a synthetic document using every
# core object type, the small shared assets and the Khronos suite's cases, each mutated. Prints the
# agreement on the ordered (code, pointer or offset, severity) list, by source, and the classes of
# difference, most frequent first. Nothing is written outside WORK.
# NEW_SHARE (default 0) of the inputs come from generate.py's SHAPES, documents built around one
# feature each (sparse accessors, cameras, images, skins, lights, ...); SHAPES_SET (default 1)
# picks generate.py's set of shapes (2: morph targets, samplers, primitives, material combinations,
# URIs, bounds, buffer views, animation samplers; 3: attributes, indices, skins, animation channels,
# instancing, variants, node properties, the asset object and extension lists; 4: all three).
#   bench/structure/differential.sh STRUCTURE_BENCH_BINARY NODE_MODULES [WORK] [COUNT=10000] [SEED=14] [NEW_SHARE=0] [SHAPES_SET=1]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bench_binary="$(realpath "$1")" node_modules="$2" work="${3:-/tmp/structure-diff}"
count="${4:-10000}" seed="${5:-14}" new_share="${6:-0}" shapes_set="${7:-1}"
shared="$(cd "$here/../../../shared" && pwd)"
rm -rf "$work" && mkdir -p "$work"
python3 "$here/generate.py" "$work" "$shared" --count "$count" --seed "$seed" --new-share "$new_share" --shapes-set "$shapes_set" >/dev/null
cd "$work"
M="$node_modules" node "$here/reference_reports.mjs" --list list.txt > ref.jsonl
"$bench_binary" --runs 1 --json --list list.txt | grep '^{' > ours.jsonl
python3 "$here/compare_reports.py"
