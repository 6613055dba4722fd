// The spherical mesh as a finished GLB asset: the layout the user asked for, the metrics
// in the mesh's extras, and the verdict on the map as a reader of the file will see it.
// Shared by `spheremap map` and the service's sphere.glb.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/io/gltf_appearance.h"
#include "core/map/pipeline.h"

namespace spheremap {

enum class SphereLayout {
  kOriginal,  // the input's own vertices and faces (attributes of the input stay aligned)
  kWelded,    // one vertex per surface point
};

struct SphereAsset {
  std::string glb;
  nlohmann::json metrics;  // metrics_json + bijective_as_written, folds_as_written
  MapCheck written;        // the file decoded again (float32, Draco-quantized) and checked
};

// Draco's position quantization when the caller did not choose one: the fewest of
// kDracoAutomaticBits whose file is still certified (the last when none is; 14 when the
// map is not certified in float32, which no grid can mend). The grid
// of 14 bits (Draco's usual default) has cells of 1.2e-4 on the unit sphere; a map whose
// smallest spherical triangles are far smaller folds once snapped to it (beast: 8 folds
// at 14 bits, min area 7e-9), and each 2 bits more cut the cell by 4.
constexpr int kDracoBitsAutomatic = -1;
constexpr int kDracoAutomaticBits[] = {14, 16, 18, 20};

// The spherical mesh of `mapped` in `layout`; Draco when draco_position_bits is not 0
// (kDracoBitsAutomatic: chosen as above; metrics name the bits used). With
// the `appearance` read beside `input` (a glTF), layout kOriginal and no Draco, the file
// keeps the input's materials, textures, attributes, names and nodes.
SphereAsset sphere_asset(const PolygonMesh& input, const MappedMesh& mapped,
                         const MapOptions& options, SphereLayout layout, int draco_position_bits,
                         const GltfAppearance* appearance = nullptr);

// Per input face, whether mapping left it out (a component dropped before mapping).
std::vector<char> dropped_faces(const PolygonMesh& input, const MappedMesh& mapped);

// The input face of each welded face: welded faces are the input's faces in order, less
// the dropped ones.
std::vector<uint32_t> welded_input_faces(const PolygonMesh& input, const MappedMesh& mapped);

// The spherical mesh of `mapped` in `layout`, in double precision.
PolygonMesh sphere_mesh(const PolygonMesh& input, const MappedMesh& mapped, SphereLayout layout);

}  // namespace spheremap
