// libFuzzer target: the STL and PLY readers (binary and ASCII), and the format sniffing
// that uploads go through, then welding + topology on what they return. Any input must
// end in a mesh or an InputError: no crash, no hang, no allocation beyond the bytes.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/io/mesh_format.h"
#include "core/io/ply.h"
#include "core/io/stl.h"
#include "core/map/pipeline.h"
#include "core/mesh/input_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  (void)spheremap::sniff_mesh_format(bytes);
  for (int format = 0; format < 2; ++format) {
    try {
      const spheremap::PolygonMesh mesh =
          format == 0 ? spheremap::parse_stl(bytes) : spheremap::parse_ply(bytes);
      spheremap::prepare_mesh(mesh, {});
    } catch (const spheremap::InputError&) {
    }
  }
  return 0;
}
