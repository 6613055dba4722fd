// Types of spheremap-client; the wire types come from api/openapi.yaml (src/openapi.d.ts,
// made by openapi-typescript: `npm run types`).
import type { components } from './openapi.js';

export type Job = components['schemas']['Job'];
export type JobOptions = components['schemas']['JobOptions'];
export type Problem = components['schemas']['Problem'];
export type Progress = NonNullable<Job['progress']> & { status?: Job['status'] };
export type ArtifactName =
  | 'sphere.glb' | 'metrics.json' | 'remesh.glb' | 'geometry_image.png' | 'uv.glb' | 'morph.glb';
export type Bytes = Uint8Array | ArrayBuffer | Blob;

export declare class SpheremapError extends Error {
  status: number;
  problem: Problem;
  type: string;
  /** The problem's one line for a person, with the counts (same as problem.detail). */
  detail?: string;
  fix?: { option: string; value: unknown; effect: string };
  /** The response's Retry-After header, when it had one (503, 429). */
  retryAfter?: string;
}

export declare class SpheremapClient {
  constructor(options: { endpoint: string; apiKey?: string; fetch?: typeof fetch;
                         headers?: Record<string, string> });
  endpoint: string;
  submit(mesh: Bytes, options?: JobOptions,
         extra?: { resources?: Record<string, Bytes>; name?: string; idempotencyKey?: string;
                   retries?: number }): Promise<Job>;
  job(id: string): Promise<Job>;
  events(id: string, options?: { signal?: AbortSignal }):
    AsyncGenerator<{ event: 'progress'; data: Progress } | { event: 'status'; data: Job }>;
  wait(id: string, options?: { onProgress?: (progress: Progress) => void; signal?: AbortSignal }): Promise<Job>;
  download(id: string, name: ArtifactName): Promise<Uint8Array>;
  cancel(id: string): Promise<void>;
  map(mesh: Bytes, options?: JobOptions,
      extra?: { resources?: Record<string, Bytes>; name?: string; onProgress?: (progress: Progress) => void;
                signal?: AbortSignal; idempotencyKey?: string; retries?: number }): Promise<{ job: Job; artifacts: Partial<Record<ArtifactName, Uint8Array>> }>;
}
