// Validates GLB files with the Khronos glTF validator and decodes them (Draco too) with
// gltf-transform; prints one line per file and exits 1 if any has an error or does not
// decode. Usage: node validate.mjs FILE.glb ...
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';
import { NodeIO } from '@gltf-transform/core';
import { ALL_EXTENSIONS } from '@gltf-transform/extensions';
import draco3d from 'draco3dgltf';

const io = new NodeIO()
  .registerExtensions(ALL_EXTENSIONS)
  .registerDependencies({ 'draco3d.decoder': await draco3d.createDecoderModule() });

let failed = false;
for (const path of process.argv.slice(2)) {
  const report = await validator.validateBytes(new Uint8Array(await readFile(path)), {
    externalResourceFunction: () => Promise.reject(new Error('no external resources')),
  });
  const { numErrors, numWarnings } = report.issues;
  let decoded = 'decoded';
  try {
    const doc = await io.read(path);
    const prim = doc.getRoot().listMeshes()[0].listPrimitives()[0];
    const vertices = prim.getAttribute('POSITION').getCount();
    const indices = prim.getIndices().getCount();
    if (vertices === 0 || indices % 3 !== 0) throw new Error('empty or broken primitive');
    decoded = `decoded by gltf-transform: ${vertices} vertices, ${indices / 3} triangles`;
  } catch (e) {
    decoded = `DOES NOT DECODE: ${e.message}`;
    failed = true;
  }
  console.log(`${path}: ${numErrors} errors, ${numWarnings} warnings; ${decoded}`);
  if (numErrors > 0) {
    failed = true;
    for (const m of report.issues.messages.filter((m) => m.severity === 0).slice(0, 5))
      console.log(`  ${m.code}: ${m.message} (${m.pointer ?? ''})`);
  }
}
process.exit(failed ? 1 : 0);
