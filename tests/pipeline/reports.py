"""Comparing gltf-pbr convert reports across runs: every figure but the measured times, which differ
from run to run, must agree.

    python3 reports.py ONE.json OTHER.json ONE_OUTPUT_DIR OTHER_OUTPUT_DIR FILES
exits non-zero unless OTHER equals ONE (times aside, ONE's outputs moved to OTHER's folder) and
both report FILES files, none failed."""
import json
import pathlib
import sys


def without_times(value):
    """The report with its measured times (every "timeMs") taken out."""
    if isinstance(value, dict):
        return {k: without_times(v) for k, v in value.items() if k != "timeMs"}
    if isinstance(value, list):
        return [without_times(v) for v in value]
    return value


if __name__ == "__main__":
    one_path, other_path, one_dir, other_dir, files = sys.argv[1:6]
    one = json.loads(pathlib.Path(one_path).read_text())
    other = json.loads(pathlib.Path(other_path).read_text())
    for entry in one["files"]:  # the two runs wrote into different folders
        entry["output"] = entry["output"].replace(f"{one_dir}/", f"{other_dir}/", 1)
    for report in (one, other):
        assert report["totals"]["files"] == int(files) and report["totals"]["failed"] == 0, report["totals"]
    assert without_times(other) == without_times(one), f"{other_path} differs from {one_path} beyond its times"
