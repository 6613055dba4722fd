#include <cstdio>
#include <iostream>

#include "cli/arguments.h"
#include "cli/commands.h"
#include "cli/map_options.h"
#include "core/io/glb_writer.h"
#include "core/io/mesh_file.h"
#include "core/map/certification.h"
#include "core/mesh/input_error.h"
#include "core/outputs/report_json.h"
#include "core/outputs/sphere_asset.h"

namespace spheremap::cli {
namespace {

const char* const kUsage = R"(Usage: spheremap map INPUT -o OUTPUT [--metrics FILE.json] [options]

Maps a closed genus-0 mesh (.obj, .off, .stl, .ply, .glb, .gltf; Draco-compressed glTF
too) onto the unit sphere, without folds. OUTPUT has the input's vertices in the input's
order and the input's faces, every vertex moved to its point on the sphere (vertices with
equal positions share one point: an STL's three corners per triangle too). A glTF input is
every triangle primitive of its default scene in world space, unless --mesh picks one mesh.

  -o, --output FILE         the spherical mesh: .obj, or .glb / .gltf (buffers embedded):
                            triangles, normals = positions, the metrics in the first mesh's
                            extras; a glTF input keeps its materials, textures, TEXCOORD_n,
                            COLOR_0, names, nodes and transforms (layout original, no Draco);
                            required
  --mesh INDEX|NAME         glTF: map only this mesh (by index or name)
  --draco                   .glb/.gltf: compress with Draco (KHR_draco_mesh_compression,
                            required; positions and normals only)
  --draco-position-bits N   quantization of Draco positions, 8-20 bits (default: the
                            fewest of 14, 16, 18, 20 whose file is still bijective)
  --layout L                original (default): the input's own vertices, so attributes such as
                            UVs stay aligned with the input file; welded: one vertex per surface
                            point
  --metrics FILE            write the quality metrics as JSON
  --quiet                   no progress on stderr (shown for runs over a second)

)";

}  // namespace

int run_map(int argc, char** argv) {
  std::set<std::string> values = kMapValueOptions;
  values.insert({"output", "metrics", "mesh", "layout", "draco-position-bits"});
  std::set<std::string> flags = kMapFlags;
  flags.insert({"quiet", "help", "draco"});
  Arguments args(argc, argv, 2, values, flags);
  if (args.flag("help")) {
    std::cout << kUsage << kMapOptionsHelp
              << "\nExit codes: 0 certified bijective map written (no folded and no degenerate\n"
                 "triangle in double, in float32 and as written); 1 usage error; 2 invalid input\n"
                 "(the failed check on stderr); 3 not certified: no bijective map reached, the\n"
                 "time limit hit, or folds once rounded to float32 or quantized (the best map and\n"
                 "its metrics are still written, with \"bijective\": false and the problem).\n";
    return kExitOk;
  }
  if (args.positional().size() != 1) throw UsageError("map takes exactly one INPUT file");
  if (!args.has("output")) throw UsageError("map needs -o OUTPUT");
  PrepareOptions prepare;
  MapOptions options;
  read_map_options(args, prepare, options);
  const std::string layout = args.text("layout", "original");
  if (layout != "original" && layout != "welded")
    throw UsageError("--layout must be original or welded, got '" + layout + "'");

  const std::string output = args.text("output", "");
  const bool gltf_text = output.size() > 5 && output.ends_with(".gltf");
  const bool glb = gltf_text || (output.size() > 4 && output.ends_with(".glb"));
  const bool obj = output.size() > 4 && output.ends_with(".obj");
  if (!glb && !obj)
    throw UsageError("-o must name a .glb, .gltf or .obj file, got '" + output + "'");
  int draco_bits = 0;
  if (args.flag("draco"))
    draco_bits = args.has("draco-position-bits")
                     ? static_cast<int>(args.integer("draco-position-bits", 14, 8, 20))
                     : kDracoBitsAutomatic;
  else if (args.has("draco-position-bits"))
    throw UsageError("--draco-position-bits needs --draco");
  if (draco_bits && !glb) throw UsageError("--draco needs a .glb or .gltf output");

  double last_print = 0;
  const MappedInput run =
      map_input(args, prepare, options, progress_printer(args.flag("quiet"), last_print));
  const PolygonMesh& input = run.input;
  const MappedMesh& mapped = run.mapped;
  const SphereLayout sphere_layout =
      layout == "welded" ? SphereLayout::kWelded : SphereLayout::kOriginal;
  nlohmann::json metrics;
  MapCheck written = mapped.map.check;  // OBJ keeps every double digit
  if (glb) {
    const SphereAsset asset =
        sphere_asset(input, mapped, options, sphere_layout, draco_bits, &run.look);
    written = asset.written;
    metrics = asset.metrics;
    write_binary_file(output, gltf_text ? glb_to_gltf(asset.glb) : asset.glb);
  } else {
    metrics = metrics_json(mapped, options);
    metrics["bijective_as_written"] = clean(written);
    metrics["folds_as_written"] = written.folds;
    write_mesh_file(output, sphere_mesh(input, mapped, sphere_layout));
  }
  if (!run.input_warnings.empty()) metrics["input_warnings"] = run.input_warnings;
  if (args.has("metrics")) {
    write_binary_file(args.text("metrics", ""), metrics.dump(2) + "\n");
  }
  print_parts_left_out(mapped.prepared);
  const Certification verdict = certify(mapped, written);
  if (!verdict.certified) {
    std::fprintf(stderr, "spheremap: %s: %s\n", verdict.problem.c_str(), verdict.detail.c_str());
    return kExitNotBijective;
  }
  return kExitOk;
}

}  // namespace spheremap::cli
