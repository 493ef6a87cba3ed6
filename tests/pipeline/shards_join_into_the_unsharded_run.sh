#!/usr/bin/env bash
# A generated library of 1,000 files converted in one run, and again as 4 shards (--shard I/4)
# into one output folder: the outputs are byte-identical, the shards are disjoint and cover the
# input, merge-reports joins the shard reports into the unsharded report (times aside), and each
# shard's --results lines name every file it converted. merge-reports refuses a missing or repeated
# shard; --inputs-from converts exactly the files listed.
#   shards_join_into_the_unsharded_run.sh CLI SAMPLES_DIR SHARED_DIR PYTHON
set -euo pipefail
cli=$1 samples=$2 shared=$3 python=$4
here=$(dirname "$0")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "$*" >&2; exit 1; }
trap 'echo "$0: line $LINENO exited with status $?" >&2' ERR

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

# One shard run with --cache among three without: the merged cache counts say whose they are.
"$cli" convert "$work/library" -o "$work/sharded" --shard 0/4 --cache "$work/cache" --report "$work/shard0-cache.json" \
  -q -j 2 || fail "shard 0/4 with a cache failed"
"$cli" merge-reports "$work/shard0-cache.json" "$work/shard1.json" "$work/shard2.json" "$work/shard3.json" \
  -o "$work/merged-cache.json" || fail "merging a shard with a cache failed"
"$python" -c 'import json,sys; c = json.load(open(sys.argv[1]))["cache"]; assert c["shards"] == {"counted": 1, "of": 4}, c' \
  "$work/merged-cache.json" || fail "a merged cache block of one shard in four does not say so"

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

# Crafted reports: refused (exit 2) with the file and the JSON pointer, never a crash.
printf '{"tool":"gltf-pbr","files":[],"shard":{}}' >"$work/empty-shard.json"
printf '{"tool":"gltf-pbr","files":[{"position":0}],"shard":{"index":0,"count":1,"files":1}}' >"$work/no-status.json"
printf '{"tool":"gltf-pbr","files":[{"position":0,"status":5}],"shard":{"index":0,"count":1,"files":1}}' \
  >"$work/bad-status.json"
