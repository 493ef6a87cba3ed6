"""The Python module gltf_pbr on real assets from ../shared: the same results as the tool, errors
that name the file, pointer and reason, the GIL released while a file is worked on, and the README's
example as written."""
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import threading
import time

import pytest

import gltf_pbr

SHARED = pathlib.Path(os.environ["GLTF_PBR_SHARED_DIR"])
CLI = os.environ["GLTF_PBR_CLI"]
SOURCE = pathlib.Path(os.environ["GLTF_PBR_SOURCE_DIR"])
sys.path.insert(0, str(SOURCE / "tests" / "pipeline"))
from reports import without_times  # noqa: E402  (the comparison the pipeline tests use)

DUCK = SHARED / "assets/Duck/specgloss/Duck.gltf"
AVOCADO = SHARED / "assets/Avocado/specgloss/Avocado.gltf"
BOX = SHARED / "assets/Box/specgloss/Box.gltf"


def tool(*args):
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, check=False)


def test_version_is_the_tools():
    assert tool("--version").stdout.strip() == f"gltf-pbr {gltf_pbr.__version__}"
    assert re.fullmatch(r"\d+\.\d+\.\d+", gltf_pbr.__version__)


def test_convert_reports_and_writes_what_the_tool_does(tmp_path):
    ran = tool("convert", DUCK, "-o", tmp_path / "tool/Duck.gltf", "--report", tmp_path / "tool.json", "-q")
    assert ran.returncode == 0, ran.stderr
    by_tool = json.loads((tmp_path / "tool.json").read_text())["files"][0]

    report = gltf_pbr.convert(DUCK, tmp_path / "module/Duck.gltf")

    assert report["status"] == "converted"
    assert [m["outcome"] for m in report["materials"]] == ["metalness"]
    assert report["materials"][0]["deltaE2000"]["readingA"]["diffuse"]["mean"] >= 0
    for key in ("input", "output"):
        by_tool.pop(key), report.pop(key)
    assert without_times(report) == without_times(by_tool)
    for name in ("Duck.gltf", "Duck0.bin"):
        assert (tmp_path / "module" / name).read_bytes() == (tmp_path / "tool" / name).read_bytes()


def test_the_error_model_is_the_tools_and_its_appearance_figures_come_with_it(tmp_path):
    ran = tool("convert", BOX, "-o", tmp_path / "tool/Box.gltf", "--error-model", "appearance",
               "--report", tmp_path / "tool.json", "-q")
    assert ran.returncode == 0, ran.stderr
    by_tool = json.loads((tmp_path / "tool.json").read_text())["files"][0]

    report = gltf_pbr.convert(BOX, tmp_path / "module/Box.gltf", error_model="appearance")
    plain = gltf_pbr.convert(BOX, tmp_path / "plain/Box.gltf")

    assert report["materials"][0]["deltaE2000"]["readingA"]["appearance"]["mean"] >= 0
    assert plain["materials"][0]["deltaE2000"]["readingA"]["appearance"] is None
    for key in ("input", "output"):
        by_tool.pop(key), report.pop(key)
    assert without_times(report) == without_times(by_tool)
    assert (tmp_path / "module/Box.gltf").read_bytes() == (tmp_path / "tool/Box.gltf").read_bytes()
    assert (tmp_path / "module/Box.gltf").read_bytes() != (tmp_path / "plain/Box.gltf").read_bytes()
    drawn = gltf_pbr.preview(BOX, tmp_path / "preview", size=32, error_model="appearance")
    assert drawn["shading"]["conversion_error_model"] == "appearance"
    with pytest.raises(ValueError, match="error_model must be one of normal-incidence, appearance"):
        gltf_pbr.convert(BOX, tmp_path / "x/Box.gltf", error_model="visual")


def test_validate_returns_the_tools_khronos_report(tmp_path):
    ran = tool("validate", "--format", "json", DUCK)
    assert ran.returncode in (0, 1), ran.stderr
    assert gltf_pbr.validate(DUCK) == json.loads(ran.stdout)


def test_validate_runs_only_the_steps_asked_for():
    ours = ("PBR_", "IMAGE_", "MESH_")
    every_step = gltf_pbr.validate(DUCK)["issues"]["messages"]
    structure = gltf_pbr.validate(DUCK, only=["structure"])["issues"]["messages"]
    assert any(m["code"].startswith(ours) for m in every_step)
    assert [m for m in every_step if not m["code"].startswith(ours)] == structure
    with pytest.raises(ValueError, match="only must be one of"):
        gltf_pbr.validate(DUCK, only=["spelling"])


