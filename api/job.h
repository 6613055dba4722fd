// One mapping job: what was asked, where it stands, and what it produced.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/map/pipeline.h"
#include "core/outputs/sphere_asset.h"

namespace spheremap::api {

enum class JobStatus { kQueued, kRunning, kSucceeded, kFailed, kCancelled };
std::string_view to_string(JobStatus status);
std::optional<JobStatus> job_status_from(std::string_view text);
inline bool is_terminal(JobStatus s) {
  return s != JobStatus::kQueued && s != JobStatus::kRunning;
}

// What a client asked for, checked and ready to run: the mesh is already read and
// prepared (welded, validated), so a job that is accepted can be mapped. An envelope
// (prepare wrap, or auto when a part cannot map) is left to the job's worker
// (prepared.pending): the intake checked that its grid fits; one that still cannot be made
// fails the job with the reason.
struct JobSpec {
  PolygonMesh input;
  GltfAppearance look;  // the input's materials, textures, attributes, nodes (outputs keep them)
  PreparedMesh prepared;
  MapOptions map;
  SphereLayout layout = SphereLayout::kOriginal;
  int draco_position_bits = 0;                    // 0 = no Draco
  std::vector<std::string> outputs = {"sphere"};  // and "remesh", "uv", "morph"
  int remesh_resolution = 256;
  bool normal_map = true;  // the remesh of an envelope: its normal map (normal_bake.h)
  size_t input_bytes = 0;
  std::string input_format;  // "glb", "gltf", "obj", "off", "stl", "ply"
  // What the reader read leniently (GltfReadStats::warnings): metrics.json "input_warnings".
  std::vector<std::string> input_warnings;
  nlohmann::json options_echo = nlohmann::json::object();  // as the client sent them (shown)
  std::string tenant;  // whose job: the API key's tenant, or the client's address
  // The client's Idempotency-Key ("" = none): a retry with the same key, by the same
  // tenant, gets the job this key made instead of a second one.
  std::string idempotency_key;
};

// An artifact's bytes, immutable once made: the job, the queue and every download share
// them, so a download costs a reference, not a copy.
using SharedBytes = std::shared_ptr<const std::string>;
SharedBytes share_bytes(std::string bytes);

struct Artifact {
  std::string name, content_type;
  SharedBytes bytes;  // null when a view lists an artifact without its bytes
  size_t size = 0;    // of bytes; also set when a view lists an artifact without its bytes
};
Artifact make_artifact(std::string name, std::string content_type, std::string bytes);

// Why a job failed, as a problem (RFC 9457) the API can return.
struct JobError {
  int status = 500;     // the HTTP status that fits
  std::string problem;  // the problem type slug ("not_bijective", "time_limit", ...)
  std::string title, detail;
};

struct JobProgress {
  std::string stage = "queued";
  int level = 0, levels = 0;
  size_t vertices = 0, iteration = 0, folds = 0;
  double energy = 0;           // stage "optimize": stretch energy per unit area (1.1 = isometric)
  size_t part = 0, parts = 0;  // several parts: the one being mapped (1-based) of how many
};

using Clock = std::chrono::steady_clock;

struct Job {
  std::string id;
  std::string tenant;  // set at submission, never changed
  Clock::time_point created = Clock::now();
  std::chrono::system_clock::time_point created_wall = std::chrono::system_clock::now();
  std::atomic<bool> cancel{false};

  mutable std::mutex mutex;  // guards everything below
  std::condition_variable finished_cv;
  JobStatus status = JobStatus::kQueued;
  std::unique_ptr<JobSpec> spec;  // released once the job ends
  size_t input_vertices = 0, input_faces = 0, input_bytes = 0;
  std::string input_format;                           // "glb", "gltf", "obj", "off", "stl" or "ply"
  nlohmann::json options = nlohmann::json::object();  // as the client sent them
  JobProgress progress;
  std::optional<Clock::time_point> started, finished;
  std::vector<Artifact> artifacts;
  // The .gltf view of a .glb artifact (by the .glb's name), built on its first request
  // and kept with the job: counted in artifact_bytes() like the artifacts.
  std::map<std::string, SharedBytes> gltf_views;
  nlohmann::json metrics;  // when succeeded
  std::optional<JobError> error;
  std::string cancel_reason;

  size_t artifact_bytes() const;  // caller holds mutex

  // Not under `mutex`: held while a .gltf view is built, so each is built once.
  std::mutex gltf_building;
};

}  // namespace spheremap::api
