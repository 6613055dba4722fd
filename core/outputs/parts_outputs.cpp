// The assets of an asset of several parts: each part's pieces (asset_builders.h) side by
// side in one file, a node per part, and their metrics summed with a list per part.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/io/png_writer.h"
#include "core/mesh/triangle_tree.h"
#include "core/outputs/asset_builders.h"
#include "core/outputs/part_grids.h"
#include "core/outputs/report_json.h"
#include "core/outputs/texcoords.h"

namespace spheremap {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<GlbNode> part_nodes(size_t parts) {
  std::vector<GlbNode> nodes(parts);
  for (size_t k = 0; k < parts; ++k) nodes[k].name = "part " + std::to_string(k);
  return nodes;
}

// Per part, its input vertices as (input vertex, vertex of the part): what a part's own
// input_to_welded would hold, in O(input) for all parts together.
std::vector<std::vector<std::pair<uint32_t, uint32_t>>> input_vertices_of_parts(
    const MappedMesh& mapped, const PartIndex& index) {
  const auto& to_welded = mapped.prepared.welded.input_to_welded;
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> out(mapped.parts.size());
  for (size_t v = 0; v < to_welded.size(); ++v)
    if (to_welded[v] != kUnreferenced && index.part[to_welded[v]] != kUnreferenced)
      out[index.part[to_welded[v]]].emplace_back(static_cast<uint32_t>(v),
                                                 index.local[to_welded[v]]);
  return out;
}

// Per part, the input face of each of its welded faces (what welded_input_faces gives for
// the part with its own input_to_welded), in one pass over the input for all parts.
std::vector<std::vector<uint32_t>> input_faces_of_parts(const PolygonMesh& input,
                                                        const MappedMesh& mapped,
                                                        const PartIndex& index) {
  const auto& to_welded = mapped.prepared.welded.input_to_welded;
  std::vector<std::vector<uint32_t>> out(mapped.parts.size());
  for (uint32_t f = 0; f < input.face_count(); ++f)
    if (const uint32_t w = to_welded[input.face(f)[0]];
        w != kUnreferenced && index.part[w] != kUnreferenced)
      out[index.part[w]].push_back(f);
  return out;
}

// The bounding-box diagonal of the vertices `mesh`'s faces use.
double faces_diagonal(const PolygonMesh& mesh) {
  AxisBox box;
  for (uint32_t v : mesh.indices) box.add(mesh.positions[v]);
  return mesh.indices.empty() ? 0.0 : norm(box.hi - box.lo);
}

}  // namespace

std::vector<const PartReport*> part_reports(const MappedMesh& mapped) {
  std::vector<const PartReport*> out;
  for (const PartReport& report : mapped.prepared.parts)
    if (report.mappable()) out.push_back(&report);
  if (out.size() != mapped.parts.size()) out.assign(mapped.parts.size(), nullptr);
  return out;
}

PartIndex::PartIndex(const MappedMesh& mapped)
    : part(mapped.prepared.welded.mesh.vertex_count(), kUnreferenced),
      local(part.size(), kUnreferenced) {
  for (size_t k = 0; k < mapped.parts.size(); ++k)
    for (size_t v = 0; v < mapped.parts[k].whole_vertex.size(); ++v) {
      part[mapped.parts[k].whole_vertex[v]] = static_cast<uint32_t>(k);
      local[mapped.parts[k].whole_vertex[v]] = static_cast<uint32_t>(v);
    }
}

