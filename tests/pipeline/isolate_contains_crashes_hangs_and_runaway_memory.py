"""convert --isolate: a batch holding a file whose conversion crashes, one that hangs and one that
allocates without end (GLTF_PBR_TEST_FAULT, the tests' fault hook) finishes with exactly those three
failed, each named with its reason, and every other file converted byte-identical to a run without
--isolate. Then resume: a run with --cache stopped part way, run again, redoes only the files the
first did not finish, and ends with the same outputs; the stopped run leaves no temporary folder.

    python3 isolate_contains_crashes_hangs_and_runaway_memory.py CLI SAMPLES_DIR SHARED_DIR"""
import hashlib
import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import tempfile
import time

cli, samples, shared = sys.argv[1:4]
here = pathlib.Path(__file__).parent
work = pathlib.Path(tempfile.mkdtemp())


def contents(folder):
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


try:
    library = work / "library"
    subprocess.run([sys.executable, str(here / "make_library.py"), samples, shared, str(library), "60", "10"],
                   check=True, capture_output=True)
    files = sorted(library.rglob("*.gltf"))
    crash, hang, oom = files[3], files[17], files[30]
    subprocess.run([cli, "convert", str(library), "-o", str(work / "reference"), "-q", "-j", "2"], check=True)

    # Limits with room for the sanitizer build under a loaded CI machine: a child there peaks at
    # about 120 MiB, and paging in 400 MiB took up to 8 s (a runaway child must reach the memory
    # limit well before the time limit).
    environment = dict(os.environ, GLTF_PBR_TEST_FAULT=f"crash={crash.name},hang={hang.name},oom={oom.name}")
    start = time.monotonic()
    run = subprocess.run([cli, "convert", str(library), "-o", str(work / "isolated"), "-q", "-j", "2", "--isolate",
                          "--file-timeout", "30", "--file-memory", "400", "--report", str(work / "isolated.json")],
                         env=environment, capture_output=True, text=True)
    print(f"isolated run: {time.monotonic() - start:.1f} s, exit {run.returncode}")
    assert run.returncode == 1, (run.returncode, run.stderr)  # 1: some files failed, the run itself went on
    report = json.loads((work / "isolated.json").read_text())
    failed = {entry["input"]: entry["error"]["reason"] for entry in report["files"] if entry["status"] == "failed"}
    assert set(failed) == {str(crash), str(hang), str(oom)}, failed
    assert "crashed: signal 6" in failed[str(crash)], failed[str(crash)]
    assert "took longer than 30 s (--file-timeout)" in failed[str(hang)], failed[str(hang)]
    assert "above 400 MiB (--file-memory)" in failed[str(oom)], failed[str(oom)]
    for name in (crash, hang, oom):
        assert f"FAILED {name}" in run.stderr, run.stderr
    assert report["totals"]["files"] == 60 and report["totals"]["failed"] == 3, report["totals"]
    expected = {name: digest for name, digest in contents(work / "reference").items()
                if not any(name.startswith(str(f.relative_to(library.parent).with_suffix(""))) for f in (crash, hang, oom))}
    assert contents(work / "isolated") == expected, "isolated children wrote other bytes than one process"

    # Resume: stop a run (-j 1, so it is part way) once some files are done, then run it again.
    cache, results = work / "cache", work / "first.jsonl"
    scratch = work / "tmp"  # the run's TMPDIR, where its children's reports go
    scratch.mkdir()
    first = subprocess.Popen([cli, "convert", str(library), "-o", str(work / "resumed"), "-q", "-j", "1", "--isolate",
                              "--cache", str(cache), "--results", str(results)],
                             env=dict(os.environ, TMPDIR=str(scratch)))
    while first.poll() is None and (not results.exists() or len(results.read_text().splitlines()) < 10):
        time.sleep(0.01)
    first.send_signal(signal.SIGINT)
    assert first.wait() != 0, "the first run finished before it could be stopped"
    assert not any(scratch.iterdir()), f"the stopped run left {sorted(scratch.iterdir())}"
    time.sleep(0.5)  # a child converting when the run stopped removes its temporaries and ends
    finished = len(list((cache / "v1" / "entries").glob("*/*")))
    assert 10 <= finished < 60, finished
    run = subprocess.run([cli, "convert", str(library), "-o", str(work / "resumed"), "-q", "-j", "2", "--isolate",
                          "--cache", str(cache), "--report", str(work / "resumed.json")], check=True)
    resumed = json.loads((work / "resumed.json").read_text())
    assert resumed["cache"]["hits"] + resumed["cache"]["misses"] == 60, resumed["cache"]
    assert resumed["cache"]["misses"] <= 60 - finished + 2 and resumed["cache"]["hits"] >= finished - 2, (
        resumed["cache"], finished)  # identical copies in the library share an entry
    assert resumed["cache"]["assetsLoaded"] == resumed["cache"]["misses"], resumed["cache"]
    assert contents(work / "resumed") == contents(work / "reference"), "the resumed run's outputs differ"
    print(f"resume: {finished} entries kept by the stopped run, {resumed['cache']['misses']} redone")
finally:
    shutil.rmtree(work, ignore_errors=True)
