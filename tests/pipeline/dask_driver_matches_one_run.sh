#!/usr/bin/env bash
# dist/dask_convert.py against one `gltf-pbr convert` run of a generated library: on a local
# cluster of two worker processes, and on a scheduler with two workers of which one is killed
# while its tasks run. Both end with every file converted, outputs byte-identical to the one run,
# and the merged report equal to its report (times aside).
#   dask_driver_matches_one_run.sh CLI SAMPLES_DIR SHARED_DIR PYTHON SOURCE_DIR
set -euo pipefail
cli=$1
samples=$2
shared=$3
python=$4
source=$5
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
  --tool "$cli" --local-workers 2 --shards 8 2>"$work/local.log" || { cat "$work/local.log" >&2; fail "local run failed"; }
same_as_one_run local

# A running scheduler with two workers; each task waits a second first, and one worker is killed
# as soon as the first shard is done: Dask runs its tasks again on the other.
cat >"$work/slow-tool" <<SH
#!/bin/sh
[ "\$1" = convert ] && sleep 1
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
for _ in $(seq 300); do compgen -G "$work/killed-shards/*.json" >/dev/null && break; sleep 0.1; done
kill -9 "$victim"
wait "$victim" 2>/dev/null || true
wait "$driver" || { cat "$work/killed.log" >&2; fail "the run with a killed worker failed"; }
grep -q "Remove worker" "$work/scheduler.log" || fail "the scheduler never saw the worker go"
[ "$(ls "$work/killed-shards"/*.json | wc -l)" -eq 8 ] || fail "not every shard reported"
same_as_one_run killed
echo "Dask: a local cluster and a cluster that lost a worker both converted the library as one run does"
