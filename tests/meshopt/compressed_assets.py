#!/usr/bin/env python3
"""EXT_meshopt_compression on the shared assets, packed by gltfpack (npm) twice: compressed and not.

  compressed_assets.py GLTF_PBR_CLI SHARED_DIR GLTFPACK

Lossless packing (-noq: no quantization, so no filter): the compressed asset must validate with the
very issues of its uncompressed twin, draw the same previews, and convert (to .gltf and .glb)
into an output that stays compressed, carries the compressed bytes unchanged, and validates as the
twin's conversion does. Quantized packing (-cc) adds the octahedral, quaternion and exponential
filters: every filter must occur, decode without a MESHOPT_* issue, and draw like the quantized
twin up to the filters' precision.
"""
import json
import pathlib
import subprocess
import sys
import tempfile
import urllib.parse

from PIL import Image, ImageChops, ImageStat

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from script_checks import check, finish  # noqa: E402

cli, shared, gltfpack = sys.argv[1:4]
scratch = tempfile.TemporaryDirectory(prefix="gltf-pbr-meshopt-")  # removed at exit, failed or not
work = pathlib.Path(scratch.name)


def run(*command):
    result = subprocess.run(command, capture_output=True, text=True)
    # validate exits 1 when a file has errors, which the comparisons judge; nothing else may fail.
    if result.returncode != 0 and not (command[1] == "validate" and result.returncode == 1):
        sys.exit(f"{' '.join(map(str, command))} exited {result.returncode}:\n{result.stderr}")
    return result.stdout


def pack(source, target, *flags):
    target.parent.mkdir(parents=True, exist_ok=True)
    run(gltfpack, *flags, "-kn", "-km", "-ke", "-i", source, "-o", target)
    return target


def issues(path):
    report = json.loads(run(cli, "validate", "-f", "json", path))
    return [(m["code"], m.get("pointer", m.get("offset")), m["severity"], m["message"])
            for m in report["issues"]["messages"]]


def document(path):
    """The JSON and, for a GLB, the BIN chunk."""
    data = path.read_bytes()
    if data[:4] != b"glTF":
        return json.loads(data), b""
    json_length = int.from_bytes(data[12:16], "little")
    bin_at = 20 + json_length
    bin_length = int.from_bytes(data[bin_at:bin_at + 4], "little") if len(data) > bin_at else 0
    return json.loads(data[20:bin_at]), data[bin_at + 8:bin_at + 8 + bin_length]


def compressed_views(doc):
    return [view["extensions"]["EXT_meshopt_compression"] for view in doc.get("bufferViews", [])
            if "EXT_meshopt_compression" in view.get("extensions", {})]


def compressed_sources(path):
    """The compressed bytes of every compressed view, in view order, with its mode and filter."""
    doc, bin_chunk = document(path)
    sources = []
    for view in compressed_views(doc):
        buffer = doc["buffers"][view["buffer"]]
        data = (path.parent / urllib.parse.unquote(buffer["uri"])).read_bytes() if "uri" in buffer else bin_chunk
        offset = view.get("byteOffset", 0)
        sources.append((view["mode"], view.get("filter", "NONE"), data[offset:offset + view["byteLength"]]))
    return sources


def preview(path, folder):
    run(cli, "preview", path, "-o", folder, "--size", "64")
    return {side: Image.open(folder / f"{side}.png").convert("RGB") for side in ("before", "after")}


def mean_difference(a, b):
    return sum(ImageStat.Stat(ImageChops.difference(a, b)).mean) / 3


# gltfpack reads no Draco: the Draco variants are left out.
inputs = sorted(p for p in pathlib.Path(shared, "assets").glob("*/specgloss*/*")
                if p.suffix in (".gltf", ".glb") and "draco" not in p.parent.name)
