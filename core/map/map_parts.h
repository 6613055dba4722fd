// Mapping an asset of several parts (prepare "parts"): each connected component, closed
// genus 0 on its own, gets a certified sphere of its own. The parts are mapped one after
// the other under one time limit; the result describes them together (MappedMesh::parts).
#pragma once

#include "core/map/pipeline.h"

namespace spheremap {

// Precondition: remaining_failures(prepared) is empty and prepared.welded.mesh has several
// components. A part the time limit leaves unmapped gets its vertices' directions from its
// centroid (not a map) and the whole stops at kTimeLimit; a cancelled part cancels the
// whole (map.sphere empty).
MappedMesh map_parts(PreparedMesh prepared, const MapOptions& options,
                     const MapControl& control = {});

// Where outputs draw part `part` of `mapped`: its unit-sphere position `on_sphere` moved to
// center + radius * on_sphere.
inline Vec3 placed(const MappedPart& part, const Vec3& on_sphere) {
  return part.center + on_sphere * part.radius;
}

}  // namespace spheremap
