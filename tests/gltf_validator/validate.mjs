// Validates GLB files with the Khronos glTF validator; prints one line per file and exits
// 1 if any has an error. Usage: node validate.mjs FILE.glb ...
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';

let failed = false;
for (const path of process.argv.slice(2)) {
  const report = await validator.validateBytes(new Uint8Array(await readFile(path)), {
    externalResourceFunction: () => Promise.reject(new Error('no external resources')),
  });
  const { numErrors, numWarnings } = report.issues;
  console.log(`${path}: ${numErrors} errors, ${numWarnings} warnings`);
  if (numErrors > 0) {
    failed = true;
    for (const m of report.issues.messages.filter((m) => m.severity === 0).slice(0, 5))
      console.log(`  ${m.code}: ${m.message} (${m.pointer ?? ''})`);
  }
}
process.exit(failed ? 1 : 0);
