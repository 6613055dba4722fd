import type { PlatformIO, Transform } from '@gltf-transform/core';
import type { JobOptions, Progress, SpheremapClient } from './index.js';

export declare function spheremap(options: JobOptions & {
  endpoint?: string;
  client?: SpheremapClient;
  io?: PlatformIO;
  outputs?: Array<'sphere' | 'remesh' | 'uv' | 'morph'>;
  onProgress?: (progress: Progress) => void;
}): Transform;
