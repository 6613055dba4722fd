#include "server/job_memory.h"

#include <algorithm>

#include "api/log.h"
#include "core/outputs/base_color_bake.h"
#include "core/prepare/envelope_plan.h"

namespace spheremap::server {

size_t estimated_job_bytes(const api::JobSpec& spec) {
  // Polygons as the fan triangulation the engine maps: a face of n corners is n - 2.
  const size_t triangles = spec.input.indices.size() - 2 * spec.input.face_count();
  const auto wants = [&](const char* output) {
    return std::find(spec.outputs.begin(), spec.outputs.end(), output) != spec.outputs.end();
  };
  size_t bytes = (16u << 20) + 400 * triangles;
  // Each part is mapped and written on its own, at about 17 KB a part whatever its size
  // (20,000 separate tetrahedra, or doubled quads: 355 MB where 400 bytes a triangle say 32).
  const size_t parts = spec.prepared.parts.size();
  bytes += 20000 * parts;
  // A wrapped whole: its original held beside, with trees for the distance and the bake.
  if (const auto& original = spec.prepared.original)
    bytes += 200 * (original->mesh.indices.size() - 2 * original->mesh.face_count());
  // Envelopes left to the worker (PreparedMesh::pending): the largest grid at its peak, the
  // input kept beside as the original (as above), and the envelope's own map (at most
  // 200,000 faces, envelope.h).
  if (const PendingEnvelopes& pending = spec.prepared.pending; pending.any()) {
    const size_t envelope_faces = pending.envelope.target_faces
                                      ? pending.envelope.target_faces
                                      : std::clamp<size_t>(triangles, 20000, 200000);
    bytes += envelope_peak_bytes(pending.grid_voxels) + 200 * triangles + 400 * envelope_faces;
  }
  // The input's images, held once each, and written once into each output that keeps them.
  size_t image_bytes = 0;
  // A wrapped whole keeps its input's look beside it (PreparedMesh::original), baked from.
  const GltfAppearance& look = spec.prepared.original ? spec.prepared.original->look : spec.look;
  for (const std::string& image : look.image_data) image_bytes += image.size();
  bytes += 2 * image_bytes;
  if (wants("remesh")) {
    const size_t side = static_cast<size_t>(std::max(spec.remesh_resolution, 1));
    // Several parts' grids hold up to 4 grids' samples together (part_grids.h): 500 parts
    // at 1024 peaked 1.5x one part's remesh (1,042 MB against 702).
    bytes += (96u << 20) + kRemeshBytesPerSample * side * side * (parts > 1 ? 2 : 1);
    // The colour bake holds each distinct base-colour image decoded, 4 bytes a pixel.
    bytes += 4 * base_color_pixels(look);
  }
  if (wants("uv")) bytes += 100 * triangles;
  if (wants("morph")) bytes += 100 * triangles;
  return bytes;
}

std::optional<MemoryBudget::Charge> charge_job(MemoryBudget& budget, api::Job& job) {
  size_t bytes;
  {
    std::lock_guard lock(job.mutex);
    bytes = job.spec ? estimated_job_bytes(*job.spec) : 0;
  }
  bool told = false;
  auto charge = budget.acquire(bytes, [&] {
    if (!told) {
      told = true;
      {
        std::lock_guard lock(job.mutex);
        job.progress.stage = "waiting_for_memory";
      }
      api::log_event({{"event", "memory_wait"},
                      {"job", job.id},
                      {"estimate_bytes", bytes},
                      {"in_use_bytes", budget.in_use()},
                      {"budget_bytes", budget.total()}});
    }
    return job.cancel.load();
  });
  if (told) {
    std::lock_guard lock(job.mutex);
    job.progress.stage = "starting";
  }
  return charge;
}

}  // namespace spheremap::server