def test_validate_takes_the_lint_profile_as_the_tool_does():
    duck = SHARED / "assets/Duck/metalrough/Duck.gltf"
    for profile in ("tolerant", "strict"):
        ran = tool("validate", "--format", "json", "--profile", profile, duck)
        assert ran.returncode in (0, 1), ran.stderr
        assert gltf_pbr.validate(duck, profile=profile) == json.loads(ran.stdout)
    strict = gltf_pbr.validate(duck, profile="strict")["issues"]["messages"]
    assert any("the strict profile's" in m["message"] for m in strict)
    with pytest.raises(ValueError, match="profile must be one of tolerant, strict"):
        gltf_pbr.validate(duck, profile="lax")


def test_bad_input_raises_input_error_with_file_pointer_and_reason(tmp_path):
    broken = tmp_path / "broken.gltf"
    broken.write_text(json.dumps({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_pbrSpecularGlossiness"],
        "materials": [{"extensions": {"KHR_materials_pbrSpecularGlossiness": {"diffuseTexture": {"index": 5}}}}],
    }))
    with pytest.raises(gltf_pbr.InputError) as raised:
        gltf_pbr.convert(broken, tmp_path / "out.gltf")
    error = raised.value
    assert isinstance(error, ValueError)
    assert error.file == str(broken)
    assert error.pointer.startswith("/materials/0")
    assert error.reason and error.offset is None
    assert str(broken) in str(error) and error.pointer in str(error)
    assert not (tmp_path / "out.gltf").exists()


def test_a_cut_glb_names_its_byte_offset(tmp_path):
    cut = tmp_path / "cut.glb"
    cut.write_bytes((SHARED / "assets/Duck/metalrough-glb/Duck.glb").read_bytes()[:20])
    with pytest.raises(gltf_pbr.InputError) as raised:
        gltf_pbr.convert(cut, tmp_path / "out.glb")
    assert raised.value.offset is not None and raised.value.pointer == ""


def test_an_input_is_never_overwritten_unless_asked(tmp_path):
    copy = tmp_path / "Duck"
    shutil.copytree(DUCK.parent, copy)
    copy.chmod(0o755)  # ../shared is read-only, and copytree keeps the folder's mode
    original = (copy / "Duck.gltf").read_bytes()
    with pytest.raises(RuntimeError, match="refusing to overwrite the input"):
        gltf_pbr.convert(copy / "Duck.gltf", copy / "Duck.gltf")
    assert (copy / "Duck.gltf").read_bytes() == original

    (copy / "Duck.gltf").chmod(0o644)  # a read-only input is never replaced
    report = gltf_pbr.convert(copy / "Duck.gltf", copy / "Duck.gltf", replace_input=True)
    assert report["status"] == "converted"
    assert "KHR_materials_pbrSpecularGlossiness" not in (copy / "Duck.gltf").read_text()


def test_convert_many_keeps_the_order_and_a_failure_stops_no_other_file(tmp_path):
    missing = tmp_path / "missing.gltf"
    reports = gltf_pbr.convert_many(
        [(DUCK, tmp_path / "a/Duck.glb"), (missing, tmp_path / "b/missing.gltf"), (BOX, tmp_path / "c/Box.gltf")],
        threads=2)
    assert [r["status"] for r in reports] == ["converted", "failed", "converted"]
    assert reports[1]["error"]["file"] == str(missing) and reports[1]["error"]["reason"]
    assert (tmp_path / "a/Duck.glb").stat().st_size > 0 and (tmp_path / "c/Box.gltf").stat().st_size > 0
    assert not (tmp_path / "b").exists()


