// spheremap-client: the spheremap service from JavaScript (Node 18+, browsers, workers).
// No dependencies: fetch, FormData and Blob are the platform's own.

/** A refusal or failure from the service, as its problem+json says it (RFC 9457). */
export class SpheremapError extends Error {
  constructor(problem, status) {
    super(`${problem.title ?? 'spheremap error'}: ${problem.detail ?? status}`);
    this.name = 'SpheremapError';
    this.status = status;
    this.problem = problem;
    this.type = problem.type;
    this.detail = problem.detail;  // the one line for a person, with the counts
    this.fix = problem.fix;  // the job option that gets past it, when there is one
  }
}

const TERMINAL = new Set(['succeeded', 'failed', 'cancelled']);

function asBlob(data, type) {
  if (typeof Blob !== 'undefined' && data instanceof Blob) return data;
  return new Blob([data], { type });
}

// The type the service reads a file as, from its name (it also sniffs the bytes).
const TYPES = { glb: 'model/gltf-binary', gltf: 'model/gltf+json', obj: 'model/obj', stl: 'model/stl',
  ply: 'application/ply', off: 'model/off' };
function contentType(name, glb) {
  const extension = /\.([a-z0-9]+)$/i.exec(name)?.[1]?.toLowerCase();
  return TYPES[extension] ?? (glb ? TYPES.glb : TYPES.gltf);
}

function isGlb(bytes) {
  const view = bytes instanceof ArrayBuffer ? new Uint8Array(bytes) : bytes;
  return view?.length >= 4 && view[0] === 0x67 && view[1] === 0x6c && view[2] === 0x54 && view[3] === 0x46;
}

export class SpheremapClient {
  /**
   * @param {{endpoint: string, apiKey?: string, fetch?: typeof fetch, headers?: Record<string,string>}} options
   *   apiKey: for a service started with --api-keys (sent as Authorization: Bearer).
   */
  constructor({ endpoint, apiKey, fetch: fetchImpl = globalThis.fetch, headers = {} }) {
    if (!endpoint) throw new TypeError('SpheremapClient needs an endpoint, e.g. http://127.0.0.1:8080');
    this.endpoint = endpoint.replace(/\/+$/, '');
    this.fetch = fetchImpl;
    this.headers = apiKey ? { ...headers, Authorization: `Bearer ${apiKey}` } : headers;
  }

