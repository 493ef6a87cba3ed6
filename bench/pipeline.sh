#!/usr/bin/env bash
# Throughput of a library run (issue 16): a generated library (tests/pipeline/make_library.py:
# samples and shared assets with varied factors; every TEXTURED_EVERY-th file textured) converted
#   - by one `gltf-pbr convert -j 2` process,
#   - by dist/dask_convert.py on a local cluster of two worker processes (8 shards, -j 1 each),
# alternating, RUNS times each; and validated by one `gltf-pbr validate -j 2` process. Then the
# same with --cache: the run that fills a cache (cold) once, and RUNS reruns restoring from it, for
# one process, the Dask driver and validate. Prints markdown: median files per second, the Dask
# run's overhead against one process, and the per-file convert and validate costs (median, p99,
# max) from their --results lines.
#   bench/pipeline.sh [SHARED_DIR]    (FILES=2000 TEXTURED_EVERY=50 RUNS=3 by default; NAMES=Avocado,...
#                                      takes the textured files from those shared assets only)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$here/.."
shared="$(cd "${1:-$root/../shared}" && pwd)"
files=${FILES:-2000}
runs=${RUNS:-3}
python=/usr/bin/python3
cmake -S "$root" -B "$root/build-bench" -G Ninja -DCMAKE_BUILD_TYPE=Release -DGLTF_PBR_TESTS=OFF >/dev/null
cmake --build "$root/build-bench" >/dev/null
tool="$root/build-bench/gltf-pbr"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$python" "$root/tests/pipeline/make_library.py" "$root/build-bench/samples" "$shared" "$work/library" "$files" \
  "${TEXTURED_EVERY:-50}" ${NAMES:+"$NAMES"} >/dev/null

seconds() {  # wall seconds of a command, to the millisecond
  local start end
  start=$(date +%s%N)
  "$@" >/dev/null 2>&1 || [ $? -eq 1 ] || { echo "failed: $*" >&2; exit 1; }  # 1: some files have issues
  end=$(date +%s%N)
  printf '%d.%03d' $(((end - start) / 1000000000)) $((((end - start) / 1000000) % 1000))
}
one=() dask=() validate=()
for run in $(seq "$runs"); do
  rm -rf "$work/one" "$work/dask" "$work/dask.json" "$work/shards"
  one+=("$(seconds "$tool" convert "$work/library" -o "$work/one" -q -j 2 --results "$work/one.jsonl")")
  dask+=("$(seconds "$python" "$root/dist/dask_convert.py" "$work/library" -o "$work/dask" --report "$work/dask.json" \
    --tool "$tool" --local-workers 2 --shards 8 --work "$work/shards")")
  validate+=("$(seconds "$tool" validate "$work/library" -q -j 2 --format json -o "$work/validated" \
    --results "$work/validated.jsonl")")
done
rm -rf "$work/one" "$work/dask" "$work/shards" "$work/validated"
cold_one="$(seconds "$tool" convert "$work/library" -o "$work/one" -q -j 2 --cache "$work/cache")"
cold_dask="$(seconds "$python" "$root/dist/dask_convert.py" "$work/library" -o "$work/dask" --report "$work/dask.json" \
  --tool "$tool" --local-workers 2 --shards 8 --work "$work/shards" -- --cache "$work/dask-cache")"
cold_validate="$(seconds "$tool" validate "$work/library" -q -j 2 --format json -o "$work/validated" \
  --cache "$work/validate-cache")"
sleep 1.5  # a file's digest is trusted once it is over a second older than its record
cached_one=() cached_dask=() cached_validate=()
for run in $(seq "$runs"); do
  cached_one+=("$(seconds "$tool" convert "$work/library" -o "$work/one" -q -j 2 --cache "$work/cache")")
  cached_dask+=("$(seconds "$python" "$root/dist/dask_convert.py" "$work/library" -o "$work/dask" \
    --report "$work/dask.json" --tool "$tool" --local-workers 2 --shards 8 --work "$work/shards" \
    -- --cache "$work/dask-cache")")
  cached_validate+=("$(seconds "$tool" validate "$work/library" -q -j 2 --format json -o "$work/validated" \
    --cache "$work/validate-cache")")
done
"$python" - "$files" "$work/one.jsonl" "$work/validated.jsonl" "${one[*]}" "${dask[*]}" "${validate[*]}" "$cold_one" "$cold_dask" \
  "$cold_validate" "${cached_one[*]}" "${cached_dask[*]}" "${cached_validate[*]}" <<'PY'
import json, statistics, sys
files = int(sys.argv[1])
convert_lines, validate_lines = ([json.loads(line) for line in open(path)] for path in sys.argv[2:4])
one, dask, validate, cold_one, cold_dask, cold_validate, cached_one, cached_dask, cached_validate = (
    [float(x) for x in arg.split()] for arg in sys.argv[4:13])
def row(name, times):
    m = statistics.median(times)
    print(f"| {name} | {m:.2f} s | {files / m:.0f} | {', '.join(f'{t:.2f}' for t in times)} |")
print(f"{files} files, {len(one)} runs each, alternating\n")
print("| run | median wall | files/s | runs |\n|---|---|---|---|")
row("convert, one process -j 2", one)
row("convert, Dask local cluster (2 workers, 8 shards)", dask)
row("validate, one process -j 2", validate)
row("convert --cache, cold (fills the cache)", cold_one)
row("convert --cache, rerun (all restored)", cached_one)
row("convert, Dask, --cache cold", cold_dask)
row("convert, Dask, --cache rerun", cached_dask)
row("validate --cache, cold", cold_validate)
row("validate --cache, rerun", cached_validate)
print(f"\ncached rerun against the run without a cache: convert {statistics.median(one) / statistics.median(cached_one):.0f}x, "
      f"Dask {statistics.median(dask) / statistics.median(cached_dask):.1f}x, "
      f"validate {statistics.median(validate) / statistics.median(cached_validate):.0f}x faster")
print(f"\nDask against one process: {statistics.median(dask) / statistics.median(one):.2f}x the wall time")
for name, lines in (("convert", convert_lines), ("validate", validate_lines)):
    costs = sorted(line["timeMs"]["total"] for line in lines)
    p99 = costs[min(len(costs) - 1, int(0.99 * len(costs)))]
    print(f"per-file {name} cost (one process -j 2, last run's --results timeMs.total): "
          f"median {statistics.median(costs):.1f} ms, p99 {p99:.1f} ms, max {costs[-1]:.1f} ms")
PY
