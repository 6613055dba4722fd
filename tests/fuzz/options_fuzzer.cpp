// libFuzzer target: the job options a client sends (the `options` JSON part, or query
// parameters), through the same parser as the service. Any input must end in options or
// a 400 problem, never a crash, a hang or another exception.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include "api/job_options.h"
#include "api/problem.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const nlohmann::json options = nlohmann::json::parse(text, nullptr, false);
  try {
    spheremap::api::parse_job_options(options.is_discarded() ? nlohmann::json(text) : options);
  } catch (const spheremap::api::Problem& problem) {
    if (problem.status != 400) __builtin_trap();
  }
  // The same text as query parameters: key=value pairs split on '&'.
  std::multimap<std::string, std::string> params;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find('&', start), text.size());
    const std::string pair = text.substr(start, end - start);
    const size_t equals = pair.find('=');
    params.emplace(pair.substr(0, equals),
                   equals == std::string::npos ? "" : pair.substr(equals + 1));
    start = end + 1;
  }
  try {
    spheremap::api::parse_job_options(spheremap::api::options_from_query(params));
  } catch (const spheremap::api::Problem& problem) {
    if (problem.status != 400) __builtin_trap();
  }
  return 0;
}
