#include "core/io/draco_file.h"

#include <algorithm>
#include <array>
#include <string>

#include <draco/compression/decode.h>
#include "core/io/draco_header.h"
#include "core/io/gltf_reader.h"
#include "core/mesh/counted.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

[[noreturn]] void refuse(const std::string& why) {
  throw InputError("parse", "drc: " + why);
}

}  // namespace

bool is_draco_file(std::span<const uint8_t> bytes) {
  static constexpr uint8_t kMagic[] = {'D', 'R', 'A', 'C', 'O'};
  return bytes.size() >= 5 && std::equal(kMagic, kMagic + 5, bytes.begin());
}

PolygonMesh read_draco_file(std::span<const uint8_t> bytes, const MeshLimits& limits) {
  if (!is_draco_file(bytes)) refuse("the file does not start with DRACO");
  // Header: magic, major, minor, geometry type (0 point cloud, 1 triangle mesh).
  if (bytes.size() < 8) refuse("the file ends inside its header");
  if (bytes[7] == 0) {
    uint64_t points = 0;
    try {
      points = read_draco_point_count(bytes);  // from the header: nothing decoded
    } catch (const InputError& e) {
      refuse(e.what());
    }
    throw InputError("empty", "drc: the file is a point cloud (" + counted(points, "point") +
                                  ", no faces): spheremap maps triangle surfaces");
  }
  if (bytes[5] != 2 || bytes[6] != 2)
    refuse("the file is Draco bitstream version " + std::to_string(bytes[5]) + "." +
           std::to_string(bytes[6]) +
           "; version 2.2 is read (what Draco 1.4 and later write: re-encode it with "
           "draco_encoder)");
  // The caps the glTF reader applies to its Draco streams bound a .drc too.
  const GltfReadOptions gltf_caps;
  const size_t max_vertices = std::min(limits.max_vertices, gltf_caps.max_vertices);
  const size_t max_triangles = std::min(limits.max_triangles, gltf_caps.max_triangles);
  DracoCounts declared;
  try {
    declared = read_draco_counts(bytes);
  } catch (const InputError& e) {
    refuse(e.what());
  }
  if (declared.faces > max_triangles || declared.vertices > max_vertices)
    throw InputError("too_large", "drc: the file declares " + std::to_string(declared.vertices) +
                                      " vertices and " + std::to_string(declared.faces) +
                                      " triangles, over the limits of " +
                                      std::to_string(max_vertices) + " and " +
                                      std::to_string(max_triangles));
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok() || !decoded.value())
    refuse("the Draco data does not decode as a mesh (truncated or malformed)");
  const draco::Mesh& mesh = *decoded.value();
  const draco::PointAttribute* position =
      mesh.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (!position || position->num_components() != 3)
    refuse("the Draco mesh has no 3-component POSITION attribute");
  // Draco converts a bool attribute by loading its bytes as bool: any byte but 0 and 1 is
  // undefined behaviour (found by the fuzzer). Positions are numbers.
  if (position->data_type() == draco::DT_BOOL || position->data_type() == draco::DT_INVALID)
    refuse("the Draco POSITION attribute is not numeric");
  const size_t points = mesh.num_points();
  if (points > max_vertices)  // edgebreaker adds seam copies to what it declares
    throw InputError("too_large", "drc: the Draco mesh has " + std::to_string(points) +
                                      " vertices, over the limit of " +
                                      std::to_string(max_vertices));
  PolygonMesh out;
  out.positions.resize(points);
  for (uint32_t i = 0; i < points; ++i) {
    std::array<float, 3> v{};
    if (!position->ConvertValue<float>(position->mapped_index(draco::PointIndex(i)), 3, v.data()))
      refuse("a Draco position does not convert to float");
    out.positions[i] = {v[0], v[1], v[2]};
  }
  out.indices.reserve(static_cast<size_t>(mesh.num_faces()) * 3);
  out.offsets.reserve(static_cast<size_t>(mesh.num_faces()) + 1);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    std::array<uint32_t, 3> corners{};
    for (int c = 0; c < 3; ++c) {
      corners[static_cast<size_t>(c)] = mesh.face(draco::FaceIndex(f))[c].value();
      if (corners[static_cast<size_t>(c)] >= points)
        refuse("a Draco face refers past the decoded vertices");
    }
    out.add_face(corners);
  }
  return out;
}

}  // namespace spheremap
