// Prints the npm gltf-validator's full report (one JSON line per file) for each file given, with
// external resources read beside the file. M is the node_modules folder that holds gltf-validator
// (bench/peers.sh installs it into a cache folder).   M=... node reference_reports.mjs FILE...
import { readFile } from 'node:fs/promises';
import { createRequire } from 'node:module';
import path from 'node:path';
const require = createRequire(process.env.M + '/');
const validator = require('gltf-validator');
for (const file of process.argv.slice(2)) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: file, maxIssues: 0,
    externalResourceFunction: (uri) => readFile(path.resolve(path.dirname(file), decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
  });
  console.log(JSON.stringify(report));
}
