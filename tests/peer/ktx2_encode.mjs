// Encodes raw RGBA8 texels to a KTX2 file with ktx2-encoder (basis_universal), as a pipeline would.
//   node ktx2_encode.mjs RGBA_FILE WIDTH HEIGHT uastc|uastc-zstd|etc1s srgb|linear mipmaps|no-mipmaps OUT
// The entry point comes from GLTF_PBR_KTX2_ENCODER (tests/peer/ktx2_encoder.sh).
import { readFileSync, writeFileSync } from "node:fs";
import { pathToFileURL } from "node:url";

const [rgba, width, height, mode, transfer, mipmaps, out] = process.argv.slice(2);
const { encodeToKTX2 } = await import(pathToFileURL(process.env.GLTF_PBR_KTX2_ENCODER).href);
const texels = new Uint8Array(readFileSync(rgba));
const encoded = await encodeToKTX2(new Uint8Array(0), {
  isUASTC: mode !== "etc1s",
  needSupercompression: mode === "uastc-zstd",
  isSetKTX2SRGBTransferFunc: transfer === "srgb",
  isNormalMap: transfer === "linear",
  generateMipmap: mipmaps === "mipmaps",
  // The texels are decoded already (by PIL): the encoder's decoder hook hands them over.
  imageDecoder: async () => ({ data: texels, width: Number(width), height: Number(height) }),
});
writeFileSync(out, encoded);
