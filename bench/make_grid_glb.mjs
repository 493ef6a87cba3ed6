// Writes a synthetic GLB: a grid of N×N vertices (positions, normals, texcoords) and 2(N-1)² triangles
// with uint32 indices, for the validate benchmark. Deterministic; min/max are exact so that a
// correct validator reports no issue on it.   node make_grid_glb.mjs N OUT.glb
import fs from 'node:fs';

const n = Number(process.argv[2]), out = process.argv[3];
const vertices = n * n, triangles = 2 * (n - 1) * (n - 1);
const positions = new Float32Array(vertices * 3), normals = new Float32Array(vertices * 3), uvs = new Float32Array(vertices * 2);
for (let y = 0, v = 0; y < n; y++)
  for (let x = 0; x < n; x++, v++) {
    positions.set([x / (n - 1), Math.sin(x * 0.01) * Math.cos(y * 0.01) * 0.05, y / (n - 1)], v * 3);
    normals.set([0, 1, 0], v * 3);
    uvs.set([x / (n - 1), y / (n - 1)], v * 2);
  }
const indices = new Uint32Array(triangles * 3);
for (let y = 0, t = 0; y < n - 1; y++)
  for (let x = 0; x < n - 1; x++) {
    const a = y * n + x, b = a + 1, c = a + n, d = c + 1;
    indices.set([a, c, b, b, c, d], t);
    t += 6;
  }
let min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
for (let i = 0; i < positions.length; i++) { min[i % 3] = Math.min(min[i % 3], positions[i]); max[i % 3] = Math.max(max[i % 3], positions[i]); }
const parts = [positions, normals, uvs, indices].map((a) => Buffer.from(a.buffer));
let offset = 0;
const views = parts.map((p, i) => { const v = { buffer: 0, byteOffset: offset, byteLength: p.length, target: i === 3 ? 34963 : 34962 }; offset += p.length; return v; });
const json = {
  asset: { version: '2.0', generator: 'gltf-pbr bench/make_grid_glb.mjs' },
  scene: 0, scenes: [{ nodes: [0] }], nodes: [{ mesh: 0 }],
  meshes: [{ primitives: [{ attributes: { POSITION: 0, NORMAL: 1, TEXCOORD_0: 2 }, indices: 3, material: 0 }] }],
  materials: [{ pbrMetallicRoughness: { baseColorFactor: [0.5, 0.5, 0.5, 1], metallicFactor: 0, roughnessFactor: 0.5 } }],
  accessors: [
    { bufferView: 0, componentType: 5126, count: vertices, type: 'VEC3', min, max },
    { bufferView: 1, componentType: 5126, count: vertices, type: 'VEC3' },
    { bufferView: 2, componentType: 5126, count: vertices, type: 'VEC2' },
    { bufferView: 3, componentType: 5125, count: triangles * 3, type: 'SCALAR' },
  ],
  bufferViews: views, buffers: [{ byteLength: offset }],
};
// Float32 rounding: min/max must be the stored values.
json.accessors[0].min = min.map((x) => Math.fround(x)); json.accessors[0].max = max.map((x) => Math.fround(x));
let text = Buffer.from(JSON.stringify(json));
text = Buffer.concat([text, Buffer.alloc((4 - (text.length % 4)) % 4, 0x20)]);
const bin = Buffer.concat(parts);
const header = Buffer.alloc(12), jsonHeader = Buffer.alloc(8), binHeader = Buffer.alloc(8);
header.write('glTF', 0); header.writeUInt32LE(2, 4); header.writeUInt32LE(12 + 8 + text.length + 8 + bin.length, 8);
jsonHeader.writeUInt32LE(text.length, 0); jsonHeader.write('JSON', 4);
binHeader.writeUInt32LE(bin.length, 0); binHeader.write('BIN\0', 4);
const fd = fs.openSync(out + '.tmp', 'w');
for (const b of [header, jsonHeader, text, binHeader, bin]) fs.writeSync(fd, b);
fs.closeSync(fd);
fs.renameSync(out + '.tmp', out);
console.error(`${out}: ${vertices} vertices, ${triangles} triangles, ${(12 + 16 + text.length + bin.length) / 1e6} MB`);
