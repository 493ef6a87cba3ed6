// Writes a glTF whose NORMAL accessor holds N vectors of length 2√3 (not unit): the structure step
// raises ACCESSOR_VECTOR3_NON_UNIT once per vertex, N issues in one file, for the report-size
// benchmark. Positions are all 0, with exact min/max, so that nothing else is reported.
//   node make_million_issues.mjs N OUT.gltf    (writes OUT.bin beside it)
import fs from 'node:fs';
import path from 'node:path';

const n = Number(process.argv[2]), out = process.argv[3];
const positions = new Float32Array(n * 3), normals = new Float32Array(n * 3).fill(2);
const bin = path.basename(out).replace(/\.gltf$/, '') + '.bin', length = positions.byteLength;
fs.writeFileSync(path.join(path.dirname(out), bin), Buffer.concat([Buffer.from(positions.buffer), Buffer.from(normals.buffer)]));
fs.writeFileSync(out, JSON.stringify({
  asset: { version: '2.0' },
  buffers: [{ uri: bin, byteLength: 2 * length }],
  bufferViews: [{ buffer: 0, byteLength: length, target: 34962 }, { buffer: 0, byteOffset: length, byteLength: length, target: 34962 }],
  accessors: [{ bufferView: 0, componentType: 5126, count: n, type: 'VEC3', min: [0, 0, 0], max: [0, 0, 0] },
              { bufferView: 1, componentType: 5126, count: n, type: 'VEC3' }],
  meshes: [{ primitives: [{ attributes: { POSITION: 0, NORMAL: 1 }, mode: 0 }] }],
  nodes: [{ mesh: 0 }], scenes: [{ nodes: [0] }], scene: 0,
}));
