// Prints the npm gltf-validator's full report (one JSON line per file) for each file given, with
// external resources read beside the file. M is the node_modules folder that holds gltf-validator
// (bench/peers.sh installs it into a cache folder).   M=... node reference_reports.mjs FILE... | --list LIST
import { readFile } from 'node:fs/promises';
import { createRequire } from 'node:module';
import path from 'node:path';
const require = createRequire(process.env.M + '/');
const validator = require('gltf-validator');
// --list FILE reads the paths from FILE, one per line (10,000 paths do not fit on a command line).
const args = process.argv.slice(2);
const files = args[0] === '--list' ? (await readFile(args[1], 'utf8')).split('\n').filter(Boolean) : args;
// Some inputs make the reference throw outside the promise it returned (a Dart exception from an
// asynchronous step): that file's report is refused like the rest, and the run goes on.
let refuse = null;
process.on('uncaughtException', (error) => {
  if (!refuse) throw error;
  refuse(error);
});
for (const file of files) {
  const bytes = new Uint8Array(await readFile(file));
  // The reference refuses some inputs outright (bytes that are neither JSON nor GLB): such a line
  // carries the exception's text instead of a report, and the comparison counts it as its own class.
  let report;
  try {
    report = await new Promise((resolve, reject) => {
      refuse = reject;
      validator.validateBytes(bytes, {
        uri: file, maxIssues: 0,
        // Our path policy, applied to the reference too: nothing outside the input's folder is read.
        externalResourceFunction: (uri) => {
          const folder = path.resolve(path.dirname(file));
          const target = path.resolve(folder, decodeURIComponent(uri));
          if (!target.startsWith(folder + path.sep)) return Promise.reject(new Error('outside the folder'));
          return readFile(target).then((b) => new Uint8Array(b));
        },
      }).then(resolve, reject);
    });
  } catch (error) {
    report = { uri: file, exception: String(error).split('\n')[0] };
  } finally {
    refuse = null;
  }
  console.log(JSON.stringify(report));
}
