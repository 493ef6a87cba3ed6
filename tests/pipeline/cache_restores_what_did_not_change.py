"""convert --cache: a rerun restores every file's outputs and report entry without loading one asset,
byte-identical to a run without the cache (its speed-up over the run that filled it is printed;
the figure to hold is measured by bench/pipeline.sh, not asserted in a test);
a changed texture redoes exactly the asset that names it; two processes sharing one cache folder
at once both finish with the right outputs; a damaged entry is computed again, never trusted;
validate --cache gives back the reports, byte for byte, that validating gives; and preview --cache
gives back the folder it drew.

    python3 cache_restores_what_did_not_change.py CLI SAMPLES_DIR SHARED_DIR"""
import hashlib
import json
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

cli, samples, shared = sys.argv[1:4]
here = pathlib.Path(__file__).parent
work = pathlib.Path(tempfile.mkdtemp())


def make_library(folder, count, textured_every, names=None):
    arguments = [samples, shared, str(folder), str(count), str(textured_every)] + ([names] if names else [])
    subprocess.run([sys.executable, str(here / "make_library.py"), *arguments], check=True, capture_output=True)


def convert(library, output, *options):
    """Runs convert; returns its report and its wall time in seconds."""
    report = work / "report.json"
    start = time.monotonic()
    subprocess.run([cli, "convert", str(library), "-o", str(output), "-q", "-j", "2", "--report", str(report),
                    *map(str, options)], check=True)
    return json.loads(report.read_text()), time.monotonic() - start


def contents(folder):
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def without_run_fields(report):
    """The file entries as a reader compares runs: measured times and cache marks aside."""
    files = []
    for entry in report["files"]:
        entry = {k: v for k, v in entry.items()
                 if k not in ("timeMs", "computedTimeMs", "cached", "imagesDecoded", "computedImagesDecoded")}
        for material in entry.get("materials", []):
            material.pop("timeMs", None)
            material.pop("computedTimeMs", None)
        files.append(entry)
    return files


