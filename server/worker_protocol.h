// What the server and a worker process say to each other over a pair of pipes.
//
// The server writes one request on the worker's stdin: a job's spec (the input mesh, the
// welded mesh it was checked as, the envelopes left to build, the options) and the run
// limits, then closes it. The worker answers on its stdout with frames, each a type byte, a
// little-endian uint64 length and that many bytes: progress (JSON, as often as every 100 ms), one
// frame per artifact, the metrics, the error if any, and last the status. A worker that dies before
// its status frame has crashed; the server says so and never trusts a partial answer.
//
// Both sides are the same binary (the worker is `spheremap worker-process`, re-executed
// by the server), so the options travel as the plain struct they are; a size check in
// the request catches a worker binary from another build.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "server/api_types.h"

namespace spheremap::server {

enum class FrameType : uint8_t {
  kProgress = 'P',  // JSON: JobProgress
  kArtifact = 'A',  // JSON header line {"name", "content_type"}, '\n', then the bytes
  kMetrics = 'M',   // JSON
  kError = 'E',     // JSON: JobError
  kStatus = 'S',    // JSON: {"status": "succeeded" | "failed" | "cancelled"}
};

struct WorkerRequest {
  // input, prepared.welded (topology is recomputed), the envelopes left to build
  // (prepared.pending), options, outputs
  JobSpec spec;
  double time_limit_seconds = 300;
  int threads = 1;
};

std::string encode_request(const JobSpec& spec, double time_limit_seconds, int threads);
// Throws std::runtime_error when the bytes are not a request of this build.
WorkerRequest decode_request(const std::string& bytes);

std::string encode_frame(FrameType type, const std::string& payload);

// Frames accumulated from a stream read in pieces.
class FrameReader {
 public:
  struct Frame {
    FrameType type;
    std::string payload;
  };
  void append(const char* data, size_t size) { buffer_.append(data, size); }
  // The next complete frame, if one has arrived. Throws std::runtime_error on a frame
  // longer than `max_payload` (a worker never sends one; it would be a bug, not data).
  std::optional<Frame> next(size_t max_payload);

 private:
  std::string buffer_;
  size_t read_ = 0;
};

std::string progress_json(const JobProgress& progress);
JobProgress progress_from_json(const std::string& text);
std::string error_json(const JobError& error);
JobError error_from_json(const std::string& text);  // throws on JSON that is not one

}  // namespace spheremap::server
