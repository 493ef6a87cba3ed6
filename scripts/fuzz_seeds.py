#!/usr/bin/env python3
"""Seeds for the convert fuzzer (fuzz/fuzz_convert.cpp), written into a scratch folder, never into
the repository: the small spec-gloss assets of ../shared/assets packed into single files (a GLB,
buffers and images in its BIN chunk; a .gltf, in data: URIs), and constructed spec-gloss GLBs whose
textures take the decoders' odd paths (16-bit grey, grey + alpha, palette with transparency,
progressive and CMYK JPEG, a specular-glossiness map beside a diffuse of another size).

    python3 scripts/fuzz_seeds.py OUT_DIR SHARED_ASSETS_DIR [MAX_BYTES]
"""
import base64
import io
import json
import struct
import sys
from pathlib import Path
from urllib.parse import unquote

from PIL import Image


def mime_of(data):
    """The media type of a buffer's or an image's bytes, by signature."""
    if data.startswith(b"\x89PNG"):
        return "image/png"
    return "image/jpeg" if data.startswith(b"\xff\xd8") else "application/octet-stream"


def glb(document, binary):
    """A GLB of a document whose one buffer is `binary` (glTF 2.0 section 4.4)."""
    binary += b"\0" * (-len(binary) % 4)
    if binary:
        document["buffers"] = [{"byteLength": len(binary)}]
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<I4s", len(text), b"JSON") + text
    if binary:
        chunks += struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def pack(gltf_path):
    """The .gltf at gltf_path with its buffers and images moved into one BIN chunk."""
    document = json.loads(gltf_path.read_text())
    binary = bytearray()

    def append(data):
        binary.extend(b"\0" * (-len(binary) % 4))
        offset = len(binary)
        binary.extend(data)
        return offset

    offsets = [append((gltf_path.parent / unquote(b["uri"])).read_bytes()) for b in document.get("buffers", [])]
    for view in document.get("bufferViews", []):
        view["byteOffset"] = view.get("byteOffset", 0) + offsets[view["buffer"]]
        view["buffer"] = 0
    views = document.setdefault("bufferViews", [])
    for image in document.get("images", []):
        if "uri" not in image:
            continue
        data = (gltf_path.parent / unquote(image.pop("uri"))).read_bytes()
        image["mimeType"] = mime_of(data)
        views.append({"buffer": 0, "byteOffset": append(data), "byteLength": len(data)})
        image["bufferView"] = len(views) - 1
    return glb(document, bytes(binary))


def embedded(gltf_path):
    """The .gltf at gltf_path as one text file, its buffers and images in data: URIs (RFC 2397)."""
    document = json.loads(gltf_path.read_text())
    for item in document.get("buffers", []) + document.get("images", []):
        if "uri" in item:
            data = (gltf_path.parent / unquote(item["uri"])).read_bytes()
            item["uri"] = f"data:{mime_of(data)};base64," + base64.b64encode(data).decode()
    return json.dumps(document, separators=(",", ":")).encode()


def encoded(image, **save):
    out = io.BytesIO()
    image.save(out, **save)
    return out.getvalue()


def gradient(mode, size):
    """A small image of `mode` whose texels all differ, so the bake solves more than one input."""
    w, h = size
    rgba = Image.new("RGBA", size)
    rgba.putdata([(x * 255 // max(1, w - 1), y * 255 // max(1, h - 1), (x * y) % 256, 128 + x) for y in range(h) for x in range(w)])
    return rgba.convert(mode)


def grey16(size):
    """A 16-bit grey image (Pillow writes no 16-bit colour PNG)."""
    image = Image.new("I;16", size)
    image.putdata([(i * 4099) % 65536 for i in range(size[0] * size[1])])
    return image


def constructed(diffuse, spec_gloss):
    """A textured quad whose material is spec-gloss with the two encoded images given."""
    positions = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
    uvs = struct.pack("<8f", 0, 0, 1, 0, 1, 1, 0, 1)
    indices = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    parts, views = bytearray(), []
    for data in (positions, uvs, indices, diffuse, spec_gloss):
        parts.extend(b"\0" * (-len(parts) % 4))
        views.append({"buffer": 0, "byteOffset": len(parts), "byteLength": len(data)})
        parts.extend(data)
    document = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_pbrSpecularGlossiness"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
        "bufferViews": views,
        "images": [{"bufferView": 3, "mimeType": mime_of(diffuse)}, {"bufferView": 4, "mimeType": mime_of(spec_gloss)}],
        "textures": [{"source": 0}, {"source": 1}],
        "materials": [{
            "extensions": {"KHR_materials_pbrSpecularGlossiness": {
                "diffuseTexture": {"index": 0},
                "specularGlossinessTexture": {"index": 1},
                "diffuseFactor": [1, 0.9, 0.8, 1],
                "specularFactor": [0.5, 0.5, 0.5],
                "glossinessFactor": 0.8,
            }},
        }],
    }
    return glb(document, bytes(parts))


def main(out_dir, assets, max_bytes=65536):
    out_dir.mkdir(parents=True, exist_ok=True)
    written = 0
    for gltf in sorted(assets.glob("*/specgloss/*.gltf")):
        for data, name in ((pack(gltf), f"{gltf.stem}.glb"), (embedded(gltf), f"{gltf.stem}.gltf")):
            if len(data) <= max_bytes:
                (out_dir / name).write_bytes(data)
                written += 1
    odd = {
        "grey16": encoded(grey16((8, 8)), format="PNG"),
        "grey_alpha": encoded(gradient("LA", (8, 8)), format="PNG"),
        "palette_transparency": encoded(gradient("RGBA", (8, 8)).convert("P"), format="PNG", transparency=0),
        "progressive_jpeg": encoded(gradient("RGB", (16, 16)), format="JPEG", progressive=True),
        "cmyk_jpeg": encoded(gradient("CMYK", (8, 8)), format="JPEG"),
        "grey_jpeg": encoded(gradient("L", (8, 8)), format="JPEG"),
    }
    spec_gloss = encoded(gradient("RGBA", (4, 4)), format="PNG")
    for name, diffuse in odd.items():
        (out_dir / f"constructed_{name}.glb").write_bytes(constructed(diffuse, spec_gloss))
        written += 1
    print(f"{written} convert seeds in {out_dir}", file=sys.stderr)


if __name__ == "__main__":
    main(Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3]) if len(sys.argv) > 3 else 65536)
