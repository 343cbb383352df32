// Validates glTF files with the Khronos glTF validator (npm gltf-validator).
//
// usage: node tests/content/validate.mjs FILE.gltf...
// Prints one summary line per file and every issue; exits 1 when any file has
// an error or a warning, 2 when the validator package is missing.
// The package is looked up in $VG_NODE_MODULES, then .cache/node/node_modules
// (where tools/dev installs it: npm install --prefix .cache/node gltf-validator).
import { readFile } from 'node:fs/promises';
import { existsSync } from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';

const moduleDirs = [process.env.VG_NODE_MODULES, path.resolve('.cache/node/node_modules')].filter(Boolean);
const found = moduleDirs.find((d) => existsSync(path.join(d, 'gltf-validator', 'package.json')));
if (!found) {
  console.error(`validate.mjs: the npm package gltf-validator is missing (looked in ${moduleDirs.join(', ')}).\n` +
                'Install it with: npm install --prefix .cache/node gltf-validator   (tools/dev does this)');
  process.exit(2);
}
const require = createRequire(path.join(found, 'index.js'));
const validator = require('gltf-validator');

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error('usage: node tests/content/validate.mjs FILE.gltf...');
  process.exit(2);
}

let failed = 0;
for (const file of files) {
  const dir = path.dirname(file);
  let report;
  try {
    report = await validator.validateBytes(new Uint8Array(await readFile(file)), {
      uri: path.basename(file),
      maxIssues: 0,
      writeTimestamp: false,
      externalResourceFunction: async (uri) => new Uint8Array(await readFile(path.resolve(dir, decodeURIComponent(uri)))),
    });
  } catch (e) {
    console.error(`${file}: validator could not read the file: ${e}`);
    failed++;
    continue;
  }
  const { numErrors, numWarnings, numInfos, numHints, messages } = report.issues;
  const info = report.info || {};
  console.log(`${file}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ${numHints} hints` +
              ` (${info.totalTriangleCount ?? '?'} triangles, ${info.animationCount ?? 0} animations)`);
  const severity = ['error', 'warning', 'info', 'hint'];
  for (const m of messages)
    console.log(`  ${severity[m.severity] ?? m.severity}: ${m.code} at ${m.pointer ?? ''}: ${m.message}`);
  if (numErrors > 0 || numWarnings > 0)
    failed++;
}
console.log(failed ? `${failed} of ${files.length} files failed validation` : `all ${files.length} files valid`);
process.exit(failed ? 1 : 0);
