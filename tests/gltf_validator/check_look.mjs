// Checks that outputs kept their input's look. Arguments in fives: INPUT SPHERE SPHERE_GLTF
// MORPH REMESH. The sphere files and the morph must have the input's materials, textures
// and images (same bytes) and TEXCOORD_0 wherever the input's primitives have it; the
// remesh must have a base colour texture when the input has any material. Exit 1 on a miss.
import { NodeIO } from '@gltf-transform/core';
import { ALL_EXTENSIONS } from '@gltf-transform/extensions';
import draco3d from 'draco3dgltf';

const io = new NodeIO()
  .registerExtensions(ALL_EXTENSIONS)
  .registerDependencies({ 'draco3d.decoder': await draco3d.createDecoderModule() });

function look(doc) {
  const root = doc.getRoot();
  const prims = root.listMeshes().flatMap((m) => m.listPrimitives());
  return {
    materials: root.listMaterials().length,
    textures: root.listTextures().map((t) => Buffer.from(t.getImage() ?? []).toString('base64')),
    texcoords: prims.filter((p) => p.getAttribute('TEXCOORD_0')).length,
    primitives: prims.length,
    baseColor: root.listMaterials().some((m) => m.getBaseColorTexture()),
  };
}

let failed = false;
const args = process.argv.slice(2);
for (let i = 0; i < args.length; i += 5) {
  const [input, sphere, sphereText, morph, remesh] = args.slice(i, i + 5);
  const want = look(await io.read(input));
  const problems = [];
  for (const path of [sphere, sphereText, morph]) {
    const got = look(await io.read(path));
    if (got.materials !== want.materials) problems.push(`${path}: ${got.materials} materials, input ${want.materials}`);
    if (got.textures.join() !== want.textures.join()) problems.push(`${path}: textures differ from the input's`);
    if (got.texcoords !== want.texcoords) problems.push(`${path}: ${got.texcoords} primitives with TEXCOORD_0, input ${want.texcoords}`);
  }
  const r = look(await io.read(remesh));
  if (want.materials > 0 && !r.baseColor) problems.push(`${remesh}: no base colour texture`);
  console.log(`${input}: ${want.materials} material(s), ${want.textures.length} texture(s): ${problems.length ? 'LOST' : 'kept'}`);
  for (const p of problems) console.log(`  ${p}`);
  failed ||= problems.length > 0;
}
process.exit(failed ? 1 : 0);
