// Input preparation (ALGORITHM §0) and the full map pipeline, shared by the command-line
// tool and the service: weld -> validate -> map -> verify -> metrics.
#pragma once

#include <functional>
#include <string>

#include "core/map/metrics.h"
#include "core/map/spherical_map.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"

namespace spheremap {

struct PrepareOptions {
  double weld_tolerance = 0;  // relative to the bounding-box diagonal; 0 = exact positions
  // Keep only the connected component with the most faces (others are dropped, their
  // input vertices then map to nothing); otherwise several components are an error.
  bool largest_component = false;
  // Asked while welding: true stops with InputError("stopped") (see StopCheck).
  std::function<bool()> should_stop;
};

struct PreparedMesh {
  WeldResult welded;
  TopologyReport topology;
};

// Welds and reports; does not reject.
PreparedMesh prepare_mesh(const PolygonMesh& input, const PrepareOptions& options);

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
