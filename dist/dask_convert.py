#!/usr/bin/env python3
"""Fans `gltf-pbr convert` out over a Dask cluster: one task per shard (`--shard I/N`), each a
`gltf-pbr` process of its own, so a file that crashes the tool takes down one task, never a Dask
worker. The shards' reports are joined by `gltf-pbr merge-reports` into the report one unsharded
run writes, and the shards' JSONL results into one file.

    python3 dist/dask_convert.py INPUT... -o OUT --report REPORT.json
        [--scheduler tcp://HOST:8786 | --local-workers 2] [--shards N] [--tool gltf-pbr]
        [--task-jobs J] [-- CONVERT OPTIONS...]

Every worker must see INPUT, OUT and the work folder at the same paths (a shared file system), and
run the same gltf-pbr version (`--tool`, default: `gltf-pbr` on PATH). A task only writes its
shard's outputs, each atomically and byte-for-byte what any other run writes for that file, so a
task that Dask retries after losing a worker converges on the same files. With no --scheduler, a
local cluster of --local-workers processes is started and stopped.

Exit codes: 0 every file converted, 1 some files failed (the report says which, and they are
named on stderr), 2 bad usage, 3 a shard's task failed every retry, even with each file in a
process of its own (no report is written).
"""
import argparse
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import uuid


def printable(text):
    """A path or message from the files as it may be shown on a terminal: control characters escaped."""
    return "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in str(text))


