#!/usr/bin/env bash
# A generated library of 1,000 files converted in one run, and again as 4 shards (--shard I/4)
# into one output folder: the outputs are byte-identical, the shards are disjoint and cover the
# input, merge-reports joins the shard reports into the unsharded report (times aside), and each
# shard's --results lines name every file it converted. merge-reports refuses a missing or repeated
# shard; --inputs-from converts exactly the files listed.
#   shards_join_into_the_unsharded_run.sh CLI SAMPLES_DIR SHARED_DIR PYTHON
set -euo pipefail
cli=$1
samples=$2
shared=$3
python=$4
here=$(dirname "$0")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "$*" >&2; exit 1; }

"$python" "$here/make_library.py" "$samples" "$shared" "$work/library" 1000 >/dev/null
"$cli" convert "$work/library" -o "$work/whole" --report "$work/whole.json" -q -j 2 ||
  fail "the unsharded run failed"
for shard in 0 1 2 3; do
  "$cli" convert "$work/library" -o "$work/sharded" --shard "$shard/4" --report "$work/shard$shard.json" \
    --results "$work/shard$shard.jsonl" -q -j 2 || fail "shard $shard/4 failed"
done
diff -r "$work/whole" "$work/sharded" >/dev/null || fail "the shards' outputs differ from the unsharded run's"

# Shards given in any order merge into the unsharded report.
"$cli" merge-reports "$work/shard2.json" "$work/shard0.json" "$work/shard3.json" "$work/shard1.json" \
  -o "$work/merged.json" || fail "merge-reports failed"
"$python" "$here/reports.py" "$work/whole.json" "$work/merged.json" "$work/whole" "$work/sharded" 1000 ||
  fail "the merged report differs from the unsharded one"
"$python" - "$work" <<'PY'
import json, pathlib, sys
work = pathlib.Path(sys.argv[1])
sizes, positions = [], []
for shard in range(4):
    report = json.loads((work / f"shard{shard}.json").read_text())
    assert report["shard"] == {"index": shard, "count": 4, "files": 1000}, report["shard"]
    lines = [json.loads(line) for line in (work / f"shard{shard}.jsonl").read_text().splitlines()]
    assert sorted(l["position"] for l in lines) == sorted(f["position"] for f in report["files"])
    assert all(l["status"] == "converted" for l in lines)
    sizes.append(len(lines))
    positions += [l["position"] for l in lines]
assert sorted(positions) == list(range(1000)), "the shards overlap or miss files"
assert min(sizes) > 150, f"the shards are far from even: {sizes}"
PY

status=0
"$cli" merge-reports "$work/shard0.json" "$work/shard1.json" "$work/shard3.json" 2>"$work/missing.txt" || status=$?
[ "$status" -eq 2 ] && grep -q "shard 2 of 4 is missing" "$work/missing.txt" ||
  fail "a missing shard: status $status, $(cat "$work/missing.txt")"
status=0
"$cli" merge-reports "$work/shard0.json" "$work/shard0.json" 2>"$work/twice.txt" || status=$?
[ "$status" -eq 2 ] && grep -q "shard 0 given twice" "$work/twice.txt" ||
  fail "a repeated shard: status $status, $(cat "$work/twice.txt")"

# A report whose header claims more than the shards hold is refused before anything is sized by it.
"$python" - "$work/shard1.json" "$work/huge.json" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
report["shard"]["files"] = 10**15
json.dump(report, open(sys.argv[2], "w"))
PY
status=0
"$cli" merge-reports "$work/shard0.json" "$work/huge.json" "$work/shard2.json" "$work/shard3.json" \
  2>"$work/huge.txt" || status=$?
[ "$status" -eq 2 ] && grep -q "a different split" "$work/huge.txt" || fail "a huge claim: status $status"
sed -i 's/"files": *1000/"files": 1000000000000000/' "$work/shard0.json"
for shard in 1 2 3; do sed -i 's/"files": *1000/"files": 1000000000000000/' "$work/shard$shard.json"; done
status=0
"$cli" merge-reports "$work"/shard?.json 2>"$work/huge.txt" || status=$?
[ "$status" -eq 2 ] && grep -q "a run of 1000000000000000 files, but the shards report 1000" "$work/huge.txt" ||
  fail "a huge claim in every shard: status $status, $(cat "$work/huge.txt")"

# --inputs-from: exactly the listed files, from a file or from standard input.
find "$work/library/group003" -name "*.gltf" | sort | head -5 >"$work/list.txt"
"$cli" convert --inputs-from - -o "$work/listed" -q <"$work/list.txt" || fail "--inputs-from - failed"
[ "$(find "$work/listed" -name "*.gltf" | wc -l)" -eq 5 ] || fail "--inputs-from did not convert the 5 files listed"
echo "1,000 files: 4 shards byte-identical to one run, reports merged; --inputs-from converted its list"
