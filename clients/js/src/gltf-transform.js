// A gltf-transform step that replaces a document's scene by what spheremap makes of it:
//
//   import { spheremap } from 'spheremap-client/gltf-transform';
//   await document.transform(spheremap({ endpoint, outputs: ['remesh'] }));
//
// The document is written as one GLB, mapped by the service (the whole default scene, as
// one closed surface), and each output asked for (sphere, remesh, uv, morph) comes back as
// a node of the default scene, named after it; the old scene content is pruned. The job's
// metrics are in the scene's extras.spheremap. Needs @gltf-transform/core and
// @gltf-transform/functions (peer dependencies).
import { WebIO } from '@gltf-transform/core';
import { mergeDocuments, prune, unpartition } from '@gltf-transform/functions';

import { SpheremapClient } from './index.js';

const FILES = { sphere: 'sphere.glb', remesh: 'remesh.glb', uv: 'uv.glb', morph: 'morph.glb' };

/**
 * @param {object} options  endpoint (or client), outputs (default ['sphere']), io (a
 *   gltf-transform IO with the extensions your documents use, e.g. Draco), onProgress,
 *   and any job option (quality, largest_component, mesh, ...).
 */
export function spheremap({ endpoint, client, io, outputs = ['sphere'], onProgress, ...jobOptions } = {}) {
  for (const output of outputs)
    if (!FILES[output]) throw new TypeError(`spheremap: unknown output '${output}' (sphere, remesh, uv, morph)`);
  const service = client ?? new SpheremapClient({ endpoint });
  return async function spheremapTransform(document) {
    const files = io ?? new WebIO();
    const glb = await files.writeBinary(document);
    const wanted = ['sphere', ...outputs.filter((o) => o !== 'sphere')];
    const { job, artifacts } = await service.map(glb, { ...jobOptions, outputs: wanted }, { onProgress });

    const root = document.getRoot();
    const scene = root.getDefaultScene() ?? root.listScenes()[0] ?? document.createScene('Scene');
    root.setDefaultScene(scene);
    for (const child of scene.listChildren()) scene.removeChild(child);
    for (const output of outputs) {
      const result = await files.readBinary(artifacts[FILES[output]]);
      const merged = mergeDocuments(document, result);
      for (const source of result.getRoot().listScenes()) {
        const copy = merged.get(source);
        const holder = document.createNode(output);
        for (const child of copy.listChildren()) holder.addChild(child);
        scene.addChild(holder);
        copy.dispose();
      }
    }
    scene.setExtras({ ...scene.getExtras(), spheremap: { job: job.id, metrics: job.metrics } });
    await document.transform(prune(), unpartition());
  };
}
