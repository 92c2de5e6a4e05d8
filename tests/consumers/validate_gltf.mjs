// The Khronos glTF validator (npm gltf-validator) on lumis's exports:
//   node validate_gltf.mjs FILE.glb|FILE.gltf ...
// Each file must have no error and no warning; the validator's infos are printed.  A .glb
// must be read as the binary container (the validator names the container it saw).
// Exit 0 pass, 1 fail.
import validator from 'gltf-validator';
import { readFileSync } from 'node:fs';
import path from 'node:path';

let failed = 0;
for (const file of process.argv.slice(2)) {
  const bytes = new Uint8Array(readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 100,
    externalResourceFunction: () => Promise.reject(new Error('lumis files name no resource')),
  });
  const { numErrors, numWarnings, numInfos, messages } = report.issues;
  const binary = file.toLowerCase().endsWith('.glb');
  const mime = report.mimeType;
  const wantMime = binary ? 'model/gltf-binary' : 'model/gltf+json';
  console.log(`${file}: ${mime}, validator ${report.validatorVersion}: ${numErrors} errors, ` +
    `${numWarnings} warnings, ${numInfos} infos; ${report.info ? report.info.extensionsUsed : ''}`);
  for (const m of messages)
    console.log(`  ${['error', 'warning', 'info', 'hint'][m.severity]} ${m.code} at ${m.pointer || ''}: ${m.message}`);
  if (numErrors || numWarnings || mime !== wantMime) {
    console.log(`FAIL: ${file}${mime !== wantMime ? ` read as ${mime}, want ${wantMime}` : ''}`);
    failed++;
  }
}
console.log(failed ? 'FAIL' : 'PASS');
process.exit(failed ? 1 : 0);
