// The body of bench/validate.sh (see there).
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const [shared, large] = process.argv.slice(2);
const ours = process.env.GLTF_PBR, runs = Number(process.env.RUNS || 3);
const peerScript = path.join(path.dirname(fileURLToPath(import.meta.url)), '..', 'tests', 'peer', 'validate.mjs');
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'gltf-pbr-bench-validate-'));
process.on('exit', () => fs.rmSync(work, { recursive: true, force: true }));

function timed(argv, cwd) {
  const start = process.hrtime.bigint();
  const r = spawnSync('/usr/bin/time', ['-f', '%M', ...argv], { encoding: 'utf8', cwd, maxBuffer: 1 << 28 });
  const seconds = Number(process.hrtime.bigint() - start) / 1e9;
  if (r.status !== 0 && r.status !== 1) throw new Error(`${argv.join(' ')} failed (${r.status}):\n${r.stderr.slice(-2000)}`);
  return { seconds, mb: Number(r.stderr.trim().split('\n').pop()) / 1024 };
}
const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
function measure(argv, cwd) {
  const samples = [];
  for (let i = 0; i < runs; i++) samples.push(timed(argv, cwd));
  return { seconds: median(samples.map((s) => s.seconds)), mb: median(samples.map((s) => s.mb)) };
}
function walk(dir) {
  return fs.readdirSync(dir, { withFileTypes: true }).flatMap((e) =>
    e.isDirectory() ? walk(path.join(dir, e.name)) : /\.(gltf|glb)$/.test(e.name) ? [path.join(dir, e.name)] : []);
}

const f3 = (x) => x.toFixed(3), f1 = (x) => x.toFixed(1), f2 = (x) => x.toFixed(2);
if (process.env.ONLY !== 'million') {
  const suiteDir = path.join(shared, 'validator-suite');
  const suite = JSON.parse(fs.readFileSync(path.join(suiteDir, 'manifest.json'))).cases.map((c) => c.input);
  const workloads = [
    { name: `validator suite (${suite.length} files, one process)`, files: suite, cwd: suiteDir },
    { name: `shared assets (${walk(path.join(shared, 'assets')).length} files)`, files: walk(path.join(shared, 'assets')).sort(), cwd: undefined },
    { name: 'grid 1M vertices / 2M triangles (GLB)', files: [path.join(large, 'grid-1M.glb')] },
    { name: 'grid 4M vertices / 8M triangles (GLB)', files: [path.join(large, 'grid-4M.glb')] },
  ];

  console.log(`### gltf-pbr validate --only structure vs gltf-validator ${process.env.GLTF_VALIDATOR_VERSION} (npm), median of ${runs} runs\n`);
  console.log('Both validate every file with its external resources in one process and print the reports; ours once on one thread (-j 1) and once on all cores.\n');
  console.log('| workload | ours -j1 s | ours -jN s | peer s | speed-up -j1 / -jN | ours MB | peer MB | mem ratio |');
  console.log('|---|---|---|---|---|---|---|---|');
  for (const w of workloads) {
    // Reports to stdout, as the peer prints its own (a report folder would refuse the suite's
    // same-named files in different folders).
    const base = [ours, 'validate', '--only', 'structure', '-f', 'json', '-q', ...w.files];
    const one = measure([...base.slice(0, 2), '-j', '1', ...base.slice(2)], w.cwd);
    const all = measure(base, w.cwd);
    const peer = measure(['node', '--max-old-space-size=16384', peerScript, ...w.files], w.cwd);
    console.log(`| ${w.name} | ${f3(one.seconds)} | ${f3(all.seconds)} | ${f3(peer.seconds)} | ${f1(peer.seconds / one.seconds)}× / ${f1(peer.seconds / all.seconds)}× | ${f1(one.mb)} | ${f1(peer.mb)} | ${f2(one.mb / peer.mb)} |`);
  }

  // Every step (structure, materials, textures, meshes) where the peer checks structure only: what a
  // user of `gltf-pbr validate` without --only waits for. Runs alternate between ours and the peer.
  console.log(`\n### gltf-pbr validate (all steps) vs gltf-validator ${process.env.GLTF_VALIDATOR_VERSION} (structure only), median of ${runs} runs\n`);
  console.log('| input | ours s | peer s | ours / peer | ours MB | peer MB |');
  console.log('|---|---|---|---|---|---|');
  for (const [name, file] of [
    ['Avocado (two 2K maps, 5 images)', path.join(shared, 'assets', 'Avocado', 'specgloss', 'Avocado.gltf')],
    ['grid 1M vertices / 2M triangles (GLB)', path.join(large, 'grid-1M.glb')],
  ]) {
    const ourRuns = [], peerRuns = [];
    for (let i = 0; i < runs; i++) {
      ourRuns.push(timed([ours, 'validate', '-f', 'json', '-o', path.join(work, 'all'), '-q', file]));
      peerRuns.push(timed(['node', '--max-old-space-size=16384', peerScript, file]));
    }
    const a = { seconds: median(ourRuns.map((s) => s.seconds)), mb: median(ourRuns.map((s) => s.mb)) };
    const b = { seconds: median(peerRuns.map((s) => s.seconds)), mb: median(peerRuns.map((s) => s.mb)) };
    console.log(`| ${name} | ${f3(a.seconds)} | ${f3(b.seconds)} | ${f2(a.seconds / b.seconds)} | ${f1(a.mb)} | ${f1(b.mb)} |`);
  }

}

// A million issues in one file: ours lists the first 1,000 distinct messages of each code and counts
// the rest (the default), or lists every one (config max-issues-per-code: 0), as the peer does.
console.log(`\n### One file with a million issues (ACCESSOR_VECTOR3_NON_UNIT per vertex), median of ${runs} runs\n`);
console.log('Reports written as JSON; runs alternate between the three.\n');
console.log('| run | s | MB | messages listed | issues counted |');
console.log('|---|---|---|---|---|');
{
  const million = path.join(large, 'million-issues.gltf'), all = path.join(work, 'all.yaml');
  fs.writeFileSync(all, 'max-issues-per-code: 0\n');
  const variants = [
    ['ours (default)', (out) => [ours, 'validate', '--only', 'structure', '-f', 'json', '-o', out, million]],
    ['ours, max-issues-per-code: 0', (out) => [ours, 'validate', '--only', 'structure', '-f', 'json', '-o', out, '--config', all, million]],
    ['peer (maxIssues 0)', null],
  ];
  const samples = variants.map(() => []);
  const listed = variants.map(() => '');
  for (let i = 0; i < runs; i++)
    variants.forEach(([, argv], v) => {
      if (argv) {
        const out = path.join(work, `million-${v}`);
        samples[v].push(timed(argv(out)));
        const report = JSON.parse(fs.readFileSync(path.join(out, 'million-issues.gltf.report.json')));
        listed[v] = `${report.issues.messages.length} | ${report.issues.numErrors}`;
      } else {
        samples[v].push(timed(['node', '--max-old-space-size=16384', peerScript, million]));
        if (i === 0) {  // its counts (it lists every issue it counts), read once
          const counts = JSON.parse(spawnSync('node', [peerScript, million], { encoding: 'utf8', maxBuffer: 1 << 28 }).stdout);
          const c = Object.values(counts)[0];
          listed[v] = `${c.numErrors} | ${c.numErrors}`;
        }
      }
    });
  variants.forEach(([name], v) => {
    const m = { seconds: median(samples[v].map((s) => s.seconds)), mb: median(samples[v].map((s) => s.mb)) };
    console.log(`| ${name} | ${f3(m.seconds)} | ${f1(m.mb)} | ${listed[v]} |`);
  });
}
