"""The gallery page (issue 15) in a real browser: Debian's headless chromium opens index.html from
file:// and the test reads the DOM.

    python3 gallery_in_a_browser.py GLTF_PBR SHARED_DIR [SCREENSHOT_DIR]

- convert --preview --preview-lint over the shared assets: one row per preview, its figures and its
  material issues (before and after) equal to its report.json and to what validate raises on the
  input and on the written output, the legacy material's hint gone
  exactly where no material was left legacy, every image decodes, sorting by a header click and
  filtering work, no console error;
  a screenshot is kept in SCREENSHOT_DIR (default: the scratch folder) for a person to look at.
- A material named with markup and an asset file named with quotes, '<' and '&' show as text, run
  nothing, and their images still load (paths are URL-encoded).
- `gltf-pbr gallery` over 1,000 previews lists them all and loads only the images on screen; a
  rerun after a preview is removed drops it; `preview --grid` gets the page too.
- A folder named in non-UTF-8 bytes still shows its images; long texts and long material and
  issue lists are capped, an issue's message with markup shows as text, a preview drawn without
  --lint says its issues were not checked; an unknown outcome gets no class of its own; an index.html gltf-pbr did not write is
  never replaced (a warning for preview, exit code 3 for gallery).
"""
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from browser import Browser  # noqa: E402

cli, shared = sys.argv[1], pathlib.Path(sys.argv[2])
work = pathlib.Path(tempfile.mkdtemp(prefix="gltf-pbr-gallery-"))
screenshots = pathlib.Path(sys.argv[3]) if len(sys.argv) > 3 else work
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)