check(len(inputs) >= 12, f"{len(inputs)} shared spec-gloss assets without Draco (at least 12)")
filters_seen = set()
for n, source in enumerate(inputs):
    name = f"{n}-{source.stem}"
    suffix = source.suffix

    # Lossless: the same data, so the same findings and pixels.
    plain = pack(source, work / name / "plain" / f"asset{suffix}", "-noq")
    packed = pack(source, work / name / "packed" / f"asset{suffix}", "-noq", "-c")
    sources = compressed_sources(packed)
    check(len(sources) > 0 and not compressed_sources(plain), f"{name}: {len(sources)} compressed bufferViews")
    plain_issues, packed_issues = issues(plain), issues(packed)
    check(plain_issues == packed_issues,
          f"{name}: compressed validates as its twin ({len(packed_issues)} issues, "
          f"{sum(1 for i in packed_issues if i[0].startswith('MESH_'))} mesh, "
          f"{sum(1 for i in packed_issues if i[0].startswith('ACCESSOR_'))} accessor data)")
    if suffix == ".gltf":
        # A declared minimum that the decoded positions break: reported only if decoding ran.
        doc, _ = document(packed)
        position = doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
        doc["accessors"][position]["min"][0] -= 1
        planted = packed.with_name("planted.gltf")
        planted.write_text(json.dumps(doc))
        check(("ACCESSOR_MIN_MISMATCH", f"/accessors/{position}/min/0") in [i[:2] for i in issues(planted)],
              f"{name}: the accessor data checks ran on the decoded positions")
    plain_images = preview(plain, work / name / "plain-preview")
    packed_images = preview(packed, work / name / "packed-preview")
    # The TRIANGLES codec may rotate a triangle's corners (winding kept), so the rasterizer can
    # round a pixel or two one level apart: nothing more.
    largest = max(max(hi for _, hi in ImageStat.Stat(ImageChops.difference(plain_images[s], packed_images[s])).extrema)
                  for s in plain_images)
    mean = max(mean_difference(plain_images[s], packed_images[s]) for s in plain_images)
    check(largest <= 2 and mean < 0.01,
          f"{name}: compressed previews as its twin (largest difference {largest} of 255, mean {mean:.4f})")
    for out_suffix in (".gltf", ".glb"):
        converted = work / name / f"converted{out_suffix}" / f"asset{out_suffix}"
        twin = work / name / f"converted-twin{out_suffix}" / f"asset{out_suffix}"
        run(cli, "convert", packed, "-o", converted, "-q")
        run(cli, "convert", plain, "-o", twin, "-q")
        doc, _ = document(converted)
        placeholders = [b for b in doc["buffers"] if b.get("extensions", {}).get("EXT_meshopt_compression")]
        check("EXT_meshopt_compression" in doc.get("extensionsRequired", []) and
              compressed_sources(converted) == sources and
              all("uri" not in b for b in placeholders) and len(placeholders) == 1,
              f"{name} -> {out_suffix}: stays compressed, {len(sources)} compressed ranges byte for byte, "
              f"fallback buffer still without data")
        check(issues(converted) == issues(twin), f"{name} -> {out_suffix}: validates as its twin's conversion")

    # Quantized, with filters: decodes cleanly and draws like its twin within the filters' precision.
    quantized = pack(source, work / name / "quantized" / f"asset{suffix}")
    filtered = pack(source, work / name / "filtered" / f"asset{suffix}", "-cc")
    filters = {f for _, f, _ in compressed_sources(filtered)}
    filters_seen |= filters
    found = [i for i in issues(filtered) if i[0].startswith("MESHOPT_")]
    check(not found, f"{name}: filters {sorted(filters)} decode without a MESHOPT_* issue {found[:2]}")
    twin_images = preview(quantized, work / name / "quantized-preview")
    filtered_images = preview(filtered, work / name / "filtered-preview")
    difference = max(mean_difference(twin_images[s], filtered_images[s]) for s in twin_images)
    check(difference < 1.0, f"{name}: filtered previews within {difference:.3f} of 255 per channel on average (< 1)")

check(filters_seen >= {"NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL"},
      f"every filter occurs: {sorted(filters_seen)}")
finish()
