// Input preparation (ALGORITHM §0) and the full map pipeline, shared by the command-line
// tool and the service: weld -> validate -> map -> verify -> metrics.
#pragma once

#include "core/metrics.h"
#include "core/spherical_map.h"
#include "core/topology.h"
#include "core/weld.h"

namespace spheremap {

struct PrepareOptions {
  double weld_tolerance = 0;  // relative to the bounding-box diagonal; 0 = exact positions
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
  QualityMetrics quality;
  double prepare_seconds = 0, metrics_seconds = 0;
};

// Throws InputError when the mesh cannot be mapped (the failed check, with counts).
MappedMesh map_mesh(const PolygonMesh& input, const PrepareOptions& prepare,
                    const MapOptions& options, const MapControl& control = {});

// The input mesh with every vertex moved to its sphere position (input order and faces;
// unreferenced vertices that weld to nothing stay at the origin).
PolygonMesh sphere_on_input(const PolygonMesh& input, const MappedMesh& mapped);

}  // namespace spheremap
