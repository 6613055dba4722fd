// JSON from untrusted input, bounded before any work: nesting depth is checked while
// parsing (a 2 KB request nested 60,000 deep overflowed the stack when an error message
// serialized it), and values are described, never serialized whole, in messages.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace spheremap {

// glTF nests at most 5 levels in practice (extensions inside accessors); options at 2.
inline constexpr int kMaxJsonDepth = 64;

// The parsed value; a discarded value when the text is not JSON. Throws
// InputError("parse") when arrays and objects nest deeper than max_depth.
nlohmann::json parse_bounded_json(std::string_view text, int max_depth = kMaxJsonDepth);

// A short description of a value for an error message: a number, true/false/null, a
// string (first 64 characters, control bytes and invalid UTF-8 replaced), or "an array
// of N elements" / "an object with N keys" (never their contents).
std::string describe_json(const nlohmann::json& value);

}  // namespace spheremap
