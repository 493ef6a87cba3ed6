// The body of bench/convert.sh (see there). Node, because the peers need it anyway.
import { spawnSync } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const [assetsDir] = process.argv.slice(2);
const ours = process.env.GLTF_PBR, peer = process.env.GLTF_TRANSFORM, runs = Number(process.env.RUNS || 5);
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'gltf-pbr-bench-'));
process.on('exit', () => fs.rmSync(work, { recursive: true, force: true }));

const inputs = [];
for (const model of fs.readdirSync(assetsDir).sort())
  for (const variant of ['specgloss', 'specgloss-glb-generated', 'specgloss-draco-generated']) {
    const dir = path.join(assetsDir, model, variant);
    if (!fs.existsSync(dir)) continue;
    for (const f of fs.readdirSync(dir)) if (/\.(gltf|glb)$/.test(f)) inputs.push({ name: variant === 'specgloss' ? model : `${model} (${variant.replace('specgloss-', '').replace('-generated', '')})`, file: path.join(dir, f) });
  }

// Wall seconds (clock around the whole process), CPU seconds (user + system) and peak RSS in MB
// (GNU time, whose own wall clock has only 10 ms resolution).
function timed(argv) {
  const start = process.hrtime.bigint();
  const r = spawnSync('/usr/bin/time', ['-f', '%M %U %S', ...argv], { encoding: 'utf8' });
  const seconds = Number(process.hrtime.bigint() - start) / 1e9;
  if (r.status !== 0) throw new Error(`${argv.join(' ')} failed:\n${r.stderr}`);
  const [kb, user, system] = r.stderr.trim().split('\n').pop().split(' ').map(Number);
  return { seconds, cpu: user + system, mb: kb / 1024 };
}
const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];

// Bytes of a .gltf/.glb and of every file it references.
function totalBytes(file) {
  const data = fs.readFileSync(file);
  const json = file.endsWith('.glb') ? JSON.parse(data.subarray(20, 20 + data.readUInt32LE(12)).toString()) : JSON.parse(data);
  let bytes = data.length;
  for (const item of [...(json.buffers || []), ...(json.images || [])])
    if (item.uri && !item.uri.startsWith('data:')) bytes += fs.statSync(path.resolve(path.dirname(file), decodeURIComponent(item.uri))).size;
  return bytes;
}

function errorSeen(input, output, viewer) {
  const r = spawnSync(ours, ['compare', input, output, '--viewer', viewer], { encoding: 'utf8', maxBuffer: 1 << 26 });
  if (r.status !== 0) throw new Error(r.stderr);
  return JSON.parse(r.stdout).summary;
}

// Ours and the peer's runs alternate, so that a slow spell of the machine falls on both.
function measure(input, index) {
  const tools = { ours: [], peer: [] }, outs = {};
  for (const tool of ['ours', 'peer']) outs[tool] = path.join(work, tool, String(index), path.basename(input));
  const argv = (tool) => (tool === 'ours' ? [ours, 'convert', input, '-o', outs.ours, '-q'] : [peer, 'metalrough', input, outs.peer]);
  for (let i = 0; i < runs; i++)
    for (const tool of ['ours', 'peer']) {
      fs.rmSync(path.dirname(outs[tool]), { recursive: true, force: true });
      fs.mkdirSync(path.dirname(outs[tool]), { recursive: true });
      tools[tool].push(timed(argv(tool)));
    }
  const summary = (tool) => ({
    seconds: median(tools[tool].map((s) => s.seconds)), cpu: median(tools[tool].map((s) => s.cpu)),
    mb: median(tools[tool].map((s) => s.mb)), bytes: totalBytes(outs[tool]),
    core: errorSeen(input, outs[tool], 'core'), full: errorSeen(input, outs[tool], 'full'),
  });
  return [summary('ours'), summary('peer')];
}

// Avocado with its maps resized to N², to see how each tool's cost grows with texels (sharp comes
// with glTF-Transform).
async function resizedAvocado(size) {
  const sharp = createRequire(path.join(process.env.GLTF_PBR_NODE_MODULES, 'resolve-from-here.js'))('sharp');
  const source = path.join(assetsDir, 'Avocado', 'specgloss'), dir = path.join(work, `avocado-${size}`);
  fs.mkdirSync(dir, { recursive: true });
  for (const f of fs.readdirSync(source)) {
    if (f.endsWith('.png')) await sharp(path.join(source, f)).resize(size, size).png().toFile(path.join(dir, f));
    else fs.copyFileSync(path.join(source, f), path.join(dir, f));
  }
  return { name: `Avocado ${size}²`, file: path.join(dir, 'Avocado.gltf'), texels: size * size };
}
for (const size of (process.env.SIZES || '512,1024,2048,4096').split(',').filter(Boolean).map(Number))
  inputs.push(await resizedAvocado(size));