RemeshAsset parts_remesh_asset(const MappedMesh& mapped, int resolution, int threads,
                               const PolygonMesh* input, const GltfAppearance* appearance,
                               const std::function<bool()>* should_stop, bool normal_map) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> areas, diagonals;
  for (const MappedPart& part : mapped.parts) {
    areas.push_back(part.surface_area);
    diagonals.push_back(faces_diagonal(part.mapped.prepared.welded.mesh));
  }
  const std::vector<int> grids = part_grids(resolution, areas, diagonals);
  // Turned frames are tried for a part whose remesh stands over kFrameTrialDistance of the
  // ASSET's diagonal from it (in the part's own terms, over its own diagonal): a part
  // nearer than that cannot set an asset's distance that is over the threshold, and trying
  // every part over its own threshold doubled the remesh stage of assets of many small
  // parts (FlightHelmet, 85 parts: 6.1 s -> 14.7 s at one thread, now 11.3 s, its
  // distance to the original the same). Going further, only the parts farthest in model
  // units (until the next is no farther than the farthest kept) costs less again but is
  // farther from the original where parts overlap (FlightHelmet 0.62% -> 0.74%): the union
  // of the parts' remeshes stands nearer the original than any one part to its own faces.
  AxisBox asset_box;
  for (const MappedPart& part : mapped.parts)
    for (uint32_t v : part.mapped.prepared.welded.mesh.indices)
      asset_box.add(part.mapped.prepared.welded.mesh.positions[v]);
  const double parts_diagonal = mapped.parts.empty() ? 0.0 : norm(asset_box.hi - asset_box.lo);
  const auto frame_trial_distance = [&](size_t k) {
    return diagonals[k] > 0 ? kFrameTrialDistance * std::max(parts_diagonal / diagonals[k], 1.0)
                            : kFrameTrialDistance;
  };
  // The base colour is baked per part through the part's own input_to_welded, made in one
  // scratch vector that each part fills and clears (O(input) in all).
  const bool bake = input && appearance;
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> inputs;
  std::vector<std::vector<uint32_t>> input_faces;
  std::vector<uint32_t> scratch;
  if (bake) {
    const PartIndex index(mapped);
    inputs = input_vertices_of_parts(mapped, index);
    input_faces = input_faces_of_parts(*input, mapped, index);
    scratch.assign(input->vertex_count(), kUnreferenced);
  }
  const std::vector<const PartReport*> reports = part_reports(mapped);
  DecodedImages decoded;  // each base-colour image decoded once for all parts
  std::vector<GlbMesh> meshes;
  std::vector<GeometryImage> images;
  nlohmann::json parts = nlohmann::json::array();
  size_t samples = 0, vertices = 0, triangles = 0, unlocated = 0, wrapped_parts = 0;
  bool closed_genus0 = true;
  double hausdorff = 0, hausdorff_at_most = 0, squared = 0, relative_rms_weight = 0;
  bool settled = true;  // every part's maximum settled (refined_maximum.h)
  double original_hausdorff = 0, original_squared = 0;  // to the original: wrapped or not
  double bake_seconds = 0, original_seconds = 0;        // of the wrapped parts, summed
  double normal_map_seconds = 0;
  double absolute_hausdorff = 0, absolute_squared = 0;  // the same in model units
  struct {
    double hausdorff = 0, at_most = 0, squared = 0;
  } measured_absolute;  // `distance` in model units
  for (size_t k = 0; k < mapped.parts.size(); ++k) {
    const MappedPart& part = mapped.parts[k];
    const int grid = grids[k];
    const int texture = part_texture_size(resolution, grid);
    BuiltRemesh built;
    if (input && reports[k] && reports[k]->wrapped) {
      // An envelope: measured against, and coloured from, the input's faces it stands for.
      const OriginalSurface original =
          original_surface(*input, appearance, &reports[k]->original_faces);
      built = build_remesh(part.mapped, grid, threads, nullptr, nullptr, should_stop, &original,
                           &decoded, normal_map, texture, nullptr, frame_trial_distance(k));
      ++wrapped_parts;
    } else if (bake) {
      MappedMesh with_input = part.mapped;
      for (auto [v, w] : inputs[k]) scratch[v] = w;
      with_input.prepared.welded.input_to_welded = std::move(scratch);
      built = build_remesh(with_input, grid, threads, input, appearance, should_stop, nullptr,
                           &decoded, normal_map, texture, &input_faces[k], frame_trial_distance(k));
      scratch = std::move(with_input.prepared.welded.input_to_welded);
      for (auto [v, w] : inputs[k]) scratch[v] = kUnreferenced;
    } else {
      built = build_remesh(part.mapped, grid, threads, nullptr, nullptr, should_stop, nullptr,
                           nullptr, true, 0, nullptr, frame_trial_distance(k));
    }
    const nlohmann::json& m = built.metrics;
    samples += m["samples"].get<size_t>();
    vertices += m["vertices"].get<size_t>();
    triangles += m["triangles"].get<size_t>();
    unlocated += m["unlocated_samples"].get<size_t>();
    closed_genus0 = closed_genus0 && m["closed_genus0"].get<bool>();
    // Distances relative to each part's own diagonal, combined as the largest and the
    // RMS weighted by samples.
    hausdorff = std::max(hausdorff, m["distance"]["hausdorff"].get<double>());
    hausdorff_at_most =
        std::max(hausdorff_at_most, m["distance"]["hausdorff_at_most"].get<double>());
    settled = settled && m["distance"]["hausdorff_settled"].get<bool>();
    const double rms = m["distance"]["rms"].get<double>();
    squared += rms * rms * m["samples"].get<double>();
    relative_rms_weight += m["samples"].get<double>();
    const double measured_diagonal = m["distance"]["diagonal"].get<double>();  // model units
    measured_absolute.hausdorff = std::max(
        measured_absolute.hausdorff, m["distance"]["hausdorff"].get<double>() * measured_diagonal);
    measured_absolute.at_most =
        std::max(measured_absolute.at_most,
                 m["distance"]["hausdorff_at_most"].get<double>() * measured_diagonal);
    measured_absolute.squared += std::pow(rms * measured_diagonal, 2) * m["samples"].get<double>();
    bake_seconds += m["seconds"].value("bake", 0.0);
    normal_map_seconds += m["seconds"].value("normal_map", 0.0);
    original_seconds += m["seconds"].value("distance_to_original", 0.0);
    const nlohmann::json& to_original =
        m.contains("distance_to_original") ? m["distance_to_original"] : m["distance"];
    original_hausdorff = std::max(original_hausdorff, to_original["hausdorff"].get<double>());
    const double original_rms = to_original["rms"].get<double>();
    original_squared += original_rms * original_rms * m["samples"].get<double>();
    const double diagonal = to_original["diagonal"].get<double>();  // model units
    absolute_hausdorff =
        std::max(absolute_hausdorff, to_original["hausdorff"].get<double>() * diagonal);
    absolute_squared += std::pow(original_rms * diagonal, 2) * m["samples"].get<double>();
    nlohmann::json entry = without_timings(m);
    entry["part"] = k;
    parts.push_back(std::move(entry));
    built.glb.extras = nlohmann::json::object();
    meshes.push_back(std::move(built.glb));
    images.push_back(std::move(built.image));
  }
  // The geometry images stacked top to bottom, each from its own row, left-aligned.
  int width = 0, height = 0;
  for (const GeometryImage& image : images) {
    width = std::max(width, image.side);
    height += image.side;
  }
  std::vector<uint16_t> rgb(static_cast<size_t>(width) * height * 3, 0);
  int row = 0;
  for (size_t k = 0; k < images.size(); ++k) {
    const GeometryImage& image = images[k];
    for (int r = 0; r < image.side; ++r)
      std::copy_n(&image.rgb[static_cast<size_t>(r) * image.side * 3], image.side * 3,
                  &rgb[(static_cast<size_t>(row + r) * width) * 3]);
    parts[k]["geometry_image"]["row"] = row;
    row += image.side;
  }
  RemeshAsset asset;
  asset.geometry_image_png = encode_png(width, height, 16, rgb);
  asset.metrics = {
      {"resolution", resolution},
      {"parts", parts},
      {"samples", samples},
      {"vertices", vertices},
      {"triangles", triangles},
      {"unlocated_samples", unlocated},
      {"closed_genus0", closed_genus0},
      {"distance",
       {{"relative_to", "bounding-box diagonal of each part"},
        {"hausdorff", hausdorff},
        {"hausdorff_at_most", hausdorff_at_most},
        {"hausdorff_settled", settled},
        {"rms", relative_rms_weight > 0 ? std::sqrt(squared / relative_rms_weight) : 0.0},
        // The same over the whole asset's diagonal: a small part far off by its own
        // diagonal (a screw at 30%) is not what the asset's remesh looks like (FlightHelmet:
        // 34.6% by the parts' own diagonals, 0.77% by the asset's).
        {"asset_diagonal", parts_diagonal},
        {"asset_hausdorff",
         parts_diagonal > 0 ? measured_absolute.hausdorff / parts_diagonal : 0.0},
        {"asset_hausdorff_at_most",
         parts_diagonal > 0 ? measured_absolute.at_most / parts_diagonal : 0.0},
        {"asset_rms",
         parts_diagonal > 0 && relative_rms_weight > 0
             ? std::sqrt(measured_absolute.squared / relative_rms_weight) / parts_diagonal
             : 0.0}}},
  };
  const double asset_diagonal = wrapped_parts > 0 ? faces_diagonal(*input) : 0.0;
  if (wrapped_parts > 0)
    asset.metrics["distance_to_original"] = {
        {"relative_to", "bounding-box diagonal of each part's original triangles"},
        {"hausdorff", original_hausdorff},
        {"rms", relative_rms_weight > 0 ? std::sqrt(original_squared / relative_rms_weight) : 0.0},
        {"wrapped_parts", wrapped_parts},
        // Relative to the whole input's diagonal, as the asset's other figures.
        {"asset_diagonal", asset_diagonal},
        {"asset_hausdorff", asset_diagonal > 0 ? absolute_hausdorff / asset_diagonal : 0.0},
        {"asset_rms", asset_diagonal > 0 && relative_rms_weight > 0
                          ? std::sqrt(absolute_squared / relative_rms_weight) / asset_diagonal
                          : 0.0}};
  asset.metrics["geometry_image"] = {
      {"width", width},
      {"height", height},
      {"bits", 16},
      {"layout",
       "the parts' images stacked from the top, each at parts[k].geometry_image.row "
       "and decoded with its own origin and scale"}};
  std::vector<GlbNode> nodes = part_nodes(meshes.size());
  GlbParts glb = build_glb(meshes, nodes);
  glb.json["meshes"][0]["extras"] = {{"spheremap_remesh", without_timings(asset.metrics)}};
  asset.glb = serialize_glb(glb);
  asset.metrics["seconds"] = {{"total", seconds_since(start)}};
  if (wrapped_parts > 0) {
    asset.metrics["seconds"]["bake"] = bake_seconds;
    asset.metrics["seconds"]["normal_map"] = normal_map_seconds;
    asset.metrics["seconds"]["distance_to_original"] = original_seconds;
  }
  return asset;
}

