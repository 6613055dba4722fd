// Decodes every TRIANGLES primitive of a GLB (Draco or not) into one OBJ, positions as
// stored (node transforms ignored: topology and the spherical map do not depend on them).
// Usage: node draco-to-obj.mjs IN.glb OUT.obj
import { NodeIO } from '@gltf-transform/core';
import { ALL_EXTENSIONS } from '@gltf-transform/extensions';
import draco3d from 'draco3dgltf';
import { createWriteStream } from 'node:fs';

const [input, output] = process.argv.slice(2);
const io = new NodeIO()
  .registerExtensions(ALL_EXTENSIONS)
  .registerDependencies({ 'draco3d.decoder': await draco3d.createDecoderModule() });
const document = await io.read(input);
const out = createWriteStream(output);
let base = 1;
for (const mesh of document.getRoot().listMeshes()) {
  for (const prim of mesh.listPrimitives()) {
    if (prim.getMode() !== 4) continue;
    const pos = prim.getAttribute('POSITION');
    const count = pos.getCount();
    const p = [0, 0, 0];
    let chunk = '';
    for (let i = 0; i < count; i++) {
      pos.getElement(i, p);
      chunk += `v ${p[0]} ${p[1]} ${p[2]}\n`;
      if (chunk.length > 1 << 20) { out.write(chunk); chunk = ''; }
    }
    const idx = prim.getIndices();
    const n = idx ? idx.getCount() : count;
    for (let i = 0; i < n; i += 3) {
      const a = idx ? idx.getScalar(i) : i, b = idx ? idx.getScalar(i + 1) : i + 1,
            c = idx ? idx.getScalar(i + 2) : i + 2;
      chunk += `f ${a + base} ${b + base} ${c + base}\n`;
      if (chunk.length > 1 << 20) { out.write(chunk); chunk = ''; }
    }
    out.write(chunk);
    base += count;
  }
}
out.end();
