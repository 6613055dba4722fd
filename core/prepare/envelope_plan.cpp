#include "core/prepare/envelope_plan.h"

#include <algorithm>
#include <cmath>

#include "core/mesh/input_error.h"
#include "core/mesh/triangle_tree.h"

namespace spheremap {

EnvelopePlan plan_envelope(const PolygonMesh& input, const EnvelopeOptions& options) {
  EnvelopePlan plan;
  const FanTriangulation fan = fan_triangulate(input);
  AxisBox box;
  for (const Triangle& t : fan.triangles) {
    const Vec3 &a = input.positions[t[0]], &b = input.positions[t[1]], &c = input.positions[t[2]];
    if (!is_finite(a) || !is_finite(b) || !is_finite(c)) continue;
    plan.triangles.push_back(t);
    box.add(a), box.add(b), box.add(c);
  }
  if (plan.triangles.empty()) throw InputError("envelope_empty", "there is no triangle to wrap");
  plan.diagonal = norm(box.hi - box.lo);
  // A resolution under 1 is a voxel wider than the input: a tiny part of an asset, grown by
  // the asset's offset (part_envelope_options).
  if (!(plan.diagonal > 0) || !std::isfinite(plan.diagonal) || !(options.resolution > 0) ||
      !std::isfinite(options.resolution))
    throw InputError("envelope_size",
                     "the envelope needs an input of some extent and a positive resolution");
  plan.h = plan.diagonal / options.resolution;
  plan.d = options.offset > 0            ? options.offset
           : options.offset_fraction > 0 ? options.offset_fraction * plan.diagonal
                                         : options.offset_voxels * plan.h;
  plan.fit_distance =
      options.fit_voxels > 0 ? std::min(plan.d, options.fit_voxels * plan.h) : plan.d;
  plan.grid = layout_grid(box.lo, box.hi, plan.h, plan.d, options.max_voxels);
  return plan;
}

}  // namespace spheremap
