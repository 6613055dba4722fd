// libFuzzer target: a job submission as the HTTP layer hands it to the service: the
// Content-Type, the query parameters, the body, and for multipart/form-data the parts
// (the mesh, the options, a .gltf's files), through read_job_request. Any input must end
// in a job spec or a 4xx problem, never a crash, a hang or another exception.
//
// Input layout (so that the fuzzer can reach every branch): byte 0 picks the content type;
// then the query string up to the first '\n'; then the body. For multipart, the body is
// split on "\n--\n" into parts: the first is the mesh, one starting with "{" the options,
// the others files named by their first line.
#include <cstddef>
#include <cstdint>
#include <string>

#include "api/job_request.h"
#include "api/problem.h"

namespace {

const char* const kTypes[] = {"model/gltf-binary", "model/gltf+json", "multipart/form-data",
                              "application/octet-stream", "application/x-www-form-urlencoded", "",
                              // Appended, so that the seeds' first bytes keep their types.
                              "model/obj", "model/stl", "application/ply", "model/off",
                              "text/plain"};

void add_query(httplib::Request& request, const std::string& query) {
  size_t start = 0;
  while (start <= query.size()) {
    const size_t end = std::min(query.find('&', start), query.size());
    const std::string pair = query.substr(start, end - start);
    const size_t equals = pair.find('=');
    request.params.emplace(pair.substr(0, equals),
                           equals == std::string::npos ? "" : pair.substr(equals + 1));
    start = end + 1;
  }
}

void add_parts(httplib::Request& request, const std::string& body) {
  size_t start = 0;
  for (int part = 0; start <= body.size() && part < 64; ++part) {
    const size_t end = std::min(body.find("\n--\n", start), body.size());
    const std::string content = body.substr(start, end - start);
    if (part == 0) {
      request.files.emplace("mesh", httplib::MultipartFormData{"mesh", content, "mesh.glb", ""});
    } else if (!content.empty() && content.front() == '{') {
      request.files.emplace("options",
                            httplib::MultipartFormData{"options", content, "", "application/json"});
    } else {
      const size_t newline = std::min(content.find('\n'), content.size());
      const std::string name = content.substr(0, newline);
      request.files.emplace(name, httplib::MultipartFormData{
                                      name, content.substr(std::min(newline + 1, content.size())),
                                      name, "application/octet-stream"});
    }
    start = end + 4;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string input(reinterpret_cast<const char*>(data) + 1, size - 1);
  httplib::Request request;
  const std::string type = kTypes[data[0] % (sizeof kTypes / sizeof kTypes[0])];
  if (!type.empty()) request.headers.emplace("Content-Type", type);
  const size_t newline = std::min(input.find('\n'), input.size());
  add_query(request, input.substr(0, newline));
  const std::string body = input.substr(std::min(newline + 1, input.size()));
  if (type == "multipart/form-data")
    add_parts(request, body);
  else
    request.body = body;
  spheremap::api::ApiSettings config;
  config.max_vertices = 200000;  // the fuzzer's memory cap, not the service's
  config.max_faces = 400000;
  try {
    const spheremap::api::IntakeDeadline no_deadline(
        spheremap::api::IntakeDeadline::Clock::time_point::max(), 0);
    spheremap::api::read_job_request(request, config, no_deadline);
  } catch (const spheremap::api::Problem& problem) {
    if (problem.status < 400 || problem.status >= 500) __builtin_trap();
  }
  return 0;
}