  async #request(path, init = {}) {
    const response = await this.fetch(this.endpoint + path, {
      ...init, headers: { ...this.headers, ...(init.headers ?? {}) } });
    if (response.ok) return response;
    let problem;
    try { problem = await response.json(); } catch { problem = { title: response.statusText }; }
    const error = new SpheremapError(problem, response.status);
    error.retryAfter = response.headers.get('Retry-After') ?? undefined;
    throw error;
  }

  /**
   * Submits a mesh: a GLB or .gltf (bytes or Blob), or an OBJ, STL, PLY or OFF file named by
   * `name` (its extension gives the type). A .gltf's external files go in `resources`, by
   * the URI the .gltf names them with. Returns the job as queued.
   *
   * `idempotencyKey` (1-255 printable ASCII characters, no quote or backslash) makes the submission safe to send
   * again: the service answers a repeat of the same key with the job the first one made.
   * With a key, `retries` (default 0) resends the submission when the service answers 503
   * (busy, or Redis unsure whether the job was stored) or the connection fails, after the
   * server's Retry-After (at most 10 s) or 1 s: never twice a job.
   */
  async submit(mesh, options = {}, { resources = {}, name, idempotencyKey, retries = 0 } = {}) {
    const form = new FormData();
    const glb = !(typeof Blob !== 'undefined' && mesh instanceof Blob) && isGlb(mesh);
    const fileName = name ?? (glb ? 'mesh.glb' : 'mesh.gltf');
    form.append('mesh', asBlob(mesh, contentType(fileName, glb)), fileName);
    for (const [uri, bytes] of Object.entries(resources))
      form.append(decodeURIComponent(uri), asBlob(bytes, 'application/octet-stream'), decodeURIComponent(uri));
    form.append('options', new Blob([JSON.stringify(options)], { type: 'application/json' }));
    if (idempotencyKey === undefined) {
      const response = await this.#request('/v1/jobs', { method: 'POST', body: form });
      return response.json();
    }
    if (!/^[\x20-\x21\x23-\x5b\x5d-\x7e]{1,255}$/.test(idempotencyKey))
      throw new TypeError('idempotencyKey: 1 to 255 printable ASCII characters, no quote or backslash');
    const headers = { 'Idempotency-Key': `"${idempotencyKey}"` };  // a Structured Field string
    for (let attempt = 0; ; ++attempt) {
      try {
        const response = await this.#request('/v1/jobs', { method: 'POST', body: form, headers });
        return await response.json();
      } catch (error) {
        const retryable = error instanceof SpheremapError ? error.status === 503 : error instanceof TypeError;
        if (!retryable || attempt >= retries) throw error;
        const seconds = Math.min(10, Number(error.retryAfter) || 1);
        await new Promise((resolve) => setTimeout(resolve, seconds * 1000));
      }
    }
  }

  /** The job as GET /v1/jobs/{id} answers it. */
  async job(id) {
    return (await this.#request(`/v1/jobs/${id}`)).json();
  }

  /**
   * The job's progress as it happens: yields {event: 'progress', data} while it runs and
   * {event: 'status', data: job} last (Server-Sent Events, read with fetch so it works
   * where EventSource does not). Falls back to polling when the server has no stream free.
   */
  async *events(id, { signal } = {}) {
    let response;
    try {
      response = await this.#request(`/v1/jobs/${id}/events`, { signal, headers: { Accept: 'text/event-stream' } });
    } catch (error) {
      if (!(error instanceof SpheremapError) || error.status !== 503) throw error;
      for (;;) {  // too many streams: poll
        const job = await this.job(id);
        if (TERMINAL.has(job.status)) { yield { event: 'status', data: job }; return; }
        yield { event: 'progress', data: { ...job.progress, status: job.status } };
        await new Promise((resolve) => setTimeout(resolve, 500));
      }
    }
    const decoder = new TextDecoder();
    let buffer = '';
    for await (const chunk of response.body) {
      buffer += decoder.decode(chunk, { stream: true });
      let end;
      while ((end = buffer.indexOf('\n\n')) >= 0) {
        const block = buffer.slice(0, end);
        buffer = buffer.slice(end + 2);
        let event = 'message', data = '';
        for (const line of block.split('\n')) {
          if (line.startsWith('event: ')) event = line.slice(7);
          else if (line.startsWith('data: ')) data += line.slice(6);
        }
        if (!data) continue;  // a keep-alive comment
        yield { event, data: JSON.parse(data) };
        if (event === 'status') return;
      }
    }
  }

  /** Waits for the job to end; `onProgress` sees every progress event. Returns the job. */
  async wait(id, { onProgress, signal } = {}) {
    for await (const { event, data } of this.events(id, { signal })) {
      if (event === 'status') return data;
      onProgress?.(data);
    }
    return this.job(id);  // the stream ended early: ask
  }

  /** An artifact's bytes (sphere.glb, metrics.json, remesh.glb, geometry_image.png, uv.glb, morph.glb). */
  async download(id, name) {
    return new Uint8Array(await (await this.#request(`/v1/jobs/${id}/artifacts/${name}`)).arrayBuffer());
  }

  /** Cancels a queued or running job (its artifacts are dropped), or deletes a finished one. */
  async cancel(id) {
    await this.#request(`/v1/jobs/${id}`, { method: 'DELETE' });
  }

  /**
   * Submit, wait, download: resolves to {job, artifacts: {name: Uint8Array}} for the
   * artifacts asked for (options.outputs, plus sphere.glb and metrics.json); throws a
   * SpheremapError when the job does not succeed. The submission carries an idempotency
   * key of its own (or `idempotencyKey`) and is resent up to `retries` (default 3) times
   * on a 503 or a failed connection, so a busy service delays it without duplicating it.
   */
  async map(mesh, options = {}, { resources, name, onProgress, signal, idempotencyKey, retries = 3 } = {}) {
    const key = idempotencyKey ?? globalThis.crypto?.randomUUID?.();
    const submitted = await this.submit(mesh, options,
      { resources, name, idempotencyKey: key, retries: key === undefined ? 0 : retries });
    const job = await this.wait(submitted.id, { onProgress, signal });
    if (job.status !== 'succeeded')
      throw new SpheremapError(job.error ?? { title: `job ${job.status}` }, job.error?.status ?? 500);
    const artifacts = {};
    for (const name of Object.keys(job.artifacts ?? {})) artifacts[name] = await this.download(job.id, name);
    return { job, artifacts };
  }
}