def run(*args):
    done = subprocess.run([cli, *map(str, args)], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        sys.exit(f"{' '.join(map(str, args))} exited {done.returncode}: {done.stderr}")
    return done


ROWS = "[...document.querySelectorAll('#entries tr')]"


def column(browser, index):
    """The raw values (data-value) of one figure column, in row order; None where not measured."""
    return browser.evaluate(
        f"{ROWS}.map(tr => {{ const v = tr.children[{index}].dataset.value; return v === undefined ? null : Number(v); }})")


def images_decode(browser):
    """Loads every image (lazy ones too) and returns the natural widths; 0 for one that failed."""
    return browser.evaluate("Promise.all([...document.images].map(i => { i.loading = 'eager'; "
                            "return i.decode().then(() => i.naturalWidth, () => 0); }))")


def click(browser, element_id):
    browser.evaluate(f"document.getElementById('{element_id}').click()")


# 1. A library converted with --preview.
previews = work / "previews"
run("convert", shared / "assets", "-o", work / "converted", "--preview", previews, "--preview-size", "96",
    "--preview-lint", "-q")
page = previews / "index.html"
html = page.read_text()
check("http:" not in html and "https:" not in html and "<link" not in html, "the page references nothing outside itself")
reports = {str(p.parent.relative_to(previews)): json.loads(p.read_text()) for p in previews.rglob("report.json")}


def material_issues_of(path):
    """What `validate --only materials` raises on a file: the PBR_* issues, as report.json lists them."""
    done = subprocess.run([cli, "validate", "--only", "materials", "-f", "json", path], capture_output=True, text=True)
    messages = json.loads(done.stdout)["issues"]["messages"]
    return [(m["code"], m["pointer"], m["message"], m.get("count", 1)) for m in messages if m["code"].startswith("PBR_")]


# The issues a preview lists are those validate raises on the input and on the output convert wrote.
for path, report in reports.items():
    source = pathlib.Path(report["input"])
    output = work / "converted" / source.resolve().relative_to(shared.resolve())  # convert keeps "assets/"
    listed = {side: [(i["code"], i["pointer"], i["message"], i.get("count", 1)) for i in report["material_issues"][side]]
              for side in ("before", "after")}
    check(listed["before"] == material_issues_of(source), f"{path}: the issues before are validate's on the input")
    check(listed["after"] == material_issues_of(output), f"{path}: the issues after are validate's on the output")
with Browser() as browser:
    browser.open(page.as_uri())
    paths = browser.evaluate(f"{ROWS}.map(tr => tr.dataset.path)")
    check(sorted(paths) == sorted(reports), f"one row per preview: {len(paths)} rows, {len(reports)} reports")
    for figure, index, pointer in (("flip", 3, ("flip", "mean")), ("deltaE", 4, ("delta_e_2000", "mean")),
                                   ("p95", 5, ("delta_e_2000", "p95")), ("rmsDb", 6, ("rms_db",))):
        shown = column(browser, index)
        for path, value in zip(paths, shown):
            expected = reports[path]["difference"]
            for key in pointer:
                expected = expected[key]
            check(value == expected, f"{path}: {figure} shows {value}, report.json has {expected}")
    materials = browser.evaluate(f"{ROWS}.map(tr => tr.children[7].querySelectorAll('li').length)")
    for path, count in zip(paths, materials):
        check(count == len(reports[path].get("conversion", {}).get("materials", [])), f"{path}: materials listed")
    counted = browser.evaluate(f"{ROWS}.map(tr => [Number(tr.children[8].dataset.before), "
                               "Number(tr.children[8].dataset.after)])")
    for path, (before, after) in zip(paths, counted):
        issues = reports[path]["material_issues"]
        expected = [sum(i.get("count", 1) for i in issues[side]) for side in ("before", "after")]
        check([before, after] == expected, f"{path}: material issues {before}, {after}; report.json has {expected}")
        # The legacy material's hint stays after the conversion exactly when a material was left legacy.
        left_legacy = any(m["outcome"] == "legacy" for m in reports[path].get("conversion", {}).get("materials", []))
        was_legacy = any(i["code"] == "PBR_LEGACY_SPEC_GLOSS" for i in issues["before"])
        still_legacy = any(i["code"] == "PBR_LEGACY_SPEC_GLOSS" for i in issues["after"])
        check(still_legacy == (was_legacy and left_legacy), f"{path}: PBR_LEGACY_SPEC_GLOSS after the conversion")
    check(any(any(i["code"] == "PBR_LEGACY_SPEC_GLOSS" for i in r["material_issues"]["before"])
              for r in reports.values()), "the spec-gloss inputs carry PBR_LEGACY_SPEC_GLOSS before")
    widths = images_decode(browser)
    check(len(widths) == 3 * len(reports) and all(w == 96 for w in widths), f"every image decodes at 96 px: {widths}")
    means = column(browser, 4)
    check(means == sorted(means, reverse=True), f"worst ΔE2000 mean first by default: {means}")
    click(browser, "sort-deltaE")
    means = column(browser, 4)
    check(means == sorted(means), f"a click on the header sorts ascending: {means}")
    click(browser, "sort-name")
    names = browser.evaluate(f"{ROWS}.map(tr => tr.querySelector('.name').textContent.toLowerCase())")
    check(names == sorted(names), f"sorted by name: {names}")
    browser.evaluate("(() => { const f = document.getElementById('filter'); f.value = 'duck'; "
                     "f.dispatchEvent(new Event('input')); })()")
    shown = browser.evaluate(f"{ROWS}.map(tr => tr.dataset.path)")
    check(len(shown) >= 1 and all("duck" in p.lower() for p in shown), f"the name filter keeps Duck: {shown}")
    browser.evaluate("(() => { const f = document.getElementById('filter'); f.value = ''; "
                     "f.dispatchEvent(new Event('input')); const o = document.getElementById('outcome'); "
                     "o.value = 'metalness'; o.dispatchEvent(new Event('change')); })()")
    shown = browser.evaluate(f"{ROWS}.map(tr => tr.dataset.path)")
    expected = [p for p in reports
                if any(m["outcome"] == "metalness" for m in reports[p].get("conversion", {}).get("materials", []))]
    check(sorted(shown) == sorted(expected), f"the outcome filter: {shown} against {expected}")
    browser.evaluate("(() => { const o = document.getElementById('outcome'); o.value = ''; "
                     "o.dispatchEvent(new Event('change')); document.getElementById('sort-deltaE').click(); })()")
    browser.screenshot(screenshots / "gallery.png")
    check(browser.errors() == [], f"no console errors: {browser.errors()}")
    outside = [url for url in browser.requests() if not url.startswith(previews.as_uri() + "/")]
    check(browser.requests() and not outside, f"every request stays in the previews' folder: {outside}")
print(f"screenshot: {screenshots / 'gallery.png'}", file=sys.stderr)

# 2. Untrusted names show as text.
hostile_name = '</script><script>window.pwned = 1</script><b id="injected">bold</b> "q" \'a\' &amp;'
hostile_file = "Box \"q\" 'a' <b>&amp; 100%.gltf"
source = shared / "assets/Box/specgloss"
hostile = work / "hostile"
shutil.copytree(source, hostile)
document = json.loads((hostile / "Box.gltf").read_text())
document["materials"][0]["name"] = hostile_name
(hostile / hostile_file).write_text(json.dumps(document))
(hostile / "Box.gltf").unlink()
run("convert", hostile, "-o", work / "hostile-out", "--preview", work / "hostile-previews", "--preview-size", "64", "-q")
with Browser() as browser:
    browser.open((work / "hostile-previews/index.html").as_uri())
    check(browser.evaluate("window.pwned === undefined"), "a <script> in a material name does not run")
    check(browser.evaluate("document.getElementById('injected') === null"), "markup in a name makes no element")
    check(browser.evaluate("document.querySelector('ul.materials li span').textContent") == hostile_name,
          "the material name shows as the text it is")
    check(browser.evaluate("document.querySelector('.name').textContent") == hostile_file,
          "the file name shows as the text it is")
    widths = images_decode(browser)
    check(widths == [64, 64, 64], f"images under a folder named with quotes, '<', '&' and '%' load: {widths}")
    check(browser.errors() == [], f"no console errors: {browser.errors()}")

# 3. A thousand previews: all listed, only what is on screen loaded.
many = work / "many"
one = next(p.parent for p in previews.rglob("report.json") if "Box" in str(p))
for i in range(1000):
    shutil.copytree(one, many / f"asset{i:04d}")
run("gallery", many)
with Browser(height=900) as browser:
    browser.open((many / "index.html").as_uri())
    check(browser.evaluate(f"{ROWS}.length") == 1000, "1,000 rows")
    loaded = browser.evaluate("[...document.images].filter(i => i.complete && i.naturalWidth > 0).length")
    check(0 < loaded < 100, f"lazy images: {loaded} of 3000 loaded on the first screen")
    check(browser.errors() == [], f"no console errors: {browser.errors()}")
shutil.rmtree(many / "asset0007")
run("gallery", many)
with Browser() as browser:
    browser.open((many / "index.html").as_uri())
    check(browser.evaluate(f"{ROWS}.length") == 999, "a rerun drops a removed preview")
# Links are not followed (a dangling one ends nothing), and a report of the wrong shape is read by type.
(many / "aa-dangling").symlink_to(work / "nowhere")
(many / "zz-linked").symlink_to(one)
odd = many / "odd"
shutil.copytree(one, odd)
report = json.loads((odd / "report.json").read_text())
report.setdefault("conversion", {})["materials"] = [{"index": "x", "name": 7, "outcome": ["metalness"]}]
(odd / "report.json").write_text(json.dumps(report))
run("gallery", many)
with Browser() as browser:
    browser.open((many / "index.html").as_uri())
    paths = browser.evaluate(f"{ROWS}.map(tr => tr.dataset.path)")
    check(len(paths) == 1000 and "odd" in paths and "zz-linked" not in paths,
          f"links skipped, the odd report listed: {len(paths)} rows")
    check(browser.errors() == [], f"no console errors: {browser.errors()}")

# 4. The sphere grid gets the page.
run("preview", "--grid", "-o", work / "grid", "--size", "64", "-q")
with Browser() as browser:
    browser.open((work / "grid/index.html").as_uri())
    check(browser.evaluate(f"{ROWS}.map(tr => tr.querySelector('.name').textContent)") == ["grid"], "the grid's page")
    width = json.loads((work / "grid/report.json").read_text())["width"]
    check(images_decode(browser) == [width] * 3, "the grid's images load")

# 5. A folder named in bytes that are not UTF-8 (and '#', '?'), long texts, many materials, an
#    outcome the page does not know, and an index.html that gltf-pbr did not write.
odd_names = work / "odd-names"
odd_names.mkdir()
non_utf8 = pathlib.Path(os.fsdecode(os.fsencode(str(odd_names)) + b"/caf\xe9 #1?"))
shutil.copytree(one, non_utf8)
report = json.loads((non_utf8 / "report.json").read_text())
report.setdefault("conversion", {})["materials"] = [{"index": 0, "name": "odd", "outcome": "constructor"}]
report["material_issues"] = None  # drawn without --lint
(non_utf8 / "report.json").write_text(json.dumps(report))
long_texts = odd_names / "long"
shutil.copytree(one, long_texts)
report = json.loads((long_texts / "report.json").read_text())
report["input"] = "x" * 5000 + ".gltf"
report["conversion"]["materials"] = (  # 300 materials, the one left legacy last
    [{"index": i, "name": f"material {i}", "outcome": "metalness"} for i in range(299)] +
    [{"index": 299, "name": "m" * 5000, "outcome": "legacy", "note": "n" * 5000}])
hostile_message = "</script><script>window.pwned2 = 1</script><b>&amp;</b>"
report["material_issues"] = {  # 150 issues before, one of them repeated 3 times; an unknown severity
    "profile": "tolerant",
    "before": [{"code": "PBR_X", "severity": "<b>", "pointer": "/materials/0", "message": hostile_message, "count": 3}] +
              [{"code": "PBR_Y", "severity": "warning", "pointer": f"/materials/{i}", "message": "m"} for i in range(149)],
    "after": []}
(long_texts / "report.json").write_text(json.dumps(report))
run("gallery", odd_names)
check(len((odd_names / "index.html").read_bytes()) < 200_000, "long texts are capped in the page")
with Browser() as browser:
    browser.open((odd_names / "index.html").as_uri())
    check(browser.evaluate(f"{ROWS}.length") == 2, "both odd previews listed")
    widths = images_decode(browser)
    check(len(widths) == 6 and all(w > 0 for w in widths), f"images under a non-UTF-8 folder name load: {widths}")
    shown = browser.evaluate(f"{ROWS}.map(tr => tr.querySelector('.name').textContent.length)")
    check(max(shown) <= 1001, f"a 5,000-character name shows capped: {shown}")
    items = browser.evaluate(f"{ROWS}.map(tr => tr.children[7].querySelectorAll('li').length)")
    check(257 in items, f"256 materials listed and a line for the rest: {items}")
    issues = browser.evaluate(f"{ROWS}.map(tr => [tr.children[8].dataset.before, "
                              "tr.children[8].querySelectorAll('li').length])")
    check(["152", 101] in issues, f"152 issues counted, 100 listed and a line for the rest: {issues}")
    check(browser.evaluate("window.pwned2 === undefined"), "a <script> in an issue's message does not run")
    first = browser.evaluate("document.querySelector('ul.issues li').textContent")
    check(hostile_message in first and "(3 times)" in first, f"an issue's message shows as text: {first}")
    check(browser.evaluate("document.querySelector('ul.issues li span').className") == "",
          "an unknown severity gets no class of its own")
    unchecked = browser.evaluate(f"{ROWS}.map(tr => tr.children[8].textContent)")
    check("not checked" in unchecked, f"a preview drawn without --lint says its issues were not checked: {unchecked}")
    lengths = browser.evaluate("[...document.querySelectorAll('ul.materials li span')].map(s => s.textContent.length)")
    check(1001 in lengths, "the worst material (left legacy, the last of 300) is listed, its name capped")
    browser.evaluate("(() => { const o = document.getElementById('outcome'); o.value = 'legacy'; "
                     "o.dispatchEvent(new Event('change')); })()")
    check(browser.evaluate(f"{ROWS}.length") == 1, "the outcome filter sees every material's outcome")
    browser.evaluate("(() => { const o = document.getElementById('outcome'); o.value = ''; "
                     "o.dispatchEvent(new Event('change')); })()")
    classes = browser.evaluate("[...document.querySelectorAll('.outcome')].map(s => s.className)")
    check("outcome outcome-constructor" not in classes and "outcome" in classes,
          "an unknown outcome gets no class of its own")
    click(browser, "sort-outcome")
    click(browser, "sort-outcome")
    check(browser.errors() == [], f"no console errors: {browser.errors()}")
foreign = work / "foreign"
foreign.mkdir()
(foreign / "index.html").write_text("<html>my own page</html>")
done = subprocess.run([cli, "preview", shared / "assets/Box/specgloss/Box.gltf", "-o", foreign, "--size", "32", "-q"],
                      capture_output=True, text=True)
check(done.returncode == 0 and "not a page gltf-pbr wrote" in done.stderr,
      f"preview into a folder with someone's index.html: exit {done.returncode}, {done.stderr}")
check((foreign / "before.png").is_file(), "the preview is written beside someone's index.html")
done = subprocess.run([cli, "gallery", foreign], capture_output=True, text=True)
check(done.returncode == 3 and "not a page gltf-pbr wrote" in done.stderr,
      f"gallery over someone's index.html: exit {done.returncode}, {done.stderr}")
check((foreign / "index.html").read_text() == "<html>my own page</html>", "someone's index.html is left as it was")
(foreign / "index.html").unlink()
run("gallery", foreign)
run("gallery", foreign)  # a page it wrote is replaced
check("gltf-pbr gallery" in (foreign / "index.html").read_text(), "the page is written once the folder is free")

if failures:
    sys.exit(f"{len(failures)} checks failed")
shutil.rmtree(work)
print("gallery: all checks passed", file=sys.stderr)
