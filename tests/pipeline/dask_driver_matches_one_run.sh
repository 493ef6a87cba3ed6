#!/usr/bin/env bash
# dist/dask_convert.py against one `gltf-pbr convert` run of a generated library: on a local
# cluster of two worker processes, and on a scheduler with two workers of which one is killed
# while its tasks run. Both end with every file converted, outputs byte-identical to the one run,
# and the merged report equal to its report (times aside).
#   dask_driver_matches_one_run.sh CLI SAMPLES_DIR SHARED_DIR PYTHON SOURCE_DIR
set -euo pipefail
cli=$1 samples=$2 shared=$3 python=$4 source=$5
work=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "$*" >&2; exit 1; }
"$python" -c "import dask.distributed" 2>/dev/null || fail "Dask is missing: apt-get install python3-distributed"

"$python" "$source/tests/pipeline/make_library.py" "$samples" "$shared" "$work/library" 400 >/dev/null
"$cli" convert "$work/library" -o "$work/whole" --report "$work/whole.json" -q || fail "the one run failed"
same_as_one_run() {  # same_as_one_run NAME: outputs in $work/NAME, report $work/NAME.json
  diff -r "$work/whole" "$work/$1" >/dev/null || fail "$1: the outputs differ from the one run's"
  "$python" "$source/tests/pipeline/reports.py" "$work/whole.json" "$work/$1.json" "$work/whole" "$work/$1" 400 ||
    fail "$1: the merged report differs from the one run's"
}

# A local cluster the driver starts: two worker processes.
"$python" "$source/dist/dask_convert.py" "$work/library" -o "$work/local" --report "$work/local.json" \
  --results "$work/local.jsonl" --tool "$cli" --local-workers 2 --shards 8 2>"$work/local.log" ||
  { cat "$work/local.log" >&2; fail "local run failed"; }
same_as_one_run local
"$python" - "$work/local.jsonl" <<'PY' || fail "the joined --results do not name every file once"
import json, sys
positions = sorted(json.loads(line)["position"] for line in open(sys.argv[1]))
assert positions == list(range(400)), positions[:10]
PY

# A file that crashes the tool (the tests' fault hook) takes its shard's process down: the shard is
# run again with each file in a process of its own, that file fails alone and is named, and the
# report, in a folder that did not exist, holds every other file.
crash=$(cd "$work/library" && find . -name "*.gltf" | sort | sed -n 7p)
status=0
GLTF_PBR_TEST_FAULT="crash=$(basename "$crash")" "$python" "$source/dist/dask_convert.py" "$work/library" \
  -o "$work/crashed" --report "$work/new-folder/crashed.json" --tool "$cli" --local-workers 2 --shards 4 \
  2>"$work/crashed.log" || status=$?
[ "$status" -eq 1 ] || { cat "$work/crashed.log" >&2; fail "a crashing file: status $status"; }
grep -q "FAILED .*$(basename "$crash")" "$work/crashed.log" || fail "the crashing file is not named: $(cat "$work/crashed.log")"
"$python" - "$work/new-folder/crashed.json" "$(basename "$crash")" <<'PY' || fail "the report of a run with a crash"
import json, sys
report = json.load(open(sys.argv[1]))
failed = [f["input"] for f in report["files"] if f["status"] == "failed"]
assert len(report["files"]) == 400 and len(failed) == 1 and failed[0].endswith(sys.argv[2]), failed
PY
[ -z "$(find "$work/new-folder" -name "shards.*")" ] || fail "the driver left its work folder"

# A running scheduler with two workers; each task waits a second first, and one worker is killed
# while it runs a task: Dask runs that task again on the other. The tool counts its conversions,
# and marks which worker (its parent process) runs one.
cat >"$work/slow-tool" <<SH
#!/bin/sh
if [ "\$1" = convert ]; then
  echo "\$PPID" >>"$work/calls"
  touch "$work/running.\$PPID"
  sleep 1
fi
exec "$cli" "\$@"
SH
chmod +x "$work/slow-tool"
"$python" -m distributed.cli.dask_scheduler --scheduler-file "$work/scheduler.json" --port 0 \
  --dashboard-address :0 >"$work/scheduler.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do [ -s "$work/scheduler.json" ] && break; sleep 0.1; done
for worker in 1 2; do
  "$python" -m distributed.cli.dask_worker --scheduler-file "$work/scheduler.json" --nthreads 1 --nworkers 1 \
    --no-nanny --dashboard-address :0 >"$work/worker$worker.log" 2>&1 &
  pids+=($!)
done
victim=${pids[1]}
"$python" "$source/dist/dask_convert.py" "$work/library" -o "$work/killed" --report "$work/killed.json" \
  --tool "$work/slow-tool" --scheduler "$("$python" -c 'import json,sys; print(json.load(open(sys.argv[1]))["address"])' "$work/scheduler.json")" \
  --shards 8 --task-jobs 1 --work "$work/killed-shards" 2>"$work/killed.log" &
driver=$!
for _ in $(seq 300); do [ -e "$work/running.$victim" ] && break; sleep 0.1; done
[ -e "$work/running.$victim" ] || fail "the worker to kill never ran a task"
kill -9 "$victim"
wait "$victim" 2>/dev/null || true
wait "$driver" || { cat "$work/killed.log" >&2; fail "the run with a killed worker failed"; }
grep -q "Remove worker" "$work/scheduler.log" || fail "the scheduler never saw the worker go"
# 8 shards, and the killed worker's task once more.
[ "$(wc -l <"$work/calls")" -ge 9 ] || fail "no task was run again after the worker died: $(wc -l <"$work/calls") runs"
same_as_one_run killed
echo "Dask: a local cluster and a cluster that lost a worker both converted the library as one run does"
