#include "server/worker_protocol.h"

#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace spheremap::server {
namespace {

// '2': the requests carry the input's warnings (a worker of the other format refuses them).
// '3': and the handles closed in preparation. '6': and the envelopes the intake left to
// the worker (PendingEnvelopes). '7': and the triangles preparation added (holes filled,
// handles closed: PreparedMesh::filled, which the map weighs down) and the vertices the
// fills' refinement added.
constexpr char kMagic[4] = {'S', 'M', 'W', '7'};

static_assert(std::is_trivially_copyable_v<MapOptions>, "MapOptions travels as bytes");
static_assert(std::is_trivially_copyable_v<Vec3>, "positions travel as bytes");
static_assert(std::is_trivially_copyable_v<EnvelopeOptions>, "EnvelopeOptions travel as bytes");

class Writer {
 public:
  template <typename T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    out_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  template <typename T>
  void put_vector(const std::vector<T>& values) {
    put<uint64_t>(values.size());
    if (values.empty()) return;  // data() may be null
    out_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  void put_string(const std::string& text) {
    put<uint64_t>(text.size());
    out_ += text;
  }
  void put_mesh(const PolygonMesh& mesh) {
    put_vector(mesh.positions);
    put_vector(mesh.offsets);
    put_vector(mesh.indices);
  }
  void put_look(const GltfAppearance& look) {
    nlohmann::json primitives = nlohmann::json::array();
    for (const auto& p : look.primitives)
      primitives.push_back({p.node, p.material, p.mesh_name, p.first_vertex, p.vertex_count,
                            p.first_face, p.face_count, p.world, p.mirrored, p.attributes});
    const nlohmann::json json = {{"materials", look.materials},
                                 {"textures", look.textures},
                                 {"samplers", look.samplers},
                                 {"cameras", look.cameras},
                                 {"images", look.images},
                                 {"used", look.extensions_used},
                                 {"required", look.extensions_required},
                                 {"nodes", look.nodes},
                                 {"scene_nodes", look.scene_nodes},
                                 {"scene_name", look.scene_name},
                                 {"primitives", primitives}};
    put_string(json.dump());
    // Each distinct image's bytes once, then which one each image uses.
    put<uint64_t>(look.image_data.size());
    for (const std::string& bytes : look.image_data) put_string(bytes);
    put_vector(look.image_source);
    put<uint64_t>(look.attributes.size());
    for (const auto& a : look.attributes) {
      put_string(a.name);
      put<int32_t>(a.components);
      put_vector(a.values);
    }
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

class Reader {
 public:
  explicit Reader(const std::string& bytes) : bytes_(bytes) {}
  template <typename T>
  T get() {
    T value;
    take(&value, sizeof(T));
    return value;
  }
  template <typename T>
  std::vector<T> get_vector() {
    const uint64_t count = get<uint64_t>();
    if (count > (bytes_.size() - at_) / sizeof(T)) throw std::runtime_error("truncated request");
    std::vector<T> values(count);
    take(values.data(), count * sizeof(T));
    return values;
  }
  std::string get_string() {
    const std::vector<char> chars = get_vector<char>();
    return {chars.begin(), chars.end()};
  }
  PolygonMesh get_mesh() {
    PolygonMesh mesh;
    mesh.positions = get_vector<Vec3>();
    mesh.offsets = get_vector<uint32_t>();
    mesh.indices = get_vector<uint32_t>();
    return mesh;
  }
  GltfAppearance get_look() {
    GltfAppearance look;
    const nlohmann::json json = nlohmann::json::parse(get_string());
    look.materials = json.at("materials");
    look.textures = json.at("textures");
    look.samplers = json.at("samplers");
    look.cameras = json.at("cameras");
    look.images = json.at("images");
    look.extensions_used = json.at("used").get<std::vector<std::string>>();
    look.extensions_required = json.at("required").get<std::vector<std::string>>();
    look.nodes = json.at("nodes");
    look.scene_nodes = json.at("scene_nodes").get<std::vector<size_t>>();
    look.scene_name = json.at("scene_name").get<std::string>();
    for (const auto& p : json.at("primitives"))
      look.primitives.push_back({p[0].get<int64_t>(), p[1].get<int64_t>(), p[2].get<std::string>(),
                                 p[3].get<uint32_t>(), p[4].get<uint32_t>(), p[5].get<uint32_t>(),
                                 p[6].get<uint32_t>(), p[7].get<Matrix4>(), p[8].get<bool>(),
                                 p[9].get<std::vector<std::string>>()});
    const uint64_t images = get<uint64_t>();
    if (images > json.at("images").size()) throw std::runtime_error("bad image count");
    for (uint64_t i = 0; i < images; ++i) look.image_data.push_back(get_string());
    look.image_source = get_vector<size_t>();
    if (look.image_source.size() != look.images.size()) throw std::runtime_error("bad images");
    for (const size_t data : look.image_source)
      if (data >= images && data != GltfAppearance::kNoImageData)
        throw std::runtime_error("bad image source");
    const uint64_t attributes = get<uint64_t>();
    if (attributes > 16) throw std::runtime_error("bad attribute count");
    for (uint64_t i = 0; i < attributes; ++i) {
      GltfAppearance::Attribute a;
      a.name = get_string();
      a.components = get<int32_t>();
      a.values = get_vector<float>();
      look.attributes.push_back(std::move(a));
    }
    return look;
  }
  bool done() const { return at_ == bytes_.size(); }

 private:
  void take(void* out, size_t size) {
    if (size > bytes_.size() - at_) throw std::runtime_error("truncated request");
    if (size == 0) return;  // an empty vector's data() may be null: memcpy must not see it
    std::memcpy(out, bytes_.data() + at_, size);
    at_ += size;
  }
  const std::string& bytes_;
  size_t at_ = 0;
};

void put_envelope(Writer& w, const EnvelopeReport& envelope) {
  for (double x : {envelope.diagonal, envelope.voxel_size, envelope.offset, envelope.hausdorff,
                   envelope.rms, envelope.envelope_to_original, envelope.original_to_envelope})
    w.put<double>(x);
  for (int n : envelope.grid) w.put<int32_t>(n);
  for (size_t count : {envelope.solid_voxels, envelope.handles_cut, envelope.handles_filled,
                       envelope.voxels_changed, envelope.largest_change_voxels,
                       envelope.voxel_faces, envelope.faces})
    w.put<uint64_t>(count);
  w.put_string(envelope.rule);
}

EnvelopeReport get_envelope(Reader& r) {
  EnvelopeReport envelope;
  for (double* x : {&envelope.diagonal, &envelope.voxel_size, &envelope.offset, &envelope.hausdorff,
                    &envelope.rms, &envelope.envelope_to_original, &envelope.original_to_envelope})
    *x = r.get<double>();
  for (int& n : envelope.grid) n = r.get<int32_t>();
  for (size_t* count : {&envelope.solid_voxels, &envelope.handles_cut, &envelope.handles_filled,
                        &envelope.voxels_changed, &envelope.largest_change_voxels,
                        &envelope.voxel_faces, &envelope.faces})
    *count = r.get<uint64_t>();
  envelope.rule = r.get_string();
  if (envelope.rule.size() > 8) throw std::runtime_error("unknown envelope rule");
  return envelope;
}

void put_failures(Writer& w, const std::vector<ValidationFailure>& failures) {
  w.put<uint64_t>(failures.size());
  for (const ValidationFailure& f : failures) {
    w.put_string(f.check);
    w.put_string(f.message);
  }
}

// Each failure is one of a dozen checks.
std::vector<ValidationFailure> get_failures(Reader& r) {
  const uint64_t count = r.get<uint64_t>();
  if (count > 16) throw std::runtime_error("too many failures of a part");
  std::vector<ValidationFailure> failures;
  for (uint64_t i = 0; i < count; ++i) {
    std::string check = r.get_string();
    failures.emplace_back(std::move(check), r.get_string());
  }
  return failures;
}

}  // namespace

std::string encode_request(const JobSpec& spec, double time_limit_seconds, int threads) {
  Writer w;
  for (char c : kMagic) w.put(c);
  w.put<uint64_t>(sizeof(MapOptions));
  w.put(spec.map);
  w.put<int32_t>(static_cast<int32_t>(spec.layout));
  w.put<int32_t>(spec.draco_position_bits);
  w.put<int32_t>(spec.remesh_resolution);
  w.put<int32_t>(spec.normal_map ? 1 : 0);
  w.put<int32_t>(threads);
  w.put<double>(time_limit_seconds);
  w.put<uint64_t>(spec.outputs.size());
  for (const std::string& output : spec.outputs) w.put_string(output);
  w.put<uint64_t>(spec.input_warnings.size());
  for (const std::string& warning : spec.input_warnings) w.put_string(warning);
  w.put_mesh(spec.input);
  w.put_look(spec.look);
  w.put_mesh(spec.prepared.welded.mesh);
  w.put_vector(spec.prepared.welded.input_to_welded);
  w.put<uint64_t>(spec.prepared.welded.unreferenced_vertices);
  const PreparationReport& preparation = spec.prepared.preparation;
  w.put<int32_t>(static_cast<int32_t>(preparation.method));
  for (size_t count :
       {preparation.input_faces, preparation.collapsed_faces, preparation.shortened_faces,
        preparation.duplicate_faces, preparation.flipped_faces, preparation.reoriented_parts,
        preparation.holes_filled, preparation.faces_added, preparation.holes_left,
        preparation.handles_closed, preparation.handles_left, preparation.vertices_split,
        preparation.t_junctions_zipped, preparation.vertices_added, preparation.edges_split,
        preparation.sheets_doubled, preparation.open_parts_cut, preparation.handles_opened,
        preparation.walls_doubled})
    w.put<uint64_t>(count);
  w.put<double>(preparation.largest_fill);
  w.put<double>(preparation.weld_tolerance);
  w.put<double>(preparation.largest_handle_cycle);
  w.put<double>(preparation.farthest_handle_fill);
  w.put_string(preparation.handles_stopped);
  put_envelope(w, preparation.envelope);
  w.put_string(preparation.decided);
  w.put<uint64_t>(spec.prepared.parts.size());
  for (const PartReport& part : spec.prepared.parts) {
    w.put<uint64_t>(part.vertices);
    w.put<uint64_t>(part.faces);
    put_failures(w, part.failures);
    w.put<uint32_t>(part.welded_vertex);
    w.put<uint8_t>(part.wrapped ? 1 : 0);
    if (part.wrapped) {
      put_failures(w, part.wrap_reasons);
      put_envelope(w, part.envelope);
      w.put_vector(part.original_faces);
    }
  }
  // A wrapped whole: the input and look it stands for (PreparedMesh::original).
  w.put<uint8_t>(spec.prepared.original ? 1 : 0);
  if (spec.prepared.original) {
    w.put_mesh(spec.prepared.original->mesh);
    w.put_look(spec.prepared.original->look);
  }
  // The envelopes the intake left to the worker (build_envelopes).
  const PendingEnvelopes& pending = spec.prepared.pending;
  w.put<int32_t>(static_cast<int32_t>(pending.method));
  w.put<uint8_t>(pending.parts ? 1 : 0);
  w.put(pending.envelope);
  w.put<double>(pending.weld_tolerance);
  w.put<uint64_t>(pending.grid_voxels);
  w.put_vector(spec.prepared.filled);
  return w.take();
}

WorkerRequest decode_request(const std::string& bytes) {
  Reader r(bytes);
  for (char c : kMagic)
    if (r.get<char>() != c) throw std::runtime_error("not a worker request");
  if (r.get<uint64_t>() != sizeof(MapOptions))
    throw std::runtime_error("the worker binary is not the server's build (MapOptions differ)");
  WorkerRequest request;
  JobSpec& spec = request.spec;
  spec.map = r.get<MapOptions>();
  spec.layout = static_cast<SphereLayout>(r.get<int32_t>());
  spec.draco_position_bits = r.get<int32_t>();
  spec.remesh_resolution = r.get<int32_t>();
  spec.normal_map = r.get<int32_t>() != 0;
  request.threads = r.get<int32_t>();
  request.time_limit_seconds = r.get<double>();
  const uint64_t outputs = r.get<uint64_t>();
  if (outputs > 16) throw std::runtime_error("too many outputs");
  spec.outputs.clear();
  for (uint64_t i = 0; i < outputs; ++i) spec.outputs.push_back(r.get_string());
  const uint64_t warnings = r.get<uint64_t>();
  if (warnings > 16) throw std::runtime_error("too many input warnings");
  spec.input_warnings.clear();
  for (uint64_t i = 0; i < warnings; ++i) spec.input_warnings.push_back(r.get_string());
  spec.input = r.get_mesh();
  spec.look = r.get_look();
  spec.prepared.welded.mesh = r.get_mesh();
  spec.prepared.welded.input_to_welded = r.get_vector<uint32_t>();
  spec.prepared.welded.unreferenced_vertices = r.get<uint64_t>();
  PreparationReport& preparation = spec.prepared.preparation;
  const int32_t method = r.get<int32_t>();
  if (method != static_cast<int32_t>(PrepareMethod::kExact) &&
      method != static_cast<int32_t>(PrepareMethod::kRepair) &&
      method != static_cast<int32_t>(PrepareMethod::kParts) &&
      method != static_cast<int32_t>(PrepareMethod::kWrap) &&
      method != static_cast<int32_t>(PrepareMethod::kAuto))
    throw std::runtime_error("unknown preparation method");
  preparation.method = static_cast<PrepareMethod>(method);
  for (size_t* count :
       {&preparation.input_faces, &preparation.collapsed_faces, &preparation.shortened_faces,
        &preparation.duplicate_faces, &preparation.flipped_faces, &preparation.reoriented_parts,
        &preparation.holes_filled, &preparation.faces_added, &preparation.holes_left,
        &preparation.handles_closed, &preparation.handles_left, &preparation.vertices_split,
        &preparation.t_junctions_zipped, &preparation.vertices_added, &preparation.edges_split,
        &preparation.sheets_doubled, &preparation.open_parts_cut, &preparation.handles_opened,
        &preparation.walls_doubled})
    *count = r.get<uint64_t>();
  preparation.largest_fill = r.get<double>();
  preparation.weld_tolerance = r.get<double>();
  preparation.largest_handle_cycle = r.get<double>();
  preparation.farthest_handle_fill = r.get<double>();
  preparation.handles_stopped = r.get_string();
  preparation.envelope = get_envelope(r);
  preparation.decided = r.get_string();
  if (preparation.decided.size() > 16) throw std::runtime_error("unknown preparation decision");
  // Each part has a face.
  const uint64_t parts = r.get<uint64_t>();
  if (parts > spec.input.face_count()) throw std::runtime_error("more parts than faces");
  for (uint64_t k = 0; k < parts; ++k) {
    PartReport part;
    part.vertices = r.get<uint64_t>();
    part.faces = r.get<uint64_t>();
    part.failures = get_failures(r);
    part.welded_vertex = r.get<uint32_t>();
    part.wrapped = r.get<uint8_t>() != 0;
    if (part.wrapped) {
      part.wrap_reasons = get_failures(r);
      part.envelope = get_envelope(r);
      part.original_faces = r.get_vector<uint32_t>();  // outputs skip faces out of range
    }
    spec.prepared.parts.push_back(std::move(part));
  }
  if (r.get<uint8_t>() != 0) {
    auto original = std::make_shared<WrappedOriginal>();
    original->mesh = r.get_mesh();
    original->look = r.get_look();
    spec.prepared.original = std::move(original);
  }
  PendingEnvelopes& pending = spec.prepared.pending;
  const int32_t pending_method = r.get<int32_t>();
  if (pending_method != static_cast<int32_t>(PrepareMethod::kExact) &&
      pending_method != static_cast<int32_t>(PrepareMethod::kWrap) &&
      pending_method != static_cast<int32_t>(PrepareMethod::kAuto))
    throw std::runtime_error("unknown pending envelope");
  pending.method = static_cast<PrepareMethod>(pending_method);
  pending.parts = r.get<uint8_t>() != 0;
  pending.envelope = r.get<EnvelopeOptions>();
  pending.weld_tolerance = r.get<double>();
  pending.grid_voxels = r.get<uint64_t>();
  // Corners of welded vertices: the map looks them up by vertex.
  spec.prepared.filled = r.get_vector<Triangle>();
  const size_t welded_vertices = spec.prepared.welded.mesh.vertex_count();
  for (const Triangle& t : spec.prepared.filled)
    for (uint32_t v : t)
      if (v >= welded_vertices) throw std::runtime_error("a filled triangle's corner out of range");
  if (!r.done()) throw std::runtime_error("trailing bytes after the request");
  spec.prepared.topology = analyze_topology(spec.prepared.welded.mesh);
  return request;
}

std::string encode_frame(FrameType type, const std::string& payload) {
  std::string frame(1, static_cast<char>(type));
  const uint64_t length = payload.size();
  frame.append(reinterpret_cast<const char*>(&length), sizeof length);
  return frame + payload;
}

std::optional<FrameReader::Frame> FrameReader::next(size_t max_payload) {
  constexpr size_t kHeader = 1 + sizeof(uint64_t);
  if (buffer_.size() - read_ < kHeader) return std::nullopt;
  uint64_t length;
  std::memcpy(&length, buffer_.data() + read_ + 1, sizeof length);
  if (length > max_payload) throw std::runtime_error("a worker frame over the size limit");
  if (buffer_.size() - read_ - kHeader < length) return std::nullopt;
  Frame frame{static_cast<FrameType>(buffer_[read_]), buffer_.substr(read_ + kHeader, length)};
  read_ += kHeader + length;
  if (read_ == buffer_.size()) buffer_.clear(), read_ = 0;
  return frame;
}

std::string progress_json(const JobProgress& p) {
  return nlohmann::json{{"stage", p.stage},       {"level", p.level},         {"levels", p.levels},
                        {"vertices", p.vertices}, {"iteration", p.iteration}, {"folds", p.folds},
                        {"energy", p.energy},     {"part", p.part},           {"parts", p.parts}}
      .dump();
}

JobProgress progress_from_json(const std::string& text) {
  const nlohmann::json j = nlohmann::json::parse(text);
  JobProgress p;
  p.stage = j.value("stage", "running");
  p.level = j.value("level", 0);
  p.levels = j.value("levels", 0);
  p.vertices = j.value("vertices", size_t{0});
  p.iteration = j.value("iteration", size_t{0});
  p.folds = j.value("folds", size_t{0});
  p.energy = j.value("energy", 0.0);
  p.part = j.value("part", size_t{0});
  p.parts = j.value("parts", size_t{0});
  return p;
}

std::string error_json(const JobError& e) {
  return nlohmann::json{
      {"status", e.status}, {"problem", e.problem}, {"title", e.title}, {"detail", e.detail}}
      .dump();
}

JobError error_from_json(const std::string& text) {
  const nlohmann::json e = nlohmann::json::parse(text);
  return JobError{e.at("status"), e.at("problem"), e.at("title"), e.at("detail")};
}

}  // namespace spheremap::server
