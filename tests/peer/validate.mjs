// Runs the Khronos glTF-Validator (npm `gltf-validator`, the reference
// implementation) over .gltf/.glb files and prints one JSON object of issue
// counts per file, so tests and benchmarks can compare our validator and our
// converter's outputs against it:
//
//   GLTF_PBR_NODE_MODULES=/path/to/node_modules node validate.mjs a.gltf b.glb
//   => {"a.gltf": {"numErrors":0, "numWarnings":0, "numInfos":0, "numHints":0,
//                  "codes": {"Information:ACCESSOR_INDEX_TRIANGLE_DEGENERATE": 25}}, ...}
//
// Exit 0 when every file was validated, whatever the assets' issues are; exit 2
// when the script itself cannot run (usage, missing module, unreadable input).
// Works on node 18 and 20 (ES module, no top-level features beyond node 14).
import { readFile } from 'node:fs/promises';
import { createRequire } from 'node:module';
import path from 'node:path';

function fail(message) {
  process.stderr.write(`validate.mjs: ${message}\n`);
  process.exit(2);
}

const files = process.argv.slice(2);
if (files.length === 0) fail('usage: GLTF_PBR_NODE_MODULES=DIR node validate.mjs FILE.gltf|FILE.glb...');

// The validator lives in a cache folder (bench/peers.sh), not in the repo, so
// we load it by absolute path instead of relying on node's module search.
const nodeModules = process.env.GLTF_PBR_NODE_MODULES;
if (!nodeModules) fail('GLTF_PBR_NODE_MODULES is not set; run: eval "$(bench/peers.sh)"');
let validator;
try {
  validator = createRequire(import.meta.url)(path.resolve(nodeModules, 'gltf-validator'));
} catch (error) {
  fail(`cannot load gltf-validator from ${nodeModules}: ${error.message.split('\n')[0]}`);
}

// The report's "severity" is numeric; name it as the validator's own text output does.
const severityNames = ['Error', 'Warning', 'Information', 'Hint'];

async function validate(file) {
  let bytes;
  try {
    bytes = await readFile(file);
  } catch (error) {
    fail(`cannot read ${file}: ${error.message}`);
  }
  const folder = path.dirname(path.resolve(file));
  const report = await validator.validateBytes(new Uint8Array(bytes.buffer, bytes.byteOffset, bytes.byteLength), {
    uri: path.basename(file),
    // Decide the format by extension, as the validator's CLI does, so a corrupt
    // file gets a report (e.g. INVALID_JSON) instead of a "could not detect" rejection.
    format: path.extname(file).toLowerCase() === '.glb' ? 'glb' : 'gltf',
    maxIssues: 0, // unlimited: the counts must be complete, not capped at the default 100
    writeTimestamp: false,
    // Buffers and images are resolved relative to the asset, as a viewer would.
    // A missing file is the asset's problem: rejecting makes the validator report
    // it as an issue (IO_ERROR) rather than silently skipping the resource.
    externalResourceFunction: (uri) =>
      readFile(path.resolve(folder, decodeURIComponent(uri))).then(
        (data) => new Uint8Array(data.buffer, data.byteOffset, data.byteLength),
        (error) => Promise.reject(error.message),
      ),
  });
  const codes = {};
  for (const message of report.issues.messages) {
    const key = `${severityNames[message.severity] ?? message.severity}:${message.code}`;
    codes[key] = (codes[key] ?? 0) + 1;
  }
  const { numErrors, numWarnings, numInfos, numHints } = report.issues;
  return { numErrors, numWarnings, numInfos, numHints, codes };
}

const results = {};
for (const file of files) {
  try {
    results[file] = await validate(file);
  } catch (error) {
    // validateBytes rejects only for invalid options; that is our bug, not the asset's.
    fail(`validator failed on ${file}: ${error}`);
  }
}
process.stdout.write(JSON.stringify(results) + '\n');
