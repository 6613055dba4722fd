// A job's expected peak memory, charged against the node's MemoryBudget before it runs.
//
// Fitted to peak resident memory of `spheremap map` / `remesh` (GNU time, 2 threads,
// 2026-11-23; BENCHMARKS.md "Memory per job"): map 11.6 MB at 5,856 triangles (spot),
// 40 MB at 96,966 (horse), 100 MB at 268,686 (igea), 427 MB at 1,310,720 (generated
// fingers): about 8 MB + 320 bytes per triangle. The remesh adds 92 MB (horse) at
// resolution 256 and 415 MB (horse) / 372 MB (igea) at 1024: about 80 MB + 330 bytes
// per resolution squared. uv and morph keep a few more copies of the vertices. A part
// adds about 17 KB whatever its size (its own map and file; 2026-11-29), and several
// parts' remesh grids share up to 4 grids' samples (500 parts at 1024: 1.5x one grid).
// An envelope the intake left to the worker adds its grid (16 bytes a voxel at the
// peak, envelope_plan.h) and the original kept beside the envelope.
// The figures here round those up (the estimate should rather wait than overcommit).
#pragma once

#include <cstddef>
#include <optional>

#include "api/job.h"
#include "server/memory_budget.h"

namespace spheremap::server {

// A remesh's bytes per sample of its grid, over a fixed 96 MB. Measured 2026-12-07 (peak
// RSS of `spheremap remesh --resolution 1024`, 2 threads): horse 646 MB, igea 672 MB,
// Voron z_drive_main_a_x2 (47K triangles, turned frames tried) 739 MB; with the map's own
// estimate about 560-600 bytes per sample. 400 was fitted before the Hausdorff distance
// over every point (2026-12-07) and the turned frames' second distance: horse had grown
// from 455 to 646 MB.
inline constexpr size_t kRemeshBytesPerSample = 700;

size_t estimated_job_bytes(const api::JobSpec& spec);

// Charges `job` its estimate against `budget`, waiting while it does not fit (the job's
// progress stage is then "waiting_for_memory", and the wait is logged). nullopt when the
// job is cancelled meanwhile; the caller runs it anyway, and it ends as cancelled.
std::optional<MemoryBudget::Charge> charge_job(MemoryBudget& budget, api::Job& job);

}  // namespace spheremap::server
