// Parts that are copies of an earlier part: an instance drawn many times (glTF nodes sharing
// a mesh, EXT_mesh_gpu_instancing), a kit piece placed again. Such a part has the earlier
// part's faces over the same local vertex order, and its positions are the earlier part's
// turned, uniformly scaled and moved. The earlier part's map turned the same way is then a
// map of the copy with the same distortion (stretch and area ratios do not change under a
// similarity of the surface and a rotation of the sphere), at the cost of a check instead
// of a map: map_parts.h tries it before mapping a part, and keeps it only when the copy's
// own certification passes (double, float32).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "core/mesh/mesh.h"

namespace spheremap {

// Equal for parts with the same face sizes and corners (local ids) and the same filled
// triangles; a hash: same_faces() decides.
uint64_t faces_hash(const PolygonMesh& mesh, std::span<const Triangle> filled);

// Equal for positions that are a similarity image of each other in the same order (up to
// rounding near a step of its quantization): the first vertices' distances from the
// centroid over the RMS of all, in steps of 1/64. Copies are looked for among parts with
// the same faces_hash and shape_hash only: by faces alone, every one of 47,000 doubled
// triangles of a shattered non-manifold mesh (vcglib's abominevole.off) was tried against
// every earlier one, a rotation fit each (quadratic: the map stopped at its time limit).
uint64_t shape_hash(std::span<const Vec3> positions);

// Whether a and b have the same vertex count, faces (corner for corner) and filled
// triangles (in the same order).
bool same_faces(const PolygonMesh& a, std::span<const Triangle> a_filled, const PolygonMesh& b,
                std::span<const Triangle> b_filled);

// A 3x3 rotation, row-major.
using Rotation = std::array<double, 9>;
Vec3 rotate(const Rotation& r, const Vec3& v);

// The proper rotation R (det +1) with to[i] - centroid(to) = s R (from[i] - centroid(from))
// for one scale s > 0 and every i, to within `tolerance` times the RMS distance of `to`
// from its centroid; nullopt when there is none (a mirror image, a different shape, a
// part of no extent). from and to have the same size.
std::optional<Rotation> rotation_onto(std::span<const Vec3> from, std::span<const Vec3> to,
                                      double tolerance);

}  // namespace spheremap
