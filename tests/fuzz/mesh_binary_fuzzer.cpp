// libFuzzer target: the STL and PLY readers (binary and ASCII), raw Draco (.drc) files, and
// the format sniffing that uploads go through, then welding + topology on what they return.
// Any input must end in a mesh or an InputError: no crash, no hang, no allocation beyond
// the bytes (Draco's: beyond the caps its header is checked against).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/io/draco_file.h"
#include "core/io/mesh_format.h"
#include "core/io/ply.h"
#include "core/io/stl.h"
#include "core/map/pipeline.h"
#include "core/mesh/input_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  (void)spheremap::sniff_mesh_format(bytes);
  // Draco allocates by the counts its header declares: caps that keep a forged one under
  // libFuzzer's memory limit (the service's are of the same order).
  spheremap::MeshLimits draco_limits;
  draco_limits.max_vertices = 1'000'000;
  draco_limits.max_triangles = 2'000'000;
  for (int format = 0; format < 3; ++format) {
    try {
      const spheremap::PolygonMesh mesh =
          format == 0   ? spheremap::parse_stl(bytes)
          : format == 1 ? spheremap::parse_ply(bytes)
                        : spheremap::read_draco_file({data, size}, draco_limits);
      spheremap::prepare_mesh(mesh, {});
    } catch (const spheremap::InputError&) {
    }
  }
  return 0;
}
