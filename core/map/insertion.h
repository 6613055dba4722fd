// Kernel-safe re-insertion of a collapsed vertex (ALGORITHM §B4.3, recipe step 3a).
//
// u goes to the normalized average of its ring if every star triangle (u, r_i, r_i+1) is
// valid there. Otherwise it is searched inside the kernel of the ring: from v (the
// vertex u collapsed into) along the bisector of the two star triangles at v, halving
// the step until valid, then blended toward the ring average while still valid.
#pragma once

#include <cstdint>
#include <span>

#include "core/mesh/vec3.h"

namespace spheremap {

enum class InsertionOutcome { kRingAverage, kKernelSearch, kFailed };

// Writes q[u]. Preconditions: q holds unit vectors for v and the ring; the ring is
// the oriented cycle recorded by the hierarchy and contains v.
InsertionOutcome insert_vertex(std::span<Vec3> q, uint32_t u, uint32_t v,
                               std::span<const uint32_t> ring);

// Whether every star triangle (p, r_i, r_i+1) is valid.
bool star_valid(std::span<const Vec3> q, const Vec3& p, std::span<const uint32_t> ring);

}  // namespace spheremap
