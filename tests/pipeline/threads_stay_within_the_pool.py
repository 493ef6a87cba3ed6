"""convert, validate and preview over a folder with -j above the core count never hold more threads
than the one pool (core/parallel.hpp: hardware threads - 1 workers plus the caller) and the signal
watcher (core/files.cpp install_signal_cleanup): files, bakes, decodes and render passes nest on the
same workers instead of each starting its own. The thread count is sampled from /proc while each
command runs.

    python3 threads_stay_within_the_pool.py CLI SHARED_DIR"""
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

cli, shared = sys.argv[1:3]
work = pathlib.Path(tempfile.mkdtemp())
cores = os.cpu_count() or 1
allowed = cores + 1  # the pool (cores - 1 workers + the main thread) and the signal watcher

# Textured assets with PNG and JPEG maps (the lean codecs; OpenImageIO, which keeps a pool of its
# own, is not loaded for them), several copies so that files overlap.
library = work / "library"
for copy in range(3):
    for name in ("Avocado", "BoxTextured", "CesiumMilkTruck"):
        shutil.copytree(pathlib.Path(shared) / "assets" / name / "specgloss", library / f"{name}{copy}")


def most_threads(arguments):
    """Runs the command to its end; returns the most threads seen at once and how often it looked."""
    # A sanitizer build's leak check stops the world from a thread of its own at exit: not ours.
    environment = dict(os.environ, ASAN_OPTIONS=os.environ.get("ASAN_OPTIONS", "") + ":detect_leaks=0")
    process = subprocess.Popen([cli, *arguments], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=environment)
    most, samples = 0, 0
    while process.poll() is None:
        try:
            most = max(most, len(os.listdir(f"/proc/{process.pid}/task")))
            samples += 1
        except FileNotFoundError:  # it ended between poll and listdir
            break
        time.sleep(0.002)
    _, err = process.communicate()
    if process.returncode not in (0, 1):  # 1: validate found issues
        sys.exit(f"{' '.join(arguments)} failed ({process.returncode}): {err.decode()}")
    return most, samples


failed = False
jobs = str(4 * cores)
for arguments in (["convert", str(library), "-o", str(work / "converted"), "-q", "-j", jobs],
                  ["validate", str(library), "-f", "json", "-o", str(work / "reports"), "-q", "-j", jobs],
                  ["preview", str(library), "-o", str(work / "previews"), "--size", "128", "-q", "-j", jobs]):
    most, samples = most_threads(arguments)
    print(f"{arguments[0]} -j {jobs} on {cores} cores: at most {most} threads ({samples} samples; allowed {allowed})")
    if samples < 5:
        print(f"  too few samples to judge: {samples}")
        failed = True
    if most > allowed:
        print("  more threads than the pool holds")
        failed = True
shutil.rmtree(work)
sys.exit(1 if failed else 0)