try:
    # Assets with real textures, each copy's factors moved a little: what a rerun of a real library skips.
    library = work / "library"
    make_library(library, 20, 1, "Avocado,CesiumMilkTruck")
    # One asset with a texture of its own (the others share theirs with their copies), to change below.
    solo = library / "solo"
    solo.mkdir()
    for resource in (pathlib.Path(shared) / "assets" / "Duck" / "specgloss").iterdir():
        shutil.copyfile(resource, solo / resource.name)
    count = 21

    reference, _ = convert(library, work / "reference")
    cache = work / "cache"
    first, first_seconds = convert(library, work / "out", "--cache", cache)
    assert first["cache"]["misses"] == count and first["cache"]["stored"] == count, first["cache"]
    assert contents(work / "out") == contents(work / "reference"), "a run that fills the cache writes other bytes"

    # A digest is trusted only for a file unchanged for over a second before it was recorded.
    time.sleep(1.5)
    reruns = [convert(library, work / "out", "--cache", cache) for _ in range(3)]
    rerun, _ = reruns[-1]
    rerun_seconds = min(seconds for _, seconds in reruns)
    assert rerun["cache"]["hits"] == count and rerun["cache"]["assetsLoaded"] == 0, rerun["cache"]
    assert all(entry["cached"] for entry in rerun["files"])
    # What this run did is not what the computing run did: no decodes, no material times.
    for restored, computed in zip(rerun["files"], first["files"]):
        assert restored["imagesDecoded"] == 0, restored
        assert restored["computedImagesDecoded"] == computed["imagesDecoded"], restored
        assert all(m["timeMs"] is None and m["computedTimeMs"] == c["timeMs"]
                   for m, c in zip(restored["materials"], computed["materials"])), restored["input"]
    assert without_run_fields(rerun) == without_run_fields(first), "a restored entry differs from the computed one"
    assert rerun["totals"]["materials"] == first["totals"]["materials"] > 0
    assert contents(work / "out") == contents(work / "reference"), "a rerun changed the outputs"
    speedup = first_seconds / rerun_seconds
    print(f"first run {first_seconds:.2f} s, cached rerun {rerun_seconds:.3f} s: {speedup:.0f}x")

    # Into an empty folder, every output comes from the cache.
    fresh, _ = convert(library, work / "elsewhere", "--cache", cache)
    assert fresh["cache"]["hits"] == count and fresh["cache"]["assetsLoaded"] == 0, fresh["cache"]
    assert contents(work / "elsewhere") == contents(work / "reference")

    # A changed texture (written as a new file, as an exporter does) redoes the one asset naming it.
    before = contents(work / "out")
    replacement = solo / "DuckCM.png.new"
    shutil.copyfile(pathlib.Path(shared) / "assets" / "BoxTextured" / "specgloss" / "CesiumLogoFlat.png", replacement)
    replacement.replace(solo / "DuckCM.png")
    changed, _ = convert(library, work / "out", "--cache", cache)
    assert changed["cache"]["hits"] == count - 1 and changed["cache"]["misses"] == 1, changed["cache"]
    assert changed["cache"]["assetsLoaded"] == 1, changed["cache"]
    redone = [entry["input"] for entry in changed["files"] if not entry.get("cached")]
    assert redone == [str(solo / "Duck.gltf")], redone
    after = contents(work / "out")
    differing = sorted(name for name in after if after[name] != before.get(name))
    assert differing and all(name.startswith("library/solo/") for name in differing), differing

    # Two processes filling one cache folder at once, on a library of mostly factor-only files.
    mixed = work / "mixed"
    make_library(mixed, 300, 25)
    mixed_reference, _ = convert(mixed, work / "mixed-reference")
    shared_cache = work / "shared-cache"
    runs = [subprocess.Popen([cli, "convert", str(mixed), "-o", str(work / f"mixed{n}"), "-q", "-j", "1",
                              "--cache", str(shared_cache), "--report", str(work / f"mixed{n}.json")])
            for n in range(2)]
    assert [run.wait() for run in runs] == [0, 0], "a run sharing the cache folder failed"
    for n in range(2):
        assert contents(work / f"mixed{n}") == contents(work / "mixed-reference"), f"run {n} wrote other bytes"
    entries = list((shared_cache / "v1" / "entries").glob("*/*"))
    assert len(entries) == 300 and all((entry / "entry.json").is_file() for entry in entries), len(entries)
    assert not list((shared_cache / "v1" / "tmp").iterdir()), "an entry was left half written"

    # A damaged entry is a miss: computed again and the output written right, never restored.
    victim = next(entry for entry in entries if json.loads((entry / "entry.json").read_text())["files"])
    (victim / "0").write_bytes(b"not what was stored")
    (victim / "entry.json").write_text(json.dumps({"entry": {}, "files": [{"root": 0, "path": "../../escape",
                                                                          "digest": "0"}]}))
    # and one whose entry is not what convert stores (its files intact): refused before any is written.
    other = next(entry for entry in entries if entry != victim)
    stored = json.loads((other / "entry.json").read_text())
    stored["entry"] = {"status": 5}
    (other / "entry.json").write_text(json.dumps(stored))
    damaged, _ = convert(mixed, work / "mixed-damaged", "--cache", shared_cache)
    assert damaged["cache"]["misses"] == 2 and damaged["cache"]["hits"] == 298, damaged["cache"]
    again, _ = convert(mixed, work / "mixed-healed", "--cache", shared_cache)
    assert again["cache"]["hits"] == 300, ("damaged entries were not replaced", again["cache"])
    assert contents(work / "mixed-damaged") == contents(work / "mixed-reference")
    assert not (work / "escape").exists()

    # validate --cache: the same reports from the cache as from validating, and no asset loaded.
    def validate(output, *options):
        run = subprocess.run([cli, "validate", str(library), "-f", "json", "-o", str(output), "-q", "--no-self-intersections",
                              *map(str, options)], capture_output=True)
        assert run.returncode in (0, 1), f"validate failed to run: exit {run.returncode}"  # 1: files with errors
        summary = json.loads((output / "summary.json").read_text())
        return {k: v for k, v in contents(output).items() if k != "summary.json"}, summary
    validated, _ = validate(work / "validated")
    validate(work / "validated-filling", "--cache", work / "validate-cache")
    time.sleep(1.5)
    restored, summary = validate(work / "validated-cached", "--cache", work / "validate-cache",
                                 "--results", work / "validated-cached.jsonl")
    assert summary["cache"]["hits"] == count and summary["cache"]["assetsLoaded"] == 0, summary["cache"]
    lines = [json.loads(line) for line in (work / "validated-cached.jsonl").read_text().splitlines()]
    assert len(lines) == count and all(line["cached"] and line["timeMs"]["total"] > 0 for line in lines), \
        "validate --results lines do not say each report was restored and what it cost"
    assert restored == validated, "validate --cache gave other reports"

    # preview --cache: the second preview of a file is the first one's folder, restored.
    def preview(output):
        return subprocess.run([cli, "preview", str(solo / "Duck.gltf"), "-o", str(output), "--size", "64",
                               "--cache", str(work / "preview-cache")], check=True, capture_output=True, text=True)
    preview(work / "preview-first")
    again = preview(work / "preview-again")
    assert "restored from the cache" in again.stderr, again.stderr
    assert contents(work / "preview-again") == contents(work / "preview-first")  # times and all: not redrawn
    # index.html is the gallery page, written again over the restored folder (not kept in the cache).
    assert set(contents(work / "preview-first")) == {"before.png", "after.png", "difference.png", "sheet.png",
                                                     "report.json", "index.html"}

    # A file that fails is not kept, and is counted so: every miss is stored or not stored.
    failing = work / "failing"
    shutil.copytree(pathlib.Path(shared) / "assets" / "Duck" / "specgloss", failing / "good")
    (failing / "broken.gltf").write_text("{")
    status = subprocess.run([cli, "convert", str(failing), "-o", str(work / "failing-out"), "-q", "--report",
                             str(work / "failing.json"), "--cache", str(work / "failing-cache")], capture_output=True)
    assert status.returncode == 1, status.stderr
    counts = json.loads((work / "failing.json").read_text())["cache"]
    assert counts["misses"] == 2 and counts["stored"] == 1 and counts["notStored"] == 1, counts
    print("cache: reruns restore, changes redo, shared folders hold, validation reports and previews return")
finally:
    shutil.rmtree(work, ignore_errors=True)
