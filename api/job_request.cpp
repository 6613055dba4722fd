#include "api/job_request.h"

#include <algorithm>
#include <map>

#include "api/job_options.h"
#include "api/problem.h"
#include "core/io/bounded_json.h"
#include "core/mesh/input_error.h"
#include "core/outputs/base_color_bake.h"
#include "core/outputs/report_json.h"

namespace spheremap::api {
namespace {

const char* const kAccepted =
    "model/gltf-binary (a .glb), model/gltf+json (a .gltf with embedded buffers), or "
    "multipart/form-data with a 'mesh' file part, an optional 'options' JSON part and, for a "
    ".gltf with external files, one part per file named by its URI";

const char* const kHowToSendResources =
    "send the .gltf as the 'mesh' part of a multipart/form-data upload and each file it names "
    "as one more part named by its URI, e.g. curl -F mesh=@scene.gltf -F scene.bin=@scene.bin";

// The detail's last sentence for a fix, in the job options' words.
std::string option_hint(const Fix& fix) {
  return "; the job option \"" + fix.option + "\": " + fix.value + " (or ?" + fix.option + "=" +
         fix.value + ") " + fix.effect;
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
  std::string format;
  std::map<std::string, std::string_view> resources;
  nlohmann::json options = nlohmann::json::object();
};

Body split_body(const httplib::Request& request) {
  const std::string type = media_type(request);
  Body body;
  if (type == "model/gltf-binary" || type == "application/octet-stream") {
    body.mesh = request.body;
  } else if (type == "model/gltf+json") {
    body.mesh = request.body;
  } else if (type == "multipart/form-data") {
    if (!request.has_file("mesh"))
      throw Problem(400, "missing_mesh", "No mesh in the form",
                    "the multipart body has no 'mesh' part; send the file as -F mesh=@FILE.glb");
    const auto& part = request.files.find("mesh")->second;
    body.mesh = part.content;
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
                      "; send " + kAccepted);
  }
  if (body.mesh.empty())
    throw Problem(400, "empty_body", "Empty mesh", "the request carries no mesh bytes");
  const bool binary = body.mesh.size() >= 4 && body.mesh.substr(0, 4) == "glTF";
  body.format = binary ? "glb" : "gltf";
  // Query parameters add to (and override) the options part.
  nlohmann::json query = options_from_query(request.params);
  for (const auto& [key, value] : query.items()) body.options[key] = value;
  return body;
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
  try {
    const MemoryResources resources(std::move(body.resources), kHowToSendResources);
    spec->input = read_gltf({reinterpret_cast<const uint8_t*>(body.mesh.data()), body.mesh.size()},
                            options.gltf, &stats, &resources, &spec->look);
  } catch (const InputError& e) {
    if (e.check() == "stopped") deadline.check("reading part of the glTF");
    nlohmann::json extra = {{"check", e.check()}};
    if (!e.fix().empty()) extra["fix"] = fix_json(e.fix());
    const std::string hint = e.fix().empty() ? "" : option_hint(e.fix());
    if (e.check() == "too_large")
      throw Problem(413, "too_large", "Mesh too large", e.what(), extra);
    if (e.check() == "missing_resources")
      throw Problem(422, "missing_resources", "Files of the glTF are missing", e.what(), extra);
    if (e.check() == "instancing")
      throw Problem(422, "not_mappable", "Mesh cannot be mapped", e.what() + hint, extra);
    throw Problem(400, "malformed_gltf", "Malformed glTF", e.what() + hint, extra);
  }
  deadline.check("reading the glTF");
  options.prepare.should_stop = options.gltf.should_stop;
  try {
    spec->prepared = prepare_mesh(spec->input, options.prepare);
  } catch (const InputError& e) {
    if (e.check() == "stopped") deadline.check("part of the weld");
    throw;
  }
  deadline.check("welding and the topology checks");
  const auto failures = input_failures(spec->prepared, &stats);
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
    const size_t pixels = base_color_pixels(spec->look);
    if (pixels > config.max_image_pixels)
      throw Problem(413, "too_large", "Textures too large",
                    "the remesh's colour bake would decode " + std::to_string(pixels) +
                        " pixels of base-colour images, over max_image_pixels (" +
                        std::to_string(config.max_image_pixels) +
                        "); ask for the other outputs, or send smaller textures",
                    {{"check", "image_pixels"}});
  }
  spec->map = options.map;
  spec->layout = options.layout;
  spec->draco_position_bits = options.draco_position_bits;
  spec->outputs = options.outputs;
  spec->remesh_resolution = options.remesh_resolution;
  spec->input_bytes = body.mesh.size();
  spec->input_format = body.format;
  spec->options_echo = body.options;
  return spec;
}

}  // namespace spheremap::api
