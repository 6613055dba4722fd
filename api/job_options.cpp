#include "api/job_options.h"

#include <algorithm>
#include <functional>
#include <map>
#include <sstream>

#include "api/problem.h"
#include "core/io/bounded_json.h"
#include "core/mesh/input_error.h"

namespace spheremap::api {
namespace {

// A value as JSON text for a message; invalid UTF-8 (a client's bytes) is replaced, not
// thrown (found by tests/fuzz/options_fuzzer), and long values are cut.
// Never the whole value: a client's option can be megabytes or nested 60,000 deep.
std::string shown(const nlohmann::json& value) {
  return describe_json(value);
}

[[noreturn]] void invalid(const std::string& detail) {
  throw Problem(400, "invalid_options", "Invalid job options", detail);
}

double number(const nlohmann::json& value, const std::string& key, double min, double max) {
  if (!value.is_number() || !(value.get<double>() >= min && value.get<double>() <= max)) {
    std::ostringstream detail;
    detail << "option '" << key << "' must be a number in [" << min << ", " << max << "], got "
           << shown(value);
    invalid(detail.str());
  }
  return value.get<double>();
}

long long integer(const nlohmann::json& value, const std::string& key, long long min,
                  long long max) {
  const double x = number(value, key, static_cast<double>(min), static_cast<double>(max));
  if (x != static_cast<double>(static_cast<long long>(x)))
    invalid("option '" + key + "' must be an integer, got " + shown(value));
  return static_cast<long long>(x);
}

bool boolean(const nlohmann::json& value, const std::string& key) {
  if (!value.is_boolean())
    invalid("option '" + key + "' must be true or false, got " + shown(value));
  return value.get<bool>();
}

std::string text(const nlohmann::json& value, const std::string& key,
                 std::initializer_list<const char*> allowed) {
  if (value.is_string())
    for (const char* a : allowed)
      if (value.get<std::string>() == a) return a;
  std::string list;
  for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
  invalid("option '" + key + "' must be one of " + list + ", got " + shown(value));
}

std::vector<std::string> outputs(const nlohmann::json& value) {
  std::vector<std::string> names;
  if (value.is_string()) {
    std::stringstream list(value.get<std::string>());
    for (std::string name; std::getline(list, name, ',');) names.push_back(name);
  } else if (value.is_array()) {
    for (const auto& v : value) {
      if (!v.is_string()) invalid("option 'outputs' must list names, got " + shown(value));
      names.push_back(v.get<std::string>());
    }
  } else {
    invalid("option 'outputs' must be a list of names, got " + shown(value));
  }
  const auto& known = available_outputs();
  for (const std::string& name : names)
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      invalid("option 'outputs': unknown output '" + name + "'; available: " + list);
    }
  if (std::find(names.begin(), names.end(), "sphere") == names.end())
    names.insert(names.begin(), "sphere");  // the map itself is always made
  return names;
}

}  // namespace

const std::vector<std::string>& available_outputs() {
  static const std::vector<std::string> names = {"sphere", "remesh", "uv", "morph"};
  return names;
}

