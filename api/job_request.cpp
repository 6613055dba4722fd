#include "api/job_request.h"

#include <algorithm>
#include <map>

#include "api/job_options.h"
#include "api/problem.h"
#include "api/upload_format.h"
#include "core/io/bounded_json.h"
#include "core/io/mesh_format.h"
#include "core/io/stl.h"
#include "core/mesh/input_error.h"
#include "core/outputs/base_color_bake.h"
#include "core/outputs/report_json.h"

namespace spheremap::api {
namespace {

const char* const kHowToSendResources =
    "send the .gltf as the 'mesh' part of a multipart/form-data upload and each file it names "
    "as one more part named by its URI, e.g. curl -F mesh=@scene.gltf -F scene.bin=@scene.bin";

// The detail's last sentence for a fix, in the job options' words.
std::string option_hint(const Fix& fix) {
  return "; the job option \"" + fix.option + "\": " + fix.value + " (or ?" + fix.option + "=" +
         fix.plain_value() + ") " + fix.effect;
}

}  // namespace

const char* const kFormEncodedHint =
    "the body was sent as application/x-www-form-urlencoded (curl's default for "
    "--data-binary), which would mangle a binary mesh; send it with -H "
    "'Content-Type: model/gltf-binary' --data-binary @mesh.glb, or as a form with "
    "-F mesh=@mesh.glb";

namespace {

std::string media_type(const httplib::Request& request) {
  std::string type = request.get_header_value("Content-Type");
  type = type.substr(0, type.find(';'));
  type.erase(std::remove(type.begin(), type.end(), ' '), type.end());
  std::transform(type.begin(), type.end(), type.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return type;
}

// The mesh bytes, the files a .gltf names (multipart parts other than mesh and options,
// by part name and by file name) and the options JSON of the request, by content type.
struct Body {
  std::string_view mesh;
  MeshFormat format = MeshFormat::kGlb;
  std::map<std::string, std::string_view> resources;
  nlohmann::json options = nlohmann::json::object();
};

Body split_body(const httplib::Request& request) {
  const std::string type = media_type(request);
  Body body;
  if (const std::optional<MeshFormat> named = format_of_media_type(type)) {
    body.mesh = request.body;
    body.format = *named;
  } else if (type == "application/octet-stream" || type == "text/plain") {
    body.mesh = request.body;
    // Read from the bytes; what fits no format goes to the glTF reader, as it always did.
    const std::optional<MeshFormat> sniffed = sniff_mesh_format(body.mesh);
    const bool text_format = sniffed && *sniffed != MeshFormat::kGlb &&
                             *sniffed != MeshFormat::kGltf && *sniffed != MeshFormat::kDrc &&
                             !(*sniffed == MeshFormat::kStl && is_binary_stl(body.mesh));
    if (type == "text/plain" && !text_format)
      throw Problem(415, "unsupported_media_type", "Unsupported media type",
                    "a text/plain body is read as OBJ, OFF, ASCII STL or ASCII PLY, and this "
                    "one is none of them; send " +
                        std::string(kAcceptedMediaTypes));
    body.format = sniffed.value_or(MeshFormat::kGlb);
  } else if (type == "multipart/form-data") {
    if (!request.has_file("mesh"))
      throw Problem(400, "missing_mesh", "No mesh in the form",
                    "the multipart body has no 'mesh' part; send the file as -F mesh=@FILE.glb");
    const auto& part = request.files.find("mesh")->second;
    body.mesh = part.content;
    body.format = format_of_part(part.filename, part.content_type, part.content);
    for (const auto& [name, file] : request.files) {
      if (name == "mesh" || name == "options") continue;
      body.resources.emplace(name, file.content);
      if (!file.filename.empty()) body.resources.emplace(file.filename, file.content);
    }
    if (request.has_file("options")) {
      const std::string& text = request.files.find("options")->second.content;
      try {
        body.options = parse_bounded_json(text);
      } catch (const InputError& e) {
        throw Problem(400, "invalid_options", "Invalid job options",
                      std::string("the 'options' part is ") + e.what());
      }
      if (body.options.is_discarded())
        throw Problem(400, "invalid_options", "Invalid job options",
                      "the 'options' part is not valid JSON");
    }
  } else if (type == "application/x-www-form-urlencoded") {
    throw Problem(415, "unsupported_media_type", "Unsupported media type", kFormEncodedHint);
  } else {
    throw Problem(415, "unsupported_media_type", "Unsupported media type",
                  (type.empty() ? std::string("no Content-Type") : "Content-Type '" + type + "'") +
                      "; send " + kAcceptedMediaTypes);
  }
  if (body.mesh.empty())
    throw Problem(400, "empty_body", "Empty mesh", "the request carries no mesh bytes");
  // glTF either way: the reader tells GLB from JSON by the magic, and so does the job.
  if (body.format == MeshFormat::kGlb || body.format == MeshFormat::kGltf)
    body.format = body.mesh.substr(0, 4) == "glTF" ? MeshFormat::kGlb : MeshFormat::kGltf;
  // Query parameters add to (and override) the options part.
  nlohmann::json query = options_from_query(request.params);
  for (const auto& [key, value] : query.items()) body.options[key] = value;
  return body;
}

PolygonMesh read_gltf_body(Body& body, const GltfReadOptions& options, GltfReadStats& stats,
                           GltfAppearance& look) {
  try {
    const MemoryResources resources(std::move(body.resources), kHowToSendResources);
    return read_gltf({reinterpret_cast<const uint8_t*>(body.mesh.data()), body.mesh.size()},
                     options, &stats, &resources, &look);
  } catch (const InputError& e) {
    if (e.check() == "stopped") throw;  // the caller answers it as the deadline's
    nlohmann::json extra = {{"check", e.check()}};
    if (!e.fix().empty()) extra["fix"] = fix_json(e.fix());
    const std::string hint = e.fix().empty() ? "" : option_hint(e.fix());
    if (e.check() == "too_large")
      throw Problem(413, "too_large", "Mesh too large", e.what(), extra);
    if (e.check() == "missing_resources")
      throw Problem(422, "missing_resources", "Files of the glTF are missing", e.what(), extra);
    if (e.check() == "instancing" || e.check() == "empty")  // empty: points or lines only
      throw Problem(422, "not_mappable", "Mesh cannot be mapped", e.what() + hint, extra);
    // Sent as glTF but another format's bytes: say which type to send.
    std::string other;
    const std::optional<MeshFormat> sniffed = sniff_mesh_format(body.mesh);
    if (sniffed && *sniffed != MeshFormat::kGlb && *sniffed != MeshFormat::kGltf)
      other = std::string("; the bytes look like ") + format_name(*sniffed) +
              ": send them with their own Content-Type (" + kAcceptedMediaTypes + ")";
    throw Problem(400, "malformed_gltf", "Malformed glTF", e.what() + hint + other, extra);
  }
}

void check_vertex_cap(size_t vertices, const ApiSettings& config, const char* when) {
  if (vertices > config.max_vertices)
    throw Problem(413, "too_large", "Mesh too large",
                  "the mesh has " + std::to_string(vertices) + " vertices " + when +
                      ", over max_vertices (" + std::to_string(config.max_vertices) + ")",
                  {{"check", "too_large"}});
}

// OBJ, OFF, STL, PLY or raw Draco: the reader checks every count against the bytes and
// the caps (STL, PLY and Draco before allocating). max_faces counts triangles, as glTF's; an STL's
// vertices are capped once welded (3 per triangle before).
PolygonMesh read_other_body(const Body& body, const ApiSettings& config) {
  MeshLimits limits;
  limits.max_triangles = config.max_faces;
  if (body.format != MeshFormat::kStl) limits.max_vertices = config.max_vertices;
  try {
    return parse_mesh_text(body.mesh, body.format, limits);
  } catch (const InputError& e) {
    if (e.check() == "too_large")
      throw Problem(413, "too_large", "Mesh too large",
                    std::string(e.what()) + " (max_vertices, max_faces)", {{"check", e.check()}});
    if (e.check() == "empty")  // a Draco point cloud: read, but nothing to map
      throw Problem(422, "not_mappable", "Mesh cannot be mapped", e.what(), {{"check", e.check()}});
    throw Problem(400, "malformed_mesh", "Malformed mesh", e.what(), {{"check", e.check()}});
  }
}

}  // namespace

std::unique_ptr<JobSpec> read_job_request(const httplib::Request& request,
                                          const ApiSettings& config,
                                          const IntakeDeadline& deadline) {
  Body body = split_body(request);
  JobOptions options = parse_job_options(body.options);
  options.gltf.max_vertices = config.max_vertices;
  options.gltf.max_triangles = config.max_faces;
  // Read once per source, buffers and images never need more than twice the body (its
  // buffers, and images copied out of them); more would mean a duplicating reference.
  size_t sent = request.body.size();  // empty for multipart: its parts are in `files`
  for (const auto& [name, part] : request.files) sent += part.content.size();
  options.gltf.max_resource_bytes = std::min(config.max_resource_bytes, 2 * sent + (1u << 20));
  // The reader asks while it works, so an intake thread is freed within a second of the
  // deadline (or of a shutdown), not at the end of the stage.
  options.gltf.should_stop = [&deadline] { return deadline.passed(); };

  auto spec = std::make_unique<JobSpec>();
  GltfReadStats stats;
  const bool gltf = body.format == MeshFormat::kGlb || body.format == MeshFormat::kGltf;
  try {
    if (gltf)
      spec->input = read_gltf_body(body, options.gltf, stats, spec->look);
    else
      spec->input = read_other_body(body, config);
  } catch (const InputError& e) {
    if (e.check() == "stopped")
      deadline.check(gltf ? "reading part of the glTF" : "reading part of the mesh");
    throw;
  }
  deadline.check(gltf ? "reading the glTF" : "reading the mesh");
  options.prepare.should_stop = options.gltf.should_stop;
  // The envelope's grid is built in the server (in the job's worker): its size is the
  // server's to bound.
  options.prepare.envelope.max_voxels =
      std::min(options.prepare.envelope.max_voxels, config.max_envelope_voxels);
  // Envelopes take seconds and hundreds of MB: the intake only checks that the grid fits,
  // and the job's worker builds them under its time limit and memory charge.
  options.prepare.defer_envelopes = true;
  try {
    spec->prepared = prepare_input(spec->input, &spec->look, options.prepare);
  } catch (const InputError& e) {
    if (e.check() == "stopped") {
      deadline.check("preparing the mesh");
      throw;
    }
    // What preparation itself refuses: an envelope it cannot make (prepare wrap: a grid
    // over max_envelope_voxels, no triangle to wrap), known before one is built.
    throw Problem(422, "not_mappable", "Mesh cannot be mapped", e.what(), {{"check", e.check()}});
  }
  deadline.check("welding and the topology checks");
  // An STL has three vertices per triangle until welded: its vertex cap is on the welded.
  if (body.format == MeshFormat::kStl)
    check_vertex_cap(spec->prepared.welded.mesh.vertex_count(), config, "after welding");
  // An envelope left to the worker is what makes the input map: nothing to refuse here.
  const auto failures = spec->prepared.pending.any() ? std::vector<ValidationFailure>{}
                                                     : input_failures(spec->prepared, &stats);
  if (!failures.empty()) {
    nlohmann::json list = nlohmann::json::array();
    std::string detail;
    Fix fix;
    for (const auto& f : failures) {
      list.push_back({{"check", f.check}, {"message", f.message}});
      if (!f.fix.empty()) list.back()["fix"] = fix_json(f.fix);
      if (fix.empty()) fix = f.fix;
      detail += (detail.empty() ? "" : "; ") + f.message;
    }
    nlohmann::json extra = {{"check", failures.front().check},
                            {"failures", list},
                            {"topology", topology_json(spec->prepared, &stats)}};
    if (!fix.empty()) extra["fix"] = fix_json(fix), detail += option_hint(fix);
    throw Problem(422, "not_mappable", "Mesh cannot be mapped", detail, extra);
  }
  if (std::count(options.outputs.begin(), options.outputs.end(), "remesh")) {
    // Counted from the images' headers now, so that the colour bake cannot fail later.
    const GltfAppearance& baked_look =
        spec->prepared.original ? spec->prepared.original->look : spec->look;
    const size_t pixels = base_color_pixels(baked_look);
    if (pixels > config.max_image_pixels)
      throw Problem(413, "too_large", "Textures too large",
                    "the remesh's colour bake would decode " + std::to_string(pixels) +
                        " pixels of base-colour images, over max_image_pixels (" +
                        std::to_string(config.max_image_pixels) +
                        "); ask for the other outputs, or send smaller textures",
                    {{"check", "image_pixels"}});
    if (base_color_jpeg_scans(baked_look) > kMaxJpegScans)
      throw Problem(422, "jpeg_scans", "Texture cannot be decoded",
                    "a base-colour JPEG has over " + std::to_string(kMaxJpegScans) +
                        " scans (progressive passes), too many to decode in time; ask for the "
                        "other outputs, or send the texture as a baseline JPEG or a PNG",
                    {{"check", "jpeg_scans"}});
  }
  spec->map = options.map;
  spec->layout = options.layout;
  spec->draco_position_bits = options.draco_position_bits;
  spec->outputs = options.outputs;
  spec->remesh_resolution = options.remesh_resolution;
  spec->normal_map = options.normal_map;
  spec->input_bytes = body.mesh.size();
  spec->input_format = format_name(body.format);
  spec->input_warnings = stats.warnings;
  spec->options_echo = body.options;
  return spec;
}

}  // namespace spheremap::api