UvAsset parts_uv_asset(const MappedMesh& mapped, const PolygonMesh* input,
                       const GltfAppearance* appearance) {
  const auto start = std::chrono::steady_clock::now();
  // One texture for all: part k's square is cell k of a grid of cells x cells, so no two
  // parts share a texel.
  const size_t count = mapped.parts.size();
  const size_t cells = static_cast<size_t>(std::ceil(std::sqrt(static_cast<double>(count))));
  std::vector<GlbMesh> meshes;
  nlohmann::json parts = nlohmann::json::array();
  nlohmann::json total = {{"vertices", 0},
                          {"triangles", 0},
                          {"input_vertices", 0},
                          {"split_triangles", 0},
                          {"seam_vertices", 0},
                          {"flipped_triangles", 0},
                          {"degenerate_triangles", 0}};
  double area = 0, l2_squared = 0, linf = 0;
  const std::string checker = checker_png();
  const std::vector<const PartReport*> reports = part_reports(mapped);
  DecodedImages decoded;  // each base-colour image decoded once for all parts
  for (size_t k = 0; k < count; ++k) {
    // A wrapped part carries the colour of the input's faces it stands for.
    std::optional<OriginalSurface> original;
    if (input && reports[k] && reports[k]->wrapped)
      original = original_surface(*input, appearance, &reports[k]->original_faces);
    BuiltAsset built = build_uv(mapped.parts[k].mapped, original ? &*original : nullptr, &decoded);
    const double column = static_cast<double>(k % cells), line = static_cast<double>(k / cells);
    for (auto& t : built.glb.texcoords) {
      t[0] = static_cast<float>((column + t[0]) / cells);
      t[1] = static_cast<float>((line + t[1]) / cells);
    }
    for (auto& [key, value] : total.items())
      value = value.get<size_t>() + built.metrics[key].get<size_t>();
    const double a = mapped.parts[k].surface_area;
    const double l2 = built.metrics["stretch"]["l2"].get<double>();
    area += a;
    l2_squared += l2 * l2 * a;
    linf = std::max(linf, built.metrics["stretch"]["linf"].get<double>());
    built.metrics["part"] = k;
    built.metrics["cell"] = {k % cells, k / cells};
    parts.push_back(std::move(built.metrics));
    built.glb.extras = nlohmann::json::object();
    built.glb.base_color_png = checker;
    meshes.push_back(std::move(built.glb));
  }
  UvAsset asset;
  asset.metrics = total;
  asset.metrics["stretch"] = {{"l2", area > 0 ? std::sqrt(l2_squared / area) : 0.0},
                              {"linf", linf}};
  asset.metrics["atlas"] = {
      {"cells_per_side", cells},
      {"layout", "part k's square is cell (k mod cells_per_side, k div cells_per_side)"}};
  asset.metrics["parts"] = parts;
  GlbParts glb = build_glb(meshes, part_nodes(meshes.size()));
  glb.json["meshes"][0]["extras"] = {{"spheremap_uv", without_timings(asset.metrics)}};
  asset.glb = serialize_glb(glb);
  asset.metrics["seconds"] = seconds_since(start);
  return asset;
}

