// libFuzzer target: the glTF / GLB / Draco reader on arbitrary bytes. Any input must end
// in a mesh or an InputError: no crash, leak, hang, or other exception.
#include <cstddef>
#include <cstdint>

#include "core/io/gltf_reader.h"
#include "core/mesh/input_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  spheremap::GltfReadOptions options;
  options.max_vertices = 1 << 20;  // the service's caps are smaller still
  options.max_triangles = 1 << 21;
  try {
    spheremap::read_gltf({data, size}, options);
  } catch (const spheremap::InputError&) {
  }
  return 0;
}
