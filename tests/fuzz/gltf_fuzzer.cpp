// libFuzzer target: the glTF / GLB / Draco reader on arbitrary bytes, with the look the
// outputs carry over (materials, attributes, nodes, images). Any input must end in a mesh
// or an InputError: no crash, leak, hang, or other exception. A file that reads is
// written back with its look (the scene writer: a mesh or an InputError again) and its
// images decoded.
#include <cstddef>
#include <cstdint>

#include "core/io/gltf_reader.h"
#include "core/io/image_reader.h"
#include "core/io/scene_glb.h"
#include "core/mesh/input_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  spheremap::GltfReadOptions options;
  options.max_vertices = 1 << 20;  // the service's caps are smaller still
  options.max_triangles = 1 << 21;
  spheremap::GltfAppearance look;
  spheremap::PolygonMesh mesh;
  try {
    mesh = spheremap::read_gltf({data, size}, options, nullptr, nullptr, &look);
  } catch (const spheremap::InputError&) {
    return 0;
  }
  spheremap::SceneGeometry geometry;
  geometry.input = &mesh;
  geometry.positions = mesh.positions;
  try {
    // Node transforms can carry float32 positions past float32's range: the writer
    // refuses those with an InputError (float32_range).
    if (!look.empty()) spheremap::build_scene_glb(look, geometry, {});
  } catch (const spheremap::InputError&) {
  }
  for (const std::string& image : look.image_data) try {
      spheremap::decode_image(image, 1 << 16);
    } catch (const spheremap::InputError&) {  // a JPEG of too many scans
    }
  return 0;
}