def convert_shard(tool, inputs, output, shard, shards, work, jobs, extra):
    """One shard, in a gltf-pbr process of its own; returns its report's path. Exit 1 means some
    files failed, which their report entries say. A process that ends otherwise (a file that
    crashes the tool takes its process down) is run again with --isolate, each file in a process of
    its own, so that file fails alone and is named; a failure then is the task's. Each attempt
    writes reports of its own: a process orphaned by a lost worker may still be writing the files
    of an earlier attempt."""
    failures = []
    for isolate in ([False, True] if "--isolate" not in extra else [False]):
        attempt = uuid.uuid4().hex[:12]
        report = pathlib.Path(work) / f"shard{shard:05d}.{attempt}.json"
        results = pathlib.Path(work) / f"shard{shard:05d}.{attempt}.jsonl"
        command = [tool, "convert", *inputs, "-o", output, "--shard", f"{shard}/{shards}", "--report", str(report),
                   "--results", str(results), "-q", *(["-j", str(jobs)] if jobs else []), *extra,
                   *(["--isolate"] if isolate else [])]
        run = subprocess.run(command, capture_output=True, text=True, check=False)
        if run.returncode in (0, 1) and report.exists():
            return str(report)
        failures.append(f"{' '.join(command)} ended with {run.returncode}: {run.stderr.strip()}")
        if 0 <= run.returncode <= 3:  # its own verdict (bad usage, a report it could not write): no crash
            break
    raise RuntimeError(f"shard {shard}/{shards}: " + "; then ".join(failures))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], allow_abbrev=False,
                                     epilog=__doc__.split("\n\n")[-1],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("inputs", nargs="+", help=".gltf/.glb files or folders")
    parser.add_argument("-o", "--output", required=True, help="output folder (on the shared file system)")
    parser.add_argument("--report", required=True, help="the merged report (as `convert --report` writes it)")
    parser.add_argument("--results", help="the shards' JSONL results joined into this file")
    parser.add_argument("--scheduler", help="address of a running Dask scheduler; none: start a local cluster")
    parser.add_argument("--local-workers", type=int, default=2, help="worker processes of the local cluster")
    parser.add_argument("--shards", type=int, default=0, help="tasks (default: 4 per worker)")
    parser.add_argument("--tool", default=shutil.which("gltf-pbr") or "gltf-pbr", help="the gltf-pbr executable")
    parser.add_argument("--task-jobs", type=int, default=0,
                        help="files at once in each task (-j); default: the local cluster's cores per worker, "
                             "or the tool's default on a remote cluster")
    parser.add_argument("--work", help="folder for the shards' reports (default: beside --report)")
    # Ours before "--", convert's after it: a mistyped option of ours is an error, not passed on.
    argv = sys.argv[1:]
    split = argv.index("--") if "--" in argv else len(argv)
    args, extra = parser.parse_args(argv[:split]), argv[split + 1:]

    from dask.distributed import Client, LocalCluster, as_completed

    tool = os.path.abspath(args.tool) if os.path.sep in args.tool else args.tool
    inputs = [os.path.abspath(path) for path in args.inputs]
    output = os.path.abspath(args.output)
    own_work = not args.work  # a folder made here is removed once the reports are merged
    os.makedirs(os.path.dirname(os.path.abspath(args.report)), exist_ok=True)  # as `convert --report` does
    work = pathlib.Path(args.work or tempfile.mkdtemp(prefix="shards.", dir=os.path.dirname(
        os.path.abspath(args.report))))
    work.mkdir(parents=True, exist_ok=True)
    work.chmod(0o755)  # mkdtemp's 0700 would shut out workers running as another user
    run = uuid.uuid4().hex[:12]  # task keys of this run: two drivers on one scheduler never share one

    cluster = None
    if args.scheduler:
        client = Client(args.scheduler)
        task_jobs = args.task_jobs
    else:
        cluster = LocalCluster(n_workers=args.local_workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
        task_jobs = args.task_jobs or max(1, (os.cpu_count() or 1) // args.local_workers)
    try:
        workers = max(1, len(client.scheduler_info()["workers"]))
        shards = args.shards or 4 * workers
        futures = [client.submit(convert_shard, tool, inputs, output, shard, shards, str(work), task_jobs, extra,
                                 key=f"gltf-pbr-{run}-shard-{shard}-of-{shards}", retries=2)
                   for shard in range(shards)]
        reports, failed = [], []
        terminal = sys.stderr.isatty()
        for done, future in enumerate(as_completed(futures), 1):
            try:
                reports.append(future.result())
            except Exception as error:  # a task that failed every retry: the run is incomplete
                failed.append(str(error))
            if terminal:
                print(f"\r[{done}/{shards}] shards finished", end="", file=sys.stderr, flush=True)
        if terminal:
            print(file=sys.stderr)
        if failed:
            for error in failed:
                print(f"dask_convert: {printable(error)}", file=sys.stderr)
            print(f"dask_convert: {len(failed)} of {shards} shards failed; no report is written. The finished "
                  f"shards' reports are in {work} (their outputs are written; a rerun redoes the rest)",
                  file=sys.stderr)
            return 3
    finally:
        client.close()
        if cluster:
            cluster.close()

    merged = subprocess.run([tool, "merge-reports", *sorted(reports), "-o", args.report], check=False)
    if merged.returncode != 0:
        return merged.returncode
    if args.results:
        with open(args.results, "w", encoding="utf-8") as joined:
            for report in sorted(reports):
                joined.write(pathlib.Path(report).with_suffix(".jsonl").read_text(encoding="utf-8"))
    if own_work:
        shutil.rmtree(work, ignore_errors=True)
    report = json.loads(pathlib.Path(args.report).read_text(encoding="utf-8"))
    totals = report["totals"]
    for entry in report["files"]:  # the files that failed, named as `gltf-pbr convert` names them
        if entry.get("status") == "failed":
            reason = entry.get("error", {}).get("reason", "")
            print(f"FAILED {printable(entry['input'])}: {printable(reason)}", file=sys.stderr)
    print(f"{shards} shards on {workers} workers: {totals['files']} files, {totals['failed']} failed; "
          f"report in {args.report}", file=sys.stderr)
    return 1 if totals["failed"] else 0  # as `gltf-pbr convert` exits


if __name__ == "__main__":
    sys.exit(main())
