// spheremap remesh | uv | morph: the assets built on the map (ALGORITHM §E).
#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>

#include "cli/arguments.h"
#include "cli/commands.h"
#include "cli/map_options.h"
#include "core/io/glb_writer.h"
#include "core/io/mesh_file.h"
#include "core/map/certification.h"
#include "core/mesh/input_error.h"
#include "core/outputs/map_outputs.h"
#include "core/outputs/report_json.h"

namespace spheremap::cli {
namespace {

const char* const kRemeshUsage =
    R"(Usage: spheremap remesh INPUT -o OUT.glb|OUT.gltf [--resolution N] [options]

Maps INPUT onto the sphere, then resamples the ORIGINAL surface on a regular grid of the
octahedral square (Praun & Hoppe 2003): N x N quads, (N+1)^2 samples, each located in
the spherical map and interpolated on the surface there. The grid's border is stitched as
the unfolding identifies it, so the remesh is closed and genus 0 (checked; the metrics
say so). TEXCOORD_0 holds the grid coordinates.

  -o, --output FILE         the remesh as .glb or .gltf (buffers embedded); required
  --resolution N            quads per side, even, 2..4096 (default 256)
  --geometry-image FILE     also write the sampled positions as a 16-bit RGB PNG,
                            (N+1) x (N+1), scaled as the metrics' geometry_image says
  --metrics FILE            the map's metrics with the remesh's: sizes, topology,
                            distance to the original (RMS, Hausdorff) relative to the
                            bounding-box diagonal
  --no-normal-map           the remesh of an envelope (wrap) without the normal map of
                            the original's shading (its bake costs about as long as the
                            colour bake: one closest-point query per texel)
  --mesh INDEX|NAME, --quiet  as for map

)";

const char* const kUvUsage = R"(Usage: spheremap uv INPUT -o OUT.glb|OUT.gltf [options]

Maps INPUT onto the sphere and gives every vertex of the (welded) surface texture
coordinates from the octahedral square. Triangles that reach across the unfolding's cuts
are split there, with a vertex per side, so no triangle's UVs span a cut. The GLB carries
TEXCOORD_0, normals and a material with an embedded checker texture (red grows with u,
green with v) to show the mapping at a glance.

  -o, --output FILE         the textured mesh as .glb or .gltf (buffers embedded); required
  --metrics FILE            the map's metrics with the UV map's: split triangles, seam
                            vertices, flipped and degenerate UV triangles, stretch
  --mesh INDEX|NAME, --quiet  as for map

)";

const char* const kMorphUsage =
    R"(Usage: spheremap morph INPUT -o OUT.glb|OUT.gltf [--seconds S] [options]

Maps INPUT onto the sphere and writes the (welded) surface with one morph target moving
every vertex to its sphere position (a sphere of the surface's area about its centroid),
normals too, and an animation that plays mesh -> sphere -> mesh: any glTF viewer shows
the mesh becoming its sphere. A glTF input keeps its own vertices, materials, textures,
TEXCOORD_n, COLOR_0, names, nodes and transforms.

  -o, --output FILE         the morph as .glb or .gltf (buffers embedded); required
  --seconds S               length of the animation (default 4)
  --metrics FILE            the map's metrics with the morph's
  --mesh INDEX|NAME, --quiet  as for map

)";

enum class Output { kRemesh, kUv, kMorph };

int run_output(int argc, char** argv, Output kind) {
  std::set<std::string> values = kMapValueOptions;
  values.insert({"output", "metrics", "mesh", "resolution", "geometry-image", "seconds"});
  std::set<std::string> flags = kMapFlags;
  flags.insert({"quiet", "help"});
  if (kind == Output::kRemesh) flags.insert("no-normal-map");
  Arguments args(argc, argv, 2, values, flags);
  const char* usage =
      kind == Output::kRemesh ? kRemeshUsage : (kind == Output::kUv ? kUvUsage : kMorphUsage);
  if (args.flag("help")) {
    std::cout << usage << kMapOptionsHelp
              << "\nExit codes: 0 written; 1 usage error; 2 invalid input; 3 no bijective map "
                 "reached (nothing written).\n";
    return kExitOk;
  }
  if (args.positional().size() != 1) throw UsageError("takes exactly one INPUT file");
  const std::string output = args.text("output", "");
  const bool gltf_text = output.size() > 5 && output.ends_with(".gltf");
  if (!gltf_text && (output.size() < 5 || !output.ends_with(".glb")))
    throw UsageError("needs -o OUTPUT.glb or OUTPUT.gltf, got '" + output + "'");
  const int resolution = static_cast<int>(args.integer("resolution", 256, 2, 4096));
  if (resolution % 2) throw UsageError("--resolution must be even");
  PrepareOptions prepare;
  MapOptions options;
  read_map_options(args, prepare, options);

  // --time-limit bounds the whole command: the map, then the remesh's colour bake.
  const auto start = std::chrono::steady_clock::now();
  const std::function<bool()> out_of_time = [&] {
    return options.time_limit_seconds > 0 &&
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >=
               options.time_limit_seconds;
  };
  double last_print = 0;
  const MappedInput run =
      map_input(args, prepare, options, progress_printer(args.flag("quiet"), last_print));
  const MappedMesh& mapped = run.mapped;
  if (const Certification verdict = certify(mapped, mapped.float32_check); !verdict.certified) {
    std::fprintf(stderr, "spheremap: %s: %s\n", verdict.problem.c_str(), verdict.detail.c_str());
    return kExitNotBijective;
  }
  print_parts_left_out(mapped.prepared);
  nlohmann::json metrics = {{"map", metrics_json(mapped, options)}};
  std::string glb;
  if (kind == Output::kRemesh) {
    RemeshAsset asset;
    try {
      asset = remesh_asset(mapped, resolution, options.smoothing.threads, &run.input, &run.look,
                           &out_of_time, !args.flag("no-normal-map"));
    } catch (const InputError& e) {
      if (e.check() != "stopped") throw;
      std::fprintf(stderr,
                   "spheremap: time_limit: the time limit (%g s) passed while the remesh was "
                   "written; nothing written\n",
                   options.time_limit_seconds);
      return kExitNotBijective;
    }
    glb = asset.glb;
    metrics["remesh"] = asset.metrics;
    if (args.has("geometry-image"))
      write_binary_file(args.text("geometry-image", ""), asset.geometry_image_png);
    if (!asset.metrics["closed_genus0"].get<bool>())
      std::fprintf(stderr, "spheremap: warning: the remesh is not a closed genus-0 surface\n");
  } else if (kind == Output::kUv) {
    const UvAsset asset = uv_asset(mapped, &run.input, &run.look);
    glb = asset.glb;
    metrics["uv"] = asset.metrics;
  } else {
    const MorphAsset asset =
        morph_asset(mapped, args.number("seconds", 4, 0.1, 3600), &run.input, &run.look);
    glb = asset.glb;
    metrics["morph"] = asset.metrics;
  }
  write_binary_file(output, gltf_text ? glb_to_gltf(glb) : glb);
  if (args.has("metrics")) write_binary_file(args.text("metrics", ""), metrics.dump(2) + "\n");
  return kExitOk;
}

}  // namespace

int run_remesh(int argc, char** argv) {
  return run_output(argc, argv, Output::kRemesh);
}
int run_uv(int argc, char** argv) {
  return run_output(argc, argv, Output::kUv);
}
int run_morph(int argc, char** argv) {
  return run_output(argc, argv, Output::kMorph);
}

}  // namespace spheremap::cli