JobOptions parse_job_options(const nlohmann::json& options) {
  if (!options.is_object()) invalid("options must be a JSON object, got " + shown(options));
  JobOptions out;
  // The method first: it sets the defaults the other options then override.
  if (options.contains("method") &&
      text(options["method"], "method", {"coarse-to-fine", "paper"}) == "paper") {
    out.map.method = Method::kPaper;
    out.map.smoothing.placement = OffsetPlacement::kPaper;
    out.map.smoothing.limit_weight = 1.0;
  }
  bool draco = false;
  using Json = nlohmann::json;
  using Setter = std::function<void(const Json&, const std::string&)>;
  const std::map<std::string, Setter> setters = {
      {"method", [](const Json&, const std::string&) {}},
      {"quality",
       [&](const Json& v, const std::string& k) {
         out.map.quality = *parse_quality(text(v, k, {"fast", "standard", "high"}));
       }},
      {"alpha", [&](const Json& v, const std::string& k) { out.map.alpha = number(v, k, 0, 1); }},
      {"offset", [&](const Json& v,
                     const std::string& k) { out.map.smoothing.offset = number(v, k, 0, 0.5); }},
      {"limit_weight",
       [&](const Json& v, const std::string& k) {
         out.map.smoothing.limit_weight = number(v, k, 0, 1);
       }},
      {"min_iterations",
       [&](const Json& v, const std::string& k) {
         out.map.min_level_iterations = static_cast<size_t>(integer(v, k, 0, 1000000));
       }},
      {"max_iterations",
       [&](const Json& v, const std::string& k) {
         out.map.max_iterations = static_cast<size_t>(integer(v, k, 0, 1000000));
       }},
      {"attempts",
       [&](const Json& v, const std::string& k) {
         out.map.attempts = static_cast<size_t>(integer(v, k, 1, 16));
       }},
      {"time_limit_seconds",
       [&](const Json& v, const std::string& k) {
         out.map.time_limit_seconds = number(v, k, 0.01, 86400);
       }},
      {"weld_tolerance",
       [&](const Json& v, const std::string& k) {
         out.prepare.weld_tolerance = number(v, k, 0, 1);
       }},
      {"prepare",
       [&](const Json& v, const std::string& k) {
         const std::string method = text(v, k, {"exact", "repair", "parts", "wrap", "auto"});
         out.prepare.method = method == "exact"    ? PrepareMethod::kExact
                              : method == "repair" ? PrepareMethod::kRepair
                              : method == "wrap"   ? PrepareMethod::kWrap
                              : method == "auto"   ? PrepareMethod::kAuto
                                                   : PrepareMethod::kParts;
       }},
      {"wrap_resolution",
       [&](const Json& v, const std::string& k) {
         out.prepare.envelope.resolution = number(v, k, 8, 4096);
       }},
      {"wrap_offset",
       [&](const Json& v, const std::string& k) {
         out.prepare.envelope.offset_fraction = number(v, k, 0, 0.25);
       }},
      {"wrap_faces",
       [&](const Json& v, const std::string& k) {
         out.prepare.envelope.target_faces = static_cast<size_t>(integer(v, k, 0, 10000000));
       }},
      {"max_hole_fill",
       [&](const Json& v, const std::string& k) {
         out.prepare.max_hole_fill = number(v, k, 0, 1);
       }},
      {"max_handle_cycle",
       [&](const Json& v, const std::string& k) {
         out.prepare.max_handle_cycle = number(v, k, 0, 1000);
       }},
      {"largest_component",
       [&](const Json& v, const std::string& k) { out.prepare.largest_component = boolean(v, k); }},
      {"draco", [&](const Json& v, const std::string& k) { draco = boolean(v, k); }},
      {"normal_map", [&](const Json& v, const std::string& k) { out.normal_map = boolean(v, k); }},
      {"draco_position_bits",
       [&](const Json& v, const std::string& k) {
         // Above 20 bits Draco's encoder allocates per quantization cell (measured: 30
         // bits cost 4 GB for a 12-triangle box), and float32 has 24 bits anyway.
         out.draco_position_bits = static_cast<int>(integer(v, k, 8, 20));
       }},
      {"layout",
       [&](const Json& v, const std::string& k) {
         out.layout = text(v, k, {"original", "welded"}) == "welded" ? SphereLayout::kWelded
                                                                     : SphereLayout::kOriginal;
       }},
      {"mesh",
       [&](const Json& v, const std::string& k) {
         if (v.is_string())
           out.gltf.mesh_name = v.get<std::string>();
         else
           out.gltf.mesh_index = static_cast<int>(integer(v, k, 0, 1 << 30));
       }},
      {"outputs", [&](const Json& v, const std::string&) { out.outputs = outputs(v); }},
      {"resolution",
       [&](const Json& v, const std::string& k) {
         out.remesh_resolution = static_cast<int>(integer(v, k, 2, 1024));
         if (out.remesh_resolution % 2)
           invalid("option 'resolution' must be even, got " + shown(v));
       }},
  };
  for (const auto& [key, value] : options.items()) {
    const auto setter = setters.find(key);
    if (setter == setters.end()) invalid("unknown option '" + key + "'");
    setter->second(value, key);
  }
  if (!draco)
    out.draco_position_bits = 0;
  else if (out.draco_position_bits == 0)
    out.draco_position_bits = kDracoBitsAutomatic;
  return out;
}

nlohmann::json options_from_query(const std::multimap<std::string, std::string>& params) {
  nlohmann::json options = nlohmann::json::object();
  for (const auto& [key, value] : params) {
    nlohmann::json parsed;
    try {
      parsed = parse_bounded_json(value);
    } catch (const InputError&) {
      parsed = nlohmann::json::value_t::discarded;  // too deep: kept as the text it is
    }
    options[key] = parsed.is_discarded() || parsed.is_object() || parsed.is_array()
                       ? nlohmann::json(value)
                       : parsed;
  }
  return options;
}

}  // namespace spheremap::api
