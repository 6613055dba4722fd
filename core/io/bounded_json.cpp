#include "core/io/bounded_json.h"

#include "core/mesh/input_error.h"

namespace spheremap {

namespace {

// Nesting depth alone, from nlohmann's SAX events: no value is built. (A parser callback
// would do it in one pass, but nlohmann 3.11's callback parser rescans the enclosing
// array after every object it closes: 400,000 empty nodes, 1.6 MB, took 29 s.)
class DepthCheck {
 public:
  using json = nlohmann::json;
  explicit DepthCheck(int max_depth) : max_depth_(max_depth) {}
  bool too_deep() const { return too_deep_; }

  bool null() { return true; }
  bool boolean(bool) { return true; }
  bool number_integer(json::number_integer_t) { return true; }
  bool number_unsigned(json::number_unsigned_t) { return true; }
  bool number_float(json::number_float_t, const json::string_t&) { return true; }
  bool string(json::string_t&) { return true; }
  bool binary(json::binary_t&) { return true; }
  bool key(json::string_t&) { return true; }
  bool start_object(std::size_t) { return enter(); }
  bool end_object() { return leave(); }
  bool start_array(std::size_t) { return enter(); }
  bool end_array() { return leave(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) {
    return false;
  }

 private:
  bool enter() {
    too_deep_ = ++depth_ > max_depth_;
    return !too_deep_;  // stops the parse at once
  }
  bool leave() {
    --depth_;
    return true;
  }
  int max_depth_, depth_ = 0;
  bool too_deep_ = false;
};

}  // namespace

nlohmann::json parse_bounded_json(std::string_view text, int max_depth) {
  // Depth first (nlohmann's parser is iterative, so the text itself cannot overflow the
  // stack, only what is later done with a deep value), then the value: two linear passes.
  DepthCheck check(max_depth);
  nlohmann::json::sax_parse(text.begin(), text.end(), &check, nlohmann::json::input_format_t::json,
                            /*strict=*/true);
  if (check.too_deep())
    throw InputError("parse", "JSON nested deeper than " + std::to_string(max_depth) + " levels");
  return nlohmann::json::parse(text.begin(), text.end(), nullptr, false);
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
