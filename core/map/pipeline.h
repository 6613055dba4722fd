// The full map pipeline (preparation: core/prepare), shared by the command-line
// tool and the service: weld -> validate -> map -> verify -> metrics.
#pragma once

#include <functional>
#include <string>

#include "core/map/metrics.h"
#include "core/map/spherical_map.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "core/prepare/prepare_mesh.h"

namespace spheremap {

struct MappedMesh {
  PreparedMesh prepared;
  MapResult map;
  // The same verdict on the positions rounded to float32, as glTF stores them: thin parts
  // squeezed below float32's resolution fold there although the double map is bijective.
  MapCheck float32_check;
  QualityMetrics quality;
  double prepare_seconds = 0, metrics_seconds = 0;
};

// Throws InputError when the mesh cannot be mapped (the failed check, with counts).
MappedMesh map_mesh(const PolygonMesh& input, const PrepareOptions& prepare,
                    const MapOptions& options, const MapControl& control = {});

// The same from a mesh already prepared; throws InputError when it is not mappable.
MappedMesh map_prepared(PreparedMesh prepared, const MapOptions& options,
                        const MapControl& control = {});

// The input mesh with every vertex moved to its sphere position (input order and faces;
// unreferenced vertices that weld to nothing stay at the origin, faces of dropped
// components are left out).
PolygonMesh sphere_on_input(const PolygonMesh& input, const MappedMesh& mapped);

// The welded mesh (one vertex per surface point) on the sphere.
PolygonMesh sphere_welded(const MappedMesh& mapped);

}  // namespace spheremap
