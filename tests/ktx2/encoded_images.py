#!/usr/bin/env python3
"""KTX2 images (KHR_texture_basisu) as a real encoder writes them, judged by gltf-pbr validate.

  encoded_images.py GLTF_PBR_CLI SHARED_DIR KTX2_ENCODE_MJS

ktx2-encoder (basis_universal) encodes the shared assets' textures, the glTF then names each KTX2
image through KHR_texture_basisu without a fallback, as glTF-Transform's ktx2 transform does:
- BoxTextured's base colour in every Basis form (UASTC, UASTC + Zstandard, ETC1S + BasisLZ) with a
  full mip pyramid: no KTX2_* issue at all;
- the same without mipmaps: KTX2_MIPMAPS_INCOMPLETE under its mipmapping sampler, none under a
  LINEAR one;
- Avocado's three maps, colour (sRGB) and non-colour (linear): the encoder writes BT709 primaries
  for linear data too, where KHR_texture_basisu asks for unspecified ones, which validate names;
  with the primaries set to unspecified (as a pipeline that follows the extension writes them) the
  files have no KTX2_* issue.
"""
import json
import pathlib
import shutil
import subprocess
import sys
import tempfile

from PIL import Image

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from script_checks import check, finish  # noqa: E402

cli, shared, encode_script = sys.argv[1:4]
shared = pathlib.Path(shared)
scratch = tempfile.TemporaryDirectory(prefix="gltf-pbr-ktx2-")  # removed at exit, failed or not
work = pathlib.Path(scratch.name)


def encode(png, target, mode, transfer, mipmaps="mipmaps"):
    image = Image.open(png).convert("RGBA")
    raw = work / (target.stem + ".rgba")
    raw.write_bytes(image.tobytes())
    subprocess.run(["node", encode_script, raw, str(image.width), str(image.height), mode, transfer, mipmaps,
                    target], check=True, capture_output=True)
    raw.unlink()
    return target


def ktx2_issues(gltf):
    result = subprocess.run([cli, "validate", "-f", "json", gltf], capture_output=True, text=True)
    if result.returncode not in (0, 1):
        sys.exit(f"validate {gltf} exited {result.returncode}:\n{result.stderr}")
    report = json.loads(result.stdout)
    return [(m["code"], m.get("pointer"), m["severity"], m["message"]) for m in report["issues"]["messages"]
            if m["code"].startswith("KTX2_")]


def with_basisu(source_gltf, folder, images, samplers=None):
    """source_gltf with image i's file replaced by images[i] (a KTX2 file), through KHR_texture_basisu."""
    doc = json.loads(source_gltf.read_text())
    folder.mkdir(parents=True, exist_ok=True)
    for name in {b["uri"] for b in doc.get("buffers", []) if "uri" in b}:
        shutil.copy(source_gltf.parent / name, folder / name)
    for i, ktx2 in images.items():
        doc["images"][i] = {"uri": ktx2.name}
    for texture in doc["textures"]:
        texture["extensions"] = {"KHR_texture_basisu": {"source": texture.pop("source")}}
    for key in ("extensionsUsed", "extensionsRequired"):
        doc[key] = sorted(set(doc.get(key, [])) | {"KHR_texture_basisu"})
    if samplers is not None:
        doc["samplers"] = samplers
    target = folder / source_gltf.name
    target.write_text(json.dumps(doc))
    return target


def primaries_unspecified(ktx2):
    """The DFD's colorPrimaries byte (the basic block's byte 9, after the DFD's size) set to 0."""
    data = bytearray(ktx2.read_bytes())
    dfd = int.from_bytes(data[48:52], "little")
    data[dfd + 4 + 9] = 0
    ktx2.write_bytes(bytes(data))


# BoxTextured: one base colour map, sampled with LINEAR_MIPMAP_NEAREST.
box = shared / "assets/BoxTextured/metalrough/BoxTextured.gltf"
logo = box.parent / "CesiumLogoFlat.png"
for mode in ("uastc", "uastc-zstd", "etc1s"):
    folder = work / ("box-" + mode)
    folder.mkdir()
    ktx2 = encode(logo, folder / "logo.ktx2", mode, "srgb")
    found = ktx2_issues(with_basisu(box, folder, {0: ktx2}))
    check(found == [], f"BoxTextured's base colour as {mode} with mipmaps has no KTX2 issue: {found}")

folder = work / "box-no-mipmaps"
folder.mkdir()
ktx2 = encode(logo, folder / "logo.ktx2", "etc1s", "srgb", "no-mipmaps")
found = ktx2_issues(with_basisu(box, folder, {0: ktx2}))
check([(code, pointer, severity) for code, pointer, severity, _ in found] ==
      [("KTX2_MIPMAPS_INCOMPLETE", "/images/0", 1)] and "1 of the 9 mip levels" in found[0][3],
      f"without mipmaps under a mipmapping sampler: one KTX2_MIPMAPS_INCOMPLETE warning: {found}")
found = ktx2_issues(with_basisu(box, folder, {0: ktx2}, samplers=[{"magFilter": 9729, "minFilter": 9729}]))
check(found == [], f"without mipmaps under a LINEAR sampler: no KTX2 issue: {found}")

# Avocado: base colour (colour data), roughness-metallic and normal maps (non-colour data).
avocado = shared / "assets/Avocado/metalrough/Avocado.gltf"
doc = json.loads(avocado.read_text())
uris = [image["uri"] for image in doc["images"]]
folder = work / "avocado"
folder.mkdir()
ktx2s = {}
for i, uri in enumerate(uris):
    colour = "baseColor" in uri
    ktx2s[i] = encode(avocado.parent / uri, folder / (pathlib.Path(uri).stem + ".ktx2"),
                      "etc1s" if colour else "uastc-zstd" if "roughness" in uri else "uastc",
                      "srgb" if colour else "linear")
gltf = with_basisu(avocado, folder, ktx2s)
found = ktx2_issues(gltf)
linear = sorted(f"/images/{i}" for i, uri in enumerate(uris) if "baseColor" not in uri)
check(sorted(pointer for _, pointer, _, _ in found) == linear and
      all(code == "KTX2_BASISU_MISMATCH" and "reads it as non-colour data" in message and
          "colorPrimaries 1 and transferFunction 1" in message for code, _, _, message in found),
      f"Avocado: the encoder's BT709 primaries on linear data are named on each non-colour map only: {found}")
for i, ktx2 in ktx2s.items():
    if f"/images/{i}" in linear:
        primaries_unspecified(ktx2)
found = ktx2_issues(gltf)
check(found == [], f"Avocado with unspecified primaries on its linear maps has no KTX2 issue: {found}")

finish()