MorphAsset parts_morph_asset(const MappedMesh& mapped, double seconds, const PolygonMesh* input,
                             const GltfAppearance* appearance) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<const PartReport*> reports = part_reports(mapped);
  DecodedImages decoded;  // each base-colour image decoded once for all parts
  std::vector<GlbMesh> meshes;
  nlohmann::json parts = nlohmann::json::array();
  size_t vertices = 0, triangles = 0, wrapped = 0;
  double max_distance = 0, distance_seconds = 0;  // over the wrapped parts' vertices
  for (size_t k = 0; k < mapped.parts.size(); ++k) {
    BuiltMorph built = build_morph(mapped.parts[k].mapped, seconds);
    if (input && reports[k] && reports[k]->wrapped) {
      const OriginalSurface original =
          original_surface(*input, appearance, &reports[k]->original_faces);
      if (auto colors = colors_closest(original, built.glb.positions, 0, nullptr, &decoded)) {
        built.glb.colors = std::move(*colors);
        built.metrics["vertex_colors"] = "COLOR_0: the original's base colour at the closest point";
      }
      VertexDistances distances = vertex_distances(original, built.glb.positions, 0, nullptr);
      built.glb.distances = std::move(distances.relative);
      built.metrics["vertex_distances"] = distances.metrics;
      max_distance = std::max(max_distance, distances.metrics["max"].get<double>());
      distance_seconds += distances.metrics["seconds"].get<double>();
      ++wrapped;
    }
    vertices += built.metrics["vertices"].get<size_t>();
    triangles += built.metrics["triangles"].get<size_t>();
    built.metrics["part"] = k;
    parts.push_back(std::move(built.metrics));
    built.glb.extras = nlohmann::json::object();
    meshes.push_back(std::move(built.glb));
  }
  MorphAsset asset;
  asset.metrics = {{"vertices", vertices},
                   {"triangles", triangles},
                   {"animation_seconds", seconds},
                   {"kept_appearance", false},
                   {"parts", parts}};
  // The wrapped parts carry _DISTANCE (each relative to its own original faces'
  // diagonal); the others are their original faces, at distance 0.
  if (wrapped > 0)
    asset.metrics["vertex_distances"] = {{"attribute", "_DISTANCE"},
                                         {"relative_to", "each wrapped part's original faces"},
                                         {"max", max_distance},
                                         {"wrapped_parts", wrapped},
                                         {"seconds", distance_seconds}};
  GlbParts glb = build_glb(meshes, part_nodes(meshes.size()));
  glb.json["meshes"][0]["extras"] = {{"spheremap_morph", without_timings(asset.metrics)}};
  asset.glb = serialize_glb(glb);
  asset.metrics["seconds"] = seconds_since(start);
  return asset;
}

}  // namespace spheremap
