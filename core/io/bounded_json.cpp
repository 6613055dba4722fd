#include "core/io/bounded_json.h"

#include "core/mesh/input_error.h"

namespace spheremap {

nlohmann::json parse_bounded_json(std::string_view text, int max_depth) {
  // The callback sees every event with its depth before the value is built; throwing
  // there stops the parse (nlohmann's parser is iterative, so the text itself cannot
  // overflow the stack, only what is later done with a deep value).
  const nlohmann::json::parser_callback_t limit = [max_depth](int depth,
                                                              nlohmann::json::parse_event_t,
                                                              nlohmann::json&) {
    if (depth > max_depth)
      throw InputError("parse", "JSON nested deeper than " + std::to_string(max_depth) + " levels");
    return true;
  };
  return nlohmann::json::parse(text.begin(), text.end(), limit, false);
}

std::string describe_json(const nlohmann::json& value) {
  if (value.is_array()) return "an array of " + std::to_string(value.size()) + " elements";
  if (value.is_object()) return "an object with " + std::to_string(value.size()) + " keys";
  if (value.is_string()) {
    std::string text = value.get<std::string>();
    const bool cut = text.size() > 64;
    if (cut) text.resize(64);
    text = nlohmann::json(text).dump(-1, ' ', true, nlohmann::json::error_handler_t::replace);
    return cut ? text + "..." : text;
  }
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace spheremap
