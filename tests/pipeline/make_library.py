"""Writes a library of glTF files for the pipeline tests and benchmarks: the generated samples and
the shared spec-gloss assets, repeated with small real differences (each copy's spec-gloss factors
moved a little, so no two convert alike), in nested folders, each copy beside its own resources.

    python3 make_library.py SAMPLES_DIR SHARED_DIR OUT_DIR COUNT [TEXTURED_EVERY [NAMES]]

Every TEXTURED_EVERY-th file (default 50) is a textured shared asset, taken in turn from NAMES (a
comma-separated list of shared asset names; default Box,Duck,BoxTextured); the rest are factor-only
samples.
Deterministic: the same arguments write the same bytes."""
import json
import os
import pathlib
import shutil
import sys

samples_dir, shared_dir, out_dir = map(pathlib.Path, sys.argv[1:4])
count = int(sys.argv[4])
textured_every = int(sys.argv[5]) if len(sys.argv) > 5 else 50
textured_names = sys.argv[6].split(",") if len(sys.argv) > 6 else ["Box", "Duck", "BoxTextured"]

samples = sorted(samples_dir.glob("*.gltf"))
textured = [shared_dir / "assets" / name / "specgloss" / f"{name}.gltf" for name in textured_names]
textured = [path for path in textured if path.exists()]


def vary(document, step):
    """Scales every spec-gloss diffuse factor by a factor a little below one: a real change."""
    scale = 1.0 - 0.0004 * (step % 997)
    for material in document.get("materials", []):
        legacy = material.get("extensions", {}).get("KHR_materials_pbrSpecularGlossiness")
        if legacy is None:
            continue
        diffuse = legacy.get("diffuseFactor", [1.0, 1.0, 1.0, 1.0])
        legacy["diffuseFactor"] = [round(c * scale, 6) for c in diffuse[:3]] + diffuse[3:]
    return document


def link_resources(source, folder):
    """The source's external resources beside the copy: hard links where the file system allows."""
    document = json.loads(source.read_text())
    for entry in document.get("buffers", []) + document.get("images", []):
        uri = entry.get("uri", "")
        if not uri or uri.startswith("data:") or (folder / uri).exists():
            continue
        target = folder / uri
        target.parent.mkdir(parents=True, exist_ok=True)
        try:
            os.link(source.parent / uri, target)
        except OSError:
            shutil.copyfile(source.parent / uri, target)


for i in range(count):
    source = textured[(i // textured_every) % len(textured)] if textured and i % textured_every == 0 \
        else samples[i % len(samples)]
    folder = out_dir / f"group{i // 100:03d}" / source.stem
    folder.mkdir(parents=True, exist_ok=True)
    link_resources(source, folder)
    document = vary(json.loads(source.read_text()), i)
    (folder / f"{source.stem}-{i:05d}.gltf").write_text(json.dumps(document, indent=1, sort_keys=True))
print(f"{count} files in {out_dir}")
