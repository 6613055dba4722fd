#include "server/config.h"

#include "server/redis_connection.h"

#include <unistd.h>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <fstream>
#include <sstream>
#include <thread>
#include <variant>
#include <vector>

namespace spheremap::server {
namespace {

// One setting: where it lives in ServerConfig and the values it accepts.
struct Setting {
  std::string name;
  std::variant<std::string ServerConfig::*, int ServerConfig::*, size_t ServerConfig::*,
               double ServerConfig::*>
      field;
  double min = 0, max = 0;  // numbers only
};

const std::vector<Setting>& settings() {
  static const std::vector<Setting> table = {
      {"host", &ServerConfig::host},
      {"port", &ServerConfig::port, 0, 65535},
      {"health_port", &ServerConfig::health_port, -1, 65535},
      {"queue", &ServerConfig::queue},
      {"visibility_timeout_seconds", &ServerConfig::visibility_timeout_seconds, 0.5, 3600},
      {"max_attempts", &ServerConfig::max_attempts, 1, 100},
      {"redis_payload_timeout_seconds", &ServerConfig::redis_payload_timeout_seconds, 0.1, 3600},
      {"redis_payload_timeout_seconds_per_mib",
       &ServerConfig::redis_payload_timeout_seconds_per_mib, 0, 60},
      {"workers", &ServerConfig::workers, -1, 1024},
      {"threads_per_job", &ServerConfig::threads_per_job, 0, 1024},
      {"http_threads", &ServerConfig::http_threads, 2, 1024},
      {"intake_threads", &ServerConfig::intake_threads, 0, 1024},
      {"intake_timeout_seconds", &ServerConfig::intake_timeout_seconds, 0.1, 3600},
      {"queue_capacity", &ServerConfig::queue_capacity, 0, 1e6},
      {"max_body_bytes", &ServerConfig::max_body_bytes, 1024, 4e9},
      {"max_vertices", &ServerConfig::max_vertices, 4, 1e8},
      {"max_faces", &ServerConfig::max_faces, 4, 2e8},
      {"max_envelope_voxels", &ServerConfig::max_envelope_voxels, 4096, 1e9},
      {"max_resource_bytes", &ServerConfig::max_resource_bytes, 1024, 1e11},
      {"max_image_pixels", &ServerConfig::max_image_pixels, 1, 67108864},
      {"job_time_limit_seconds", &ServerConfig::job_time_limit_seconds, 0.01, 86400},
      {"result_ttl_seconds", &ServerConfig::result_ttl_seconds, 1, 30 * 86400.0},
      {"result_memory_bytes", &ServerConfig::result_memory_bytes, 0, 1e12},
      {"max_jobs_kept", &ServerConfig::max_jobs_kept, 1, 1e7},
      {"sync_timeout_seconds", &ServerConfig::sync_timeout_seconds, 0, 3600},
      {"shutdown_grace_seconds", &ServerConfig::shutdown_grace_seconds, 0, 3600},
      {"keep_alive_timeout_seconds", &ServerConfig::keep_alive_timeout_seconds, 0, 3600},
      {"read_timeout_seconds", &ServerConfig::read_timeout_seconds, 0.1, 3600},
      {"header_timeout_seconds", &ServerConfig::header_timeout_seconds, 0.1, 3600},
      {"body_timeout_seconds", &ServerConfig::body_timeout_seconds, 0.1, 86400},
      {"max_header_count", &ServerConfig::max_header_count, 8, 10000},
      {"max_header_bytes", &ServerConfig::max_header_bytes, 1024, 1 << 20},
      {"max_connections_per_address", &ServerConfig::max_connections_per_address, 0, 1e6},
      {"max_connections", &ServerConfig::max_connections, 16, 1e6},
      {"request_buffer_bytes", &ServerConfig::request_buffer_bytes, 0, 1e12},
      {"response_min_bytes_per_second", &ServerConfig::response_min_bytes_per_second, 1, 1e12},
      {"api_keys", &ServerConfig::api_keys},
      {"tenant_max_queued", &ServerConfig::tenant_max_queued, 1, 1e6},
      {"tenant_max_running", &ServerConfig::tenant_max_running, 0, 1024},
      {"tenant_result_memory_bytes", &ServerConfig::tenant_result_memory_bytes, 0, 1e12},
      {"cors_origins", &ServerConfig::cors_origins},
      {"trusted_proxies", &ServerConfig::trusted_proxies},
      {"worker_isolation", &ServerConfig::worker_isolation},
      {"worker_executable", &ServerConfig::worker_executable},
      {"worker_memory_bytes", &ServerConfig::worker_memory_bytes, 0, 1e15},
      {"jobs_memory_bytes", &ServerConfig::jobs_memory_bytes, 0, 1e15},
      {"worker_cpu_seconds", &ServerConfig::worker_cpu_seconds, 0, 1e7},
  };
  return table;
}

const Setting& find_setting(const std::string& key, const std::string& source) {
  for (const Setting& s : settings())
    if (s.name == key) return s;
  throw ConfigError(source + ": unknown setting '" + key + "'");
}

template <typename T>
void store_number(ServerConfig& config, T ServerConfig::*field, const Setting& s, double value,
                  const std::string& source) {
  const bool integral = std::is_integral_v<T>;
  if (!(value >= s.min && value <= s.max) || (integral && value != static_cast<long long>(value))) {
    std::ostringstream message;
    message << source << ": " << s.name << " must be " << (integral ? "an integer" : "a number")
            << " in [" << s.min << ", " << s.max << "], got " << value;
    throw ConfigError(message.str());
  }
  config.*field = static_cast<T>(value);
}

void store(ServerConfig& config, const Setting& s, const nlohmann::json& value,
           const std::string& source) {
  if (auto text = std::get_if<std::string ServerConfig::*>(&s.field)) {
    if (!value.is_string()) throw ConfigError(source + ": " + s.name + " must be a string");
    if (s.name == "worker_isolation" && value != "process" && value != "thread")
      throw ConfigError(source + ": worker_isolation must be \"process\" or \"thread\"");
    if (s.name == "queue" && value != "memory://") {
      try {
        RedisAddress::parse(value.get<std::string>());
      } catch (const std::invalid_argument& e) {
        throw ConfigError(source + ": queue: " + e.what());
      }
    }
    config.*(*text) = value.get<std::string>();
    return;
  }
  if (!value.is_number()) throw ConfigError(source + ": " + s.name + " must be a number");
  const double number = value.get<double>();
  std::visit(
      [&](auto field) {
        using T = std::remove_reference_t<decltype(config.*field)>;
        if constexpr (!std::is_same_v<T, std::string>)
          store_number(config, field, s, number, source);
      },
      s.field);
}

int cores() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

}  // namespace

int ServerConfig::effective_workers() const {
  return workers >= 0 ? workers : cores();
}

int ServerConfig::effective_threads_per_job() const {
  return threads_per_job > 0 ? threads_per_job
                             : std::max(1, cores() / std::max(1, effective_workers()));
}

int ServerConfig::effective_intake_threads() const {
  return intake_threads > 0 ? intake_threads : cores();
}

size_t ServerConfig::effective_jobs_memory_bytes() const {
  if (jobs_memory_bytes > 0) return jobs_memory_bytes;
  const size_t three_quarters = ServerConfig{}.effective_worker_memory_bytes();
  return three_quarters > 0 ? three_quarters : size_t{4} << 30;
}

size_t ServerConfig::effective_worker_memory_bytes() const {
  if (worker_memory_bytes > 0) return worker_memory_bytes;
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? static_cast<size_t>(pages) / 4 * 3 * static_cast<size_t>(page) : 0;
}

double ServerConfig::effective_worker_cpu_seconds() const {
  if (worker_cpu_seconds > 0) return worker_cpu_seconds;
  return (2 * job_time_limit_seconds + 60) * effective_threads_per_job();
}

nlohmann::json ServerConfig::to_json() const {
  nlohmann::json out = nlohmann::json::object();
  for (const Setting& s : settings())
    std::visit([&](auto field) { out[s.name] = this->*field; }, s.field);
  out["workers"] = effective_workers();
  out["threads_per_job"] = effective_threads_per_job();
  out["intake_threads"] = effective_intake_threads();
  out["worker_memory_bytes"] = effective_worker_memory_bytes();
  out["jobs_memory_bytes"] = effective_jobs_memory_bytes();
  out["worker_cpu_seconds"] = effective_worker_cpu_seconds();
  return out;
}

void apply_json(ServerConfig& config, const nlohmann::json& values, const std::string& source) {
  if (!values.is_object()) throw ConfigError(source + ": settings must be a JSON object");
  for (const auto& [key, value] : values.items()) {
    if (key.starts_with("_")) continue;  // comments: "_doc", "_host", ...
    store(config, find_setting(key, source), value, source);
  }
}

void apply_setting(ServerConfig& config, const std::string& key, const std::string& value,
                   const std::string& source) {
  const Setting& s = find_setting(key, source);
  if (std::holds_alternative<std::string ServerConfig::*>(s.field)) {
    store(config, s, value, source);
    return;
  }
  double number = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
  if (error != std::errc() || end != value.data() + value.size() || value.empty())
    throw ConfigError(source + ": " + key + " must be a number, got '" + value + "'");
  store(config, s, number, source);
}

void apply_environment(ServerConfig& config,
                       const std::map<std::string, std::string>& environment) {
  for (const Setting& s : settings()) {
    std::string variable = "SPHEREMAP_" + s.name;
    std::transform(variable.begin(), variable.end(), variable.begin(),
                   [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    const auto it = environment.find(variable);
    if (it != environment.end()) apply_setting(config, s.name, it->second, variable);
  }
}

void apply_file(ServerConfig& config, const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError("cannot read the configuration file '" + path + "'");
  nlohmann::json values;
  try {
    values = nlohmann::json::parse(in, nullptr, true, /*ignore_comments=*/true);
  } catch (const nlohmann::json::parse_error& e) {
    throw ConfigError(path + ": not valid JSON (" + e.what() + ")");
  }
  apply_json(config, values, path);
}

const std::vector<std::string>& setting_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const Setting& s : settings()) out.push_back(s.name);
    return out;
  }();
  return names;
}

}  // namespace spheremap::server
