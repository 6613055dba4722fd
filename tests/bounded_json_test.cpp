// JSON from untrusted input: how deep it may nest, and what a message says of a value.
#include <gtest/gtest.h>

#include <string>

#include "core/io/bounded_json.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

std::string nested(int levels, const std::string& inner = "") {
  std::string text;
  for (int k = 0; k < levels; ++k) text += k % 2 ? "{\"a\":" : "[";
  text += inner.empty() ? "0" : inner;
  for (int k = levels - 1; k >= 0; --k) text += k % 2 ? "}" : "]";
  return text;
}

TEST(BoundedJson, SixtyFourLevelsParseAndTheSixtyFifthIsRefused) {
  const nlohmann::json deepest = parse_bounded_json(nested(64));
  ASSERT_TRUE(deepest.is_array());
  const nlohmann::json* value = &deepest;
  for (int k = 0; k < 64; ++k) value = k % 2 ? &(*value)["a"] : &(*value)[0];
  EXPECT_EQ(*value, 0);
  try {
    parse_bounded_json(nested(65));
    FAIL() << "65 levels were parsed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nested deeper than 64 levels"), std::string::npos);
  }
  EXPECT_NO_THROW(parse_bounded_json(nested(3), 3));
  EXPECT_THROW(parse_bounded_json(nested(4), 3), InputError);
}

TEST(BoundedJson, BracketsInsideStringsAreNotNesting) {
  const std::string brackets(1000, '[');
  const nlohmann::json value = parse_bounded_json("{\"k\":\"" + brackets + "\"}");
  EXPECT_EQ(value["k"], brackets);
}

// Text that is not JSON is a discarded value (the caller says what it expected).
TEST(BoundedJson, TextThatIsNotJsonIsDiscarded) {
  EXPECT_TRUE(parse_bounded_json("{\"a\":").is_discarded());
  EXPECT_TRUE(parse_bounded_json("[1,2,]").is_discarded());
  EXPECT_TRUE(parse_bounded_json("").is_discarded());
  EXPECT_TRUE(parse_bounded_json("{} trailing").is_discarded());
}

// A long array of objects (what a glTF's nodes or accessors are) parses whole: every
// element kept, in order.
TEST(BoundedJson, ALongArrayOfObjectsIsKeptWhole) {
  std::string text = "{\"nodes\":[";
  for (int k = 0; k < 50000; ++k)
    text += (k ? ",{\"mesh\":" : "{\"mesh\":") + std::to_string(k) + "}";
  text += "]}";
  const nlohmann::json value = parse_bounded_json(text);
  ASSERT_EQ(value["nodes"].size(), 50000u);
  EXPECT_EQ(value["nodes"][49999]["mesh"], 49999);
}

TEST(BoundedJson, DescriptionsNeverHoldAWholeValue) {
  EXPECT_EQ(describe_json(nlohmann::json::array({1, 2, 3})), "an array of 3 elements");
  EXPECT_EQ(describe_json(nlohmann::json{{"a", 1}}), "an object with 1 keys");
  const std::string text = describe_json(std::string(100, 'x'));
  EXPECT_EQ(text, "\"" + std::string(64, 'x') + "\"...");
  EXPECT_EQ(describe_json(2.5), "2.5");
}

}  // namespace
}  // namespace spheremap