def test_the_metalness_tolerance_is_the_tools(tmp_path):
    box = SHARED / "assets/BoxTextured/specgloss/BoxTextured.gltf"
    ran = tool("convert", box, "-o", tmp_path / "tool/Box.gltf", "--metalness-tolerance", "0",
               "--report", tmp_path / "tool.json", "-q")
    assert ran.returncode == 0, ran.stderr
    by_tool = json.loads((tmp_path / "tool.json").read_text())["files"][0]

    every = gltf_pbr.convert(box, tmp_path / "every/Box.gltf", metalness_tolerance=0)
    fewer = gltf_pbr.convert(box, tmp_path / "fewer/Box.gltf")
    ran = tool("convert", box, "-o", tmp_path / "tool-default/Box.gltf", "--report", tmp_path / "default.json", "-q")
    assert ran.returncode == 0, ran.stderr
    by_tool_default = json.loads((tmp_path / "default.json").read_text())["files"][0]
    assert without_times(fewer)["materials"] == without_times(by_tool_default)["materials"]

    assert "metalnessLevels" not in every["materials"][0]
    levels = fewer["materials"][0]["metalnessLevels"]
    assert levels["written"] < levels["solved"]
    for key in ("input", "output"):
        by_tool.pop(key), every.pop(key)
    assert without_times(every) == without_times(by_tool)
    with pytest.raises(ValueError, match="metalness_tolerance must be a finite number >= 0"):
        gltf_pbr.convert(box, tmp_path / "x/Box.gltf", metalness_tolerance=-1)


def test_options_are_checked_by_name():
    with pytest.raises(ValueError, match="target must be one of metalness, specular"):
        gltf_pbr.convert(DUCK, "/nonexistent/out.gltf", target="gold")
    with pytest.raises(ValueError, match="png_compression must be 0-9"):
        gltf_pbr.convert(DUCK, "/nonexistent/out.gltf", png_compression=10)
    with pytest.raises(ValueError, match="width must be 16-8192"):
        gltf_pbr.preview(DUCK, "/nonexistent/preview", size=8)


def test_the_gil_is_released_while_a_file_converts(tmp_path):
    window = {}

    def convert():
        window["start"] = time.monotonic()
        gltf_pbr.convert(AVOCADO, tmp_path / "Avocado.gltf", error_samples=0)
        window["end"] = time.monotonic()

    worker = threading.Thread(target=convert)
    first = last = None  # this thread's first and last ticks while the worker is inside the call
    worker.start()
    while worker.is_alive():
        now = time.monotonic()
        if "start" in window and "end" not in window:
            first = first or now
            last = now
    worker.join()
    # With the GIL held for the whole call this thread could not run inside the call at all.
    assert window["end"] - window["start"] > 0.05
    assert first is not None and last - first > 0.5 * (window["end"] - window["start"])


def test_preview_writes_its_images_and_returns_its_report(tmp_path):
    report = gltf_pbr.preview(DUCK, tmp_path / "preview", size=64)
    for name in ("before.png", "after.png", "difference.png", "sheet.png"):
        assert (tmp_path / "preview" / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert json.loads((tmp_path / "preview/report.json").read_text()) == report
    assert report["input"] == str(DUCK)
    assert report["width"] == 64 and report["height"] == 64
    assert report["material_issues"] is None  # not checked unless asked


def test_preview_with_lint_reports_the_material_issues_of_both_sides(tmp_path):
    report = gltf_pbr.preview(DUCK, tmp_path / "preview", size=64, lint="strict")
    issues = report["material_issues"]
    assert issues["profile"] == "strict"
    assert "PBR_LEGACY_SPEC_GLOSS" in {i["code"] for i in issues["before"]}
    assert "PBR_LEGACY_SPEC_GLOSS" not in {i["code"] for i in issues["after"]}
    with pytest.raises(ValueError):
        gltf_pbr.preview(DUCK, tmp_path / "other", size=64, lint="lenient")


def test_the_readme_example_runs_as_written(tmp_path):
    lines = (SOURCE / "README.md").read_text().splitlines()
    start = lines.index("<!-- the example tests/python/test_module.py runs as written -->") + 2  # the marker, then the fence
    end = lines.index("```", start)
    example = tmp_path / "example.py"
    example.write_text("\n".join(lines[start:end]) + "\n")
    ran = subprocess.run([sys.executable, str(example), str(DUCK), str(tmp_path)], capture_output=True, text=True,
                         check=False)
    assert ran.returncode == 0, ran.stderr
    out = ran.stdout.splitlines()
    assert out[0].startswith("/materials/0 metalness {")
    assert re.fullmatch(r"errors: 0 warnings: \d+", out[1])
    assert out[2].startswith(f"refused: {tmp_path}/missing.gltf ")