// The shared Avocado is one more point of the growth table (its maps' size from the diffuse PNG's
// IHDR: width and height at bytes 16-23), so a single SIZES entry still gives a row; not where a
// resized copy has its size (the copies are encoded alike, the shared maps otherwise).
const avocado = inputs.find((x) => x.name === 'Avocado');
if (avocado && inputs.some((x) => x.texels)) {
  const ihdr = fs.readFileSync(path.join(path.dirname(avocado.file), 'Avocado_diffuse.png')).subarray(16, 24);
  const [width, height] = [ihdr.readUInt32BE(0), ihdr.readUInt32BE(4)];
  if (!inputs.some((x) => x.texels === width * height))
    Object.assign(avocado, { texels: width * height, growthName: `Avocado (shared, ${width}×${height})` });
}

// A figure nothing measured is null in our JSON (an asset with no spec-gloss material): say so, never 0.
const fixed = (digits) => (x) => (x === null || x === undefined ? 'not measured' : x.toFixed(digits));
const f1 = fixed(1), f2 = fixed(2), f3 = fixed(3);
console.log(`### gltf-pbr convert vs glTF-Transform ${process.env.GLTF_TRANSFORM_VERSION} metalrough (median of ${runs} runs)\n`);
console.log('Error: ΔE2000 of diffuse weight and F0 against the legacy material (reading A), mean over materials of the per-material mean, and the worst texel; "core" is a viewer without KHR_materials_specular/_ior, "full" one with them.\n');
console.log('| asset | ours s | peer s | speed-up | ours CPU s | peer CPU s | ours MB | peer MB | mem ratio | ours bytes | peer bytes | size ratio | core err ours / peer (worst) | full err ours / peer |');
console.log('|---|---|---|---|---|---|---|---|---|---|---|---|---|---|');
const grown = [];
inputs.forEach(({ name, file, texels, growthName }, i) => {
  const [a, b] = measure(file, i);
  if (texels) grown.push({ name: growthName || name, texels, a, b });
  console.log(`| ${name} | ${f3(a.seconds)} | ${f3(b.seconds)} | ${f1(b.seconds / a.seconds)}× | ${f2(a.cpu)} | ${f2(b.cpu)} | ${f1(a.mb)} | ${f1(b.mb)} | ${f2(a.mb / b.mb)} | ${a.bytes} | ${b.bytes} | ${f2(a.bytes / b.bytes)} | ` +
    `${f2(a.core.meanOfMaterialMeans)} / ${f2(b.core.meanOfMaterialMeans)} (${f1(a.core.worst)} / ${f1(b.core.worst)}) | ${f2(a.full.meanOfMaterialMeans)} / ${f2(b.full.meanOfMaterialMeans)} |`);
});
// Cost per added Mtexel (per map) between consecutive sizes: the slope of wall time against texels.
grown.sort((p, q) => p.texels - q.texels);
if (grown.length > 1) {
  console.log('\n#### Growth with texture size (Avocado maps resized, and the shared Avocado where no copy has its size): wall seconds per added Mtexel per map\n');
  console.log('| from | to | ours s/Mtexel | peer s/Mtexel |');
  console.log('|---|---|---|---|');
  for (let k = 1; k < grown.length; k++) {
    const p = grown[k - 1], q = grown[k], mtexels = (q.texels - p.texels) / 1e6;
    console.log(`| ${p.name} | ${q.name} | ${f3((q.a.seconds - p.a.seconds) / mtexels)} | ${f3((q.b.seconds - p.b.seconds) / mtexels)} |`);
  }
}

// Error against time for each solver setting, from our own report.
console.log(`\n### Error against time per solver setting (median of ${runs} runs; error from --report, reading A)\n`);
console.log('| asset | solver | s | solve ms | mean ΔE diffuse | mean ΔE F0 | worst ΔE |');
console.log('|---|---|---|---|---|---|---|');
for (const { name, file } of inputs.filter((x) => /^(Avocado|2CylinderEngine|VC|CesiumMilkTruck)$/.test(x.name)))
  for (const solver of ['fast', 'balanced', 'exact', 'reference']) {
    const out = path.join(work, 'solver', solver, path.basename(file)), report = path.join(work, `report-${solver}.json`);
    const times = [];
    for (let i = 0; i < runs; i++) times.push(timed([ours, 'convert', file, '-o', out, '-q', '--solver', solver, '--report', report]).seconds);
    const r = JSON.parse(fs.readFileSync(report)).files[0], ms = r.materials;
    const mean = (key) => ms.reduce((s, m) => s + m.deltaE2000.readingA[key].mean, 0) / ms.length;
    const worst = Math.max(...ms.map((m) => Math.max(m.deltaE2000.readingA.diffuse.max, m.deltaE2000.readingA.f0.max)));
    console.log(`| ${name} | ${solver} | ${f2(median(times))} | ${f1(r.timeMs.convert.solve)} | ${f2(mean('diffuse'))} | ${f2(mean('f0'))} | ${f1(worst)} |`);
  }
