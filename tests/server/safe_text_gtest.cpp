// Text from clients made safe for JSON answers, the log and error messages.
#include "input/safe_text.hpp"

#include <gtest/gtest.h>

#include "input/api_error.hpp"
#include "input/json_input.hpp"

using namespace compaction::server;
using nlohmann::json;

TEST(ValidUtf8, ReplacesEachInvalidByteAndKeepsValidText) {
  EXPECT_EQ(valid_utf8("caf\xC3\xA9"), "caf\xC3\xA9");
  EXPECT_EQ(valid_utf8("/\xFF"), "/\xEF\xBF\xBD");
  EXPECT_EQ(valid_utf8("x\xC3\x28"), "x\xEF\xBF\xBD(");                   // truncated sequence
  EXPECT_EQ(valid_utf8("\xC0\xAF"), "\xEF\xBF\xBD\xEF\xBF\xBD");          // overlong '/'
  EXPECT_EQ(valid_utf8("\xED\xA0\x80"), "\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");  // surrogate
  // What comes out always serialises.
  EXPECT_NO_THROW(json(valid_utf8("\xFF\xFE\x80 end")).dump());
}

TEST(LogEscape, WritesOneLineWithoutControlCharactersAndCutsLongText) {
  EXPECT_EQ(log_escape("a\nb\r\tc"), "a\\nb\\r\\tc");
  EXPECT_EQ(log_escape("\x1b[31mred"), "\\x1b[31mred");
  EXPECT_EQ(log_escape("back\\slash"), "back\\\\slash");
  EXPECT_EQ(log_escape("\xFF"), "\\xff");
  EXPECT_EQ(log_escape("\xC2\x9B"), "\\x9b");  // C1 control (CSI)
  EXPECT_EQ(log_escape(std::string(500, 'x'), 10), std::string(10, 'x') + "...");
  EXPECT_EQ(log_escape("r\xC3\xA9sum\xC3\xA9"), "r\xC3\xA9sum\xC3\xA9");  // printable UTF-8 stays
}

TEST(Describe, GivesScalarsShortAndContainersByTheirSize) {
  EXPECT_EQ(describe(json(3.5)), "3.5");
  EXPECT_EQ(describe(json("fast")), "\"fast\"");
  EXPECT_EQ(describe(json(std::string(100, 'y'))), "\"" + std::string(40, 'y') + "...\"");
  EXPECT_EQ(describe(json::array({1, 2, 3})), "an array of 3 values");
  EXPECT_EQ(describe(json::object()), "an object of 0 keys");
}

TEST(ControlCharacters, AreFoundInNamesAndNewlinesMayBeAllowed) {
  EXPECT_FALSE(has_control_characters("sweep 1 (phi = 0.4)"));
  EXPECT_TRUE(has_control_characters(std::string("a\0b", 3)));
  EXPECT_TRUE(has_control_characters("a\nb"));
  EXPECT_FALSE(has_control_characters("a\nb", true));
  EXPECT_TRUE(has_control_characters("\x1b[2J", true));
  EXPECT_TRUE(has_control_characters("\xFF"));
}

TEST(JsonNesting, IsCountedOutsideStringsAndRefusedBeyondTheLimit) {
  EXPECT_EQ(json_nesting_depth(R"({"a": [1, {"b": []}]})"), 4);
  EXPECT_EQ(json_nesting_depth(R"({"a": "[[[[\"[[["})"), 1);
  const std::string deep = std::string(70000, '[') + std::string(70000, ']');
  EXPECT_EQ(json_nesting_depth(deep), max_json_depth + 1);  // stops counting there
  try {
    parse_client_json("{\"name\": " + deep + "}", "body");
    FAIL() << "accepted 70000 levels";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 400);
    EXPECT_EQ(e.field, "body");
  }
  const std::string ok = std::string(max_json_depth, '[') + std::string(max_json_depth, ']');
  EXPECT_TRUE(parse_client_json(ok, "body").is_array());
  EXPECT_THROW(parse_client_json("{\"a\": 1e999}", "body"), ApiError);
  EXPECT_THROW(parse_client_json("{\"a\": \"\xFF\"}", "body"), ApiError);  // invalid UTF-8
}
