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

struct MappedPart;

struct MappedMesh {
  PreparedMesh prepared;
  MapResult map;
  // The same verdict on the positions rounded to float32, as glTF stores them: thin parts
  // squeezed below float32's resolution fold there although the double map is bijective.
  MapCheck float32_check;
  QualityMetrics quality;
  double prepare_seconds = 0, metrics_seconds = 0;
  // An asset of several parts (prepare "parts", map_parts.h): each part mapped alone,
  // largest first. The members above then describe them together: map.sphere holds each
  // welded vertex's place on its own part's unit sphere, the checks' counts are summed
  // (the signed areas to 4 pi per part) and bijective only when every part's is, and the
  // quality is combined area-weighted. Empty for an asset of one part.
  std::vector<MappedPart> parts;
};

struct MappedPart {
  MappedMesh mapped;                   // the part alone (its input_to_welded is empty)
  std::vector<uint32_t> whole_vertex;  // per vertex of the part: its welded vertex in the whole
  // Where outputs that show every part draw its sphere: about the part's area-weighted
  // centroid, with the part's surface area.
  Vec3 center;
  double radius = 0, surface_area = 0;
  // A copy of an earlier part (part_copies.h): its map is that part's turned; the index
  // is in the same list of parts.
  std::optional<size_t> copy_of;
};

// Throws InputError when the mesh cannot be mapped (the failed check, with counts).
MappedMesh map_mesh(const PolygonMesh& input, const PrepareOptions& prepare,
                    const MapOptions& options, const MapControl& control = {});

// The same from a mesh already prepared; throws InputError when it is not mappable.
MappedMesh map_prepared(PreparedMesh prepared, const MapOptions& options,
                        const MapControl& control = {});

// The quality metrics and the float32 check of out.map (a map of out.prepared.welded.mesh),
// with metrics_seconds; map_prepared's last step.
void measure_map(MappedMesh& out, const MapOptions& options);

// The input mesh with every vertex moved to its sphere position (input order and faces;
// unreferenced vertices that weld to nothing stay at the origin, faces of dropped
// components are left out). With several parts, each part's sphere is where it is drawn
// (MappedPart::center, radius).
PolygonMesh sphere_on_input(const PolygonMesh& input, const MappedMesh& mapped);

// The welded mesh (one vertex per surface point) on the sphere (its parts' as above).
PolygonMesh sphere_welded(const MappedMesh& mapped);

}  // namespace spheremap
