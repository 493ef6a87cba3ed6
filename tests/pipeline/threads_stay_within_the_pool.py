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
cores = os.cpu_count() or 1
allowed = cores + 1  # the pool (cores - 1 workers + the main thread) and the signal watcher



def most_threads(arguments, allowed_exits):
    """Runs the command to its end; returns the most threads seen at once and how often it looked."""
    process = subprocess.Popen([cli, *arguments], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    most, samples = 0, 0
    while process.poll() is None:
        try:
            most = max(most, len(os.listdir(f"/proc/{process.pid}/task")))
            samples += 1
        except FileNotFoundError:  # it ended between poll and listdir
            break
        time.sleep(0.002)
    _, err = process.communicate()
    if process.returncode not in allowed_exits:
        sys.exit(f"{' '.join(arguments)} failed ({process.returncode}): {err.decode()}")
    return most, samples


def check(work):
    # Textured assets with PNG maps and with JPEG maps (CesiumMan, VC) through the lean codecs;
    # OpenImageIO, which keeps a pool of its own, is not loaded for them. Several copies so that
    # files overlap.
    library = work / "library"
    for copy in range(2):
        for name in ("Avocado", "BoxTextured", "CesiumMilkTruck", "CesiumMan", "VC"):
            shutil.copytree(pathlib.Path(shared) / "assets" / name / "specgloss", library / f"{name}{copy}")
    failed = False
    jobs = str(4 * cores)
    for arguments, allowed_exits in (
            (["convert", str(library), "-o", str(work / "converted"), "-q", "-j", jobs], (0,)),
            (["validate", str(library), "-f", "json", "-o", str(work / "reports"), "-q", "-j", jobs], (0, 1)),
            (["preview", str(library), "-o", str(work / "previews"), "--size", "128", "-q", "-j", jobs], (0,))):
        most, samples = most_threads(arguments, allowed_exits)  # validate exits 1 when it found issues
        print(f"{arguments[0]} -j {jobs} on {cores} cores: at most {most} threads ({samples} samples; allowed {allowed})")
        if samples < 5:
            print(f"  too few samples to judge: {samples}")
            failed = True
        if most > allowed:
            print("  more threads than the pool holds")
            failed = True
        if cores > 1 and most < 2:  # the pool has cores - 1 workers: fewer means it was never used
            print("  the pool's workers never ran: nothing was checked")
            failed = True
    return failed


with tempfile.TemporaryDirectory() as folder:
    sys.exit(1 if check(pathlib.Path(folder)) else 0)
