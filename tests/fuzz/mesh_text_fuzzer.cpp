// libFuzzer target: the OBJ, MNI obj and OFF readers (and welding + topology on what they
// return) on arbitrary text. Any input must end in a mesh or an InputError.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/io/mni_obj.h"
#include "core/io/obj.h"
#include "core/io/off.h"
#include "core/map/pipeline.h"
#include "core/mesh/input_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (int format = 0; format < 3; ++format) {
    try {
      const spheremap::PolygonMesh mesh = format == 0   ? spheremap::parse_obj(text)
                                          : format == 1 ? spheremap::parse_off(text)
                                                        : spheremap::parse_mni_obj(text);
      spheremap::prepare_mesh(mesh, {});
    } catch (const spheremap::InputError&) {
    }
  }
  return 0;
}
