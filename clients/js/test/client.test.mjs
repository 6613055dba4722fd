// spheremap-client against a real server: SPHEREMAP_URL (a running service),
// SPHEREMAP_MESH (a closed GLB) and SPHEREMAP_SLOW_MESH (a GLB the paper's loop never
// unfolds), set by test/run.sh.
import assert from 'node:assert/strict';
import { readFile } from 'node:fs/promises';
import { test } from 'node:test';

import { NodeIO } from '@gltf-transform/core';

import { SpheremapClient, SpheremapError } from '../src/index.js';
import { spheremap } from '../src/gltf-transform.js';

const endpoint = process.env.SPHEREMAP_URL;
const mesh = await readFile(process.env.SPHEREMAP_MESH);
const client = new SpheremapClient({ endpoint });

test('submit, follow the progress, download', async () => {
  const submitted = await client.submit(mesh, { quality: 'fast', outputs: ['sphere', 'remesh'] });
  assert.match(submitted.id, /^[0-9a-f]{32}$/);
  const seen = [];
  const job = await client.wait(submitted.id, { onProgress: (p) => seen.push(p) });
  assert.equal(job.status, 'succeeded');
  assert.ok(seen.length >= 1, 'at least one progress event');
  assert.equal(job.metrics.bijective, true);
  const sphere = await client.download(job.id, 'sphere.glb');
  assert.equal(new TextDecoder().decode(sphere.slice(0, 4)), 'glTF');
  const metrics = JSON.parse(new TextDecoder().decode(await client.download(job.id, 'metrics.json')));
  assert.equal(metrics.bijective, true);
  assert.ok(job.artifacts['remesh.glb']);
});

test('map() resolves to the job and its artifacts', async () => {
  const { job, artifacts } = await client.map(mesh, { outputs: ['morph'] });
  assert.equal(job.status, 'succeeded');
  assert.deepEqual(Object.keys(artifacts).sort(), ['metrics.json', 'morph.glb', 'sphere.glb']);
});

test('cancel stops a running job', async () => {
  const slow = await readFile(process.env.SPHEREMAP_SLOW_MESH);
  const submitted = await client.submit(slow, { method: 'paper', max_iterations: 1000000, time_limit_seconds: 60 });
  for (let i = 0; i < 100 && (await client.job(submitted.id)).status === 'queued'; ++i)
    await new Promise((r) => setTimeout(r, 50));
  await client.cancel(submitted.id);
  const job = await client.wait(submitted.id);
  assert.equal(job.status, 'cancelled');
});

test('a refusal is a SpheremapError with the problem', async () => {
  await assert.rejects(client.submit(new TextEncoder().encode('{"asset":{"version":"2.0"}}')), (error) => {
    assert.ok(error instanceof SpheremapError);
    assert.equal(error.status, 400);
    assert.equal(error.type, '/v1/problems/malformed_gltf');
    assert.match(error.message, /no meshes/);
    return true;
  });
});

test('the gltf-transform step replaces the scene by the remesh', async () => {
  const io = new NodeIO();
  const document = await io.readBinary(mesh);
  await document.transform(spheremap({ endpoint, outputs: ['remesh'], quality: 'fast', resolution: 32 }));
  const scene = document.getRoot().getDefaultScene();
  const nodes = scene.listChildren();
  assert.deepEqual(nodes.map((n) => n.getName()), ['remesh']);
  const meshes = document.getRoot().listMeshes();
  assert.equal(meshes.length, 1, 'the input mesh was pruned');
  const positions = meshes[0].listPrimitives()[0].getAttribute('POSITION');
  assert.ok(positions.getCount() > 1000, `remesh vertices: ${positions.getCount()}`);
  assert.equal(scene.getExtras().spheremap.metrics.bijective, true);
  assert.ok((await io.writeBinary(document)).byteLength > 0);
});

test('the same idempotency key gives the same job, not a second one', async () => {
  const key = `client-test-${Date.now()}-${Math.random()}`;
  const first = await client.submit(mesh, { quality: 'fast' }, { idempotencyKey: key });
  const again = await client.submit(mesh, { quality: 'fast' }, { idempotencyKey: key });
  assert.equal(again.id, first.id);
  const other = await client.submit(mesh, { quality: 'fast' }, { idempotencyKey: `${key}-other` });
  assert.notEqual(other.id, first.id);
  await assert.rejects(client.submit(mesh, {}, { idempotencyKey: '' }), TypeError);
  await assert.rejects(client.submit(mesh, {}, { idempotencyKey: 'a"b' }), TypeError);
});

test('a 503 is retried with the same key; a 400 is not retried', async () => {
  const sent = [];
  let refuse = 1;
  const flaky = new SpheremapClient({
    endpoint,
    fetch: async (url, init) => {
      if (init.method !== 'POST') return fetch(url, init);
      sent.push(init.headers['Idempotency-Key']);
      if (refuse-- > 0) {
        return new Response(JSON.stringify({ title: 'busy', status: 503 }),
          { status: 503, headers: { 'Content-Type': 'application/problem+json', 'Retry-After': '1' } });
      }
      return fetch(url, init);
    },
  });
  const key = `retry-${Date.now()}-${Math.random()}`;
  const { job } = await flaky.map(mesh, { quality: 'fast' }, { idempotencyKey: key });
  assert.equal(job.status, 'succeeded');
  assert.equal(sent.length, 2);
  assert.equal(sent[0], sent[1]);
  assert.equal(sent[0], `"${key}"`);
  assert.equal((await client.submit(mesh, {}, { idempotencyKey: key })).id, job.id);

  sent.length = 0;
  await assert.rejects(flaky.submit(new TextEncoder().encode('{"asset":{"version":"2.0"}}'), {},
    { idempotencyKey: `bad-${Date.now()}`, retries: 3 }), (error) => error.status === 400);
  assert.equal(sent.length, 1);
});

test('an OBJ is sent as model/obj by its name and maps', async () => {
  const octahedron = ['v 1 0 0', 'v -1 0 0', 'v 0 1 0', 'v 0 -1 0', 'v 0 0 1', 'v 0 0 -1',
    'f 1 3 5', 'f 3 2 5', 'f 2 4 5', 'f 4 1 5', 'f 3 1 6', 'f 2 3 6', 'f 4 2 6', 'f 1 4 6'].join('\n');
  const { job } = await client.map(new TextEncoder().encode(octahedron), { quality: 'fast' },
    { name: 'octahedron.obj' });
  assert.equal(job.metrics.bijective, true);
  assert.equal(job.input.format, 'obj');
  assert.equal(job.input.faces, 8);
});