printf '{"tool":1}' >"$work/bad-tool.json"
"$python" -c 'print("[" * 100000 + "]" * 100000)' >"$work/deep.json"
for crafted in "empty-shard.json:/shard" "no-status.json:/files/0/status" "bad-status.json:/files/0/status" \
  "bad-tool.json:not a report" "deep.json:nested deeper"; do
  file=${crafted%%:*} expected=${crafted#*:}
  status=0
  "$cli" merge-reports "$work/$file" 2>"$work/crafted.txt" || status=$?
  [ "$status" -eq 2 ] && grep -qF "$work/$file: $expected" "$work/crafted.txt" ||
    fail "$file: status $status, $(cat "$work/crafted.txt")"
done

# --shard is checked, and --shard 0/1 is the whole run in a form merge-reports takes.
for bad in 4/4 1/0 x/4 "1/4x"; do
  status=0
  "$cli" convert "$work/library" -o "$work/bad" --shard "$bad" -q 2>/dev/null || status=$?
  [ "$status" -eq 2 ] || fail "--shard $bad: status $status"
done
"$cli" convert "$work/library" -o "$work/one-shard" --shard 0/1 --report "$work/one-shard.json" -q ||
  fail "--shard 0/1 failed"
"$cli" merge-reports "$work/one-shard.json" -o "$work/one-shard-merged.json" || fail "merging one shard failed"
"$python" "$here/reports.py" "$work/whole.json" "$work/one-shard-merged.json" "$work/whole" "$work/one-shard" 1000 ||
  fail "one shard merged differs from the unsharded report"

# --inputs-from: exactly the listed files, from a file or from standard input.
# (Not `sort | head`: under pipefail, head closing the pipe early fails the run with SIGPIPE.)
find "$work/library/group003" -name "*.gltf" | sort >"$work/group003.txt"
sed -n 1,5p "$work/group003.txt" >"$work/list.txt"
"$cli" convert --inputs-from - -o "$work/listed" -q <"$work/list.txt" || fail "--inputs-from - failed"
[ "$(find "$work/listed" -name "*.gltf" | wc -l)" -eq 5 ] || fail "--inputs-from did not convert the 5 files listed"
# A list written on Windows: a byte-order mark, CRLF line ends and blank lines.
{ printf '\xef\xbb\xbf'; sed 's/$/\r/' "$work/list.txt"; printf '\r\n\n'; } >"$work/list-crlf.txt"
"$cli" convert --inputs-from "$work/list-crlf.txt" -o "$work/listed-crlf" -q || fail "--inputs-from a CRLF list failed"
[ "$(find "$work/listed-crlf" -name "*.gltf" | wc -l)" -eq 5 ] || fail "a CRLF list did not convert its 5 files"
# A list of changed files relative to where the run starts (`git diff --name-only`) updates what the
# run over their folder wrote, at the same paths; a listed file that is gone fails alone (exit 1).
(cd "$work" && sed "s|^$work/||" list.txt >relative.txt && echo library/group003/deleted.gltf >>relative.txt)
status=0
(cd "$work" && "$cli" convert --inputs-from relative.txt -o listed-relative -q 2>relative-err.txt) || status=$?
[ "$status" -eq 1 ] && grep -q "deleted.gltf: cannot read the file" "$work/relative-err.txt" ||
  fail "a relative list with a deleted file: status $status, $(cat "$work/relative-err.txt")"
while read -r listed; do
  cmp -s "$work/listed-relative/$listed" "$work/whole/$listed" || fail "$listed: not where the folder run wrote it"
done < <(sed "s|^$work/||" "$work/list.txt")
# A file given beside the folder that holds it is one input, written where the folder run writes it.
"$cli" convert "$work/library" "$(sed -n 1p "$work/list.txt")" -o "$work/twice" --report "$work/twice.json" -q ||
  fail "a folder and a file in it failed"
"$python" -c 'import json,sys; assert json.load(open(sys.argv[1]))["totals"]["files"] == 1000' "$work/twice.json" ||
  fail "a file given beside its folder was converted twice"
# --shard splits by the path under the input root, whatever the root's name.
cp -r "$work/library" "$work/renamed"
"$cli" convert "$work/library" -o "$work/shard1-only" --shard 1/4 -q || fail "shard 1/4 alone failed"
"$cli" convert "$work/renamed" -o "$work/shard1-renamed" --shard 1/4 -q || fail "shard 1/4 of the renamed library failed"
[ "$(cd "$work/shard1-only/library" && find . -type f | sort)" = "$(cd "$work/shard1-renamed/renamed" && find . -type f | sort)" ] ||
  fail "the renamed library's shard 1/4 holds other files than the library's"
printf 'a.gltf\0b\n' >"$work/list-nul.txt"
status=0
"$cli" convert --inputs-from "$work/list-nul.txt" -o "$work/nul" -q 2>"$work/nul.txt" || status=$?
[ "$status" -eq 2 ] && grep -q "line 1 holds a NUL byte" "$work/nul.txt" || fail "a NUL in a list: status $status"

# validate shards the same way: the per-file reports of 3 shards in one folder are the unsharded
# run's, and merge-reports joins the shards' summaries into its summary.json byte for byte.
validate() { "$cli" validate "$@" -f json -q --no-self-intersections 2>/dev/null || [ $? -eq 1 ]; }
validate "$work/library/group000" "$work/library/group001" -o "$work/validated" ||
  fail "the unsharded validate failed"
for shard in 0 1 2; do
  validate "$work/library/group000" "$work/library/group001" -o "$work/validated-shards" --shard "$shard/3" \
    --results "$work/validated$shard.jsonl" || fail "validate shard $shard/3 failed"
done
diff -r -x 'summary*' "$work/validated" "$work/validated-shards" >/dev/null ||
  fail "the validate shards' reports differ from the unsharded run's"
"$cli" merge-reports "$work"/validated-shards/summary-shard*.json -o "$work/validated-merged.json" ||
  fail "merge-reports of validate summaries failed"
cmp -s "$work/validated/summary.json" "$work/validated-merged.json" ||
  fail "the merged validate summary differs from the unsharded summary.json"
[ "$(cat "$work"/validated?.jsonl | wc -l)" -eq 200 ] || fail "the validate shards' --results do not hold 200 lines"
status=0
"$cli" merge-reports "$work/shard1.json" "$work/validated-shards/summary-shard0.json" 2>"$work/mixed.txt" ||
  status=$?
[ "$status" -eq 2 ] && grep -q "a different kind of report" "$work/mixed.txt" || fail "mixed kinds: status $status"
echo "1,000 files: 4 shards byte-identical to one run, reports merged; --inputs-from converted its list;"
echo "validate shards: reports identical, summaries merged byte for byte"
