"""How fast the gallery page (issue 15) is written and opens with many entries: one preview of a
shared asset copied COUNT times into a folder, `gltf-pbr gallery` over it, then the page opened in
Debian's headless chromium RUNS times (tests/preview/browser.py). Prints the medians of the page
write, the first contentful paint, the load event and the images loaded on the first screen.

    python3 bench/gallery.py GLTF_PBR SHARED_DIR [COUNT=1000] [RUNS=5] [SIZE=512]
"""
import pathlib
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "tests" / "preview"))
from browser import Browser  # noqa: E402

cli, shared = sys.argv[1], pathlib.Path(sys.argv[2])
count = int(sys.argv[3]) if len(sys.argv) > 3 else 1000
runs = int(sys.argv[4]) if len(sys.argv) > 4 else 5
size = sys.argv[5] if len(sys.argv) > 5 else "512"
work = pathlib.Path(tempfile.mkdtemp(prefix="gltf-pbr-gallery-bench-"))
one = work / "one"
subprocess.run([cli, "preview", shared / "assets/Duck/specgloss/Duck.gltf", "-o", one, "--size", size, "-q",
                "--no-gallery"], check=True)
many = work / "many"
for i in range(count):
    shutil.copytree(one, many / f"asset{i:05d}")

writes, paints, loads, loaded = [], [], [], []
for _ in range(runs):
    start = time.monotonic()
    subprocess.run([cli, "gallery", many, "-q"], check=True)
    writes.append((time.monotonic() - start) * 1000)
    with Browser() as browser:
        browser.open((many / "index.html").as_uri())
        paints.append(browser.evaluate(
            "performance.getEntriesByName('first-contentful-paint')[0]?.startTime ?? null"))
        loads.append(browser.evaluate("performance.getEntriesByType('navigation')[0].loadEventEnd"))
        loaded.append(browser.evaluate("[...document.images].filter(i => i.complete && i.naturalWidth > 0).length"))
page_bytes = (many / "index.html").stat().st_size
print(f"{count} entries ({size} px previews), {runs} runs; page {page_bytes / 1e6:.2f} MB")
print(f"  gallery write (process): median {statistics.median(writes):.0f} ms, max {max(writes):.0f} ms")
print(f"  first contentful paint:  median {statistics.median(paints):.0f} ms, max {max(paints):.0f} ms")
print(f"  load event end:          median {statistics.median(loads):.0f} ms, max {max(loads):.0f} ms")
print(f"  images loaded on the first screen: {statistics.median(loaded):.0f} of {3 * count}")
shutil.rmtree(work)
