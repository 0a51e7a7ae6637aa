// The one JSON entry point (io/scene/JsonText.h) against hostile text: nesting that would overflow
// nlohmann's recursion, numbers of a million digits, duplicate keys, UTF-16 files and raw bytes.
// Every refusal is one short printable line naming the place. Also the message helpers
// (io/MessageText.h) that keep such lines short.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "io/scene/JsonText.h"
#include "io/MessageText.h"
#include "sim/InputError.h"

namespace sph {
namespace {

// The message parseJson throws for `text` ("" if it parses).
std::string errorOf(const std::string& text) {
  try {
    io::scene::parseJson(text, "x.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// One line of printable ASCII, short enough to read.
::testing::AssertionResult oneShortLine(const std::string& m) {
  if (m.empty()) return ::testing::AssertionFailure() << "no error";
  if (m.size() > 300) return ::testing::AssertionFailure() << m.size() << " characters";
  for (const char c : m) {
    const auto b = static_cast<unsigned char>(c);
    if (b < 0x20 || b >= 0x7f)
      return ::testing::AssertionFailure() << "byte " << int(b) << " in: " << m;
  }
  return ::testing::AssertionSuccess();
}

TEST(JsonText, NestingDeeperThanTheLimitIsRefusedBeforeParsing) {
  // 70,000 levels overflowed the stack (exit 139) before the limit existed.
  const std::string deep = std::string(70000, '[') + std::string(70000, ']');
  const std::string e = errorOf(deep);
  EXPECT_EQ(e, "x.json:1:65: nested deeper than 64 levels of [ and {; expected at most 64");
  // Exactly the limit parses; brackets inside strings do not count.
  EXPECT_EQ(errorOf(std::string(64, '[') + std::string(64, ']')), "");
  EXPECT_EQ(errorOf("[\"" + std::string(500, '[') + "\"]"), "");
  std::string nested;
  for (int i = 0; i < 65; ++i) nested += "{\"k\":\n";
  EXPECT_EQ(errorOf(nested + "1" + std::string(65, '}')).rfind("x.json:65:1: nested deeper", 0),
            0u);
}

TEST(JsonText, HugeAndOverflowingNumbersGetAShortLine) {
  // A number of a million digits made a megabyte-long "internal error" line (exit 1).
  const std::string e = errorOf("{\"solver\": {\"spacing\": 1" + std::string(1000000, '0') + "}}");
  EXPECT_EQ(e,
            "x.json:1:24: a number of 1e6 characters; expected at most 64 (a double keeps 17 "
            "significant digits)");
  EXPECT_EQ(errorOf("[1e400]"),
            "x.json:1:2: the number 1e400 is out of range; expected a magnitude below 1.8e308 (a "
            "double)");
  EXPECT_EQ(errorOf("[-1e308, 1e-400, 0.10000000000000000555]"), "");  // underflow is 0
}

TEST(JsonText, DuplicateKeysNameTheKeyPathAndBothLines) {
  EXPECT_EQ(errorOf("{\n  \"solver\": {\"spacing\": 0.01},\n  \"solver\": {\"cfl\": 0.3}\n}"),
            "x.json:3:3: duplicate key solver (first given at 2:3); expected each key once (JSON "
            "keeps only one of the two)");
  EXPECT_EQ(errorOf("{\"fluids\": [{}, {\"min\": 1,\n  \"max\": 2, \"min\": 3}]}"),
            "x.json:2:13: duplicate key fluids[1].min (first given at 1:18); expected each key "
            "once (JSON keeps only one of the two)");
  // The same key in different objects is fine; escapes are decoded before comparing.
  EXPECT_EQ(errorOf("[{\"a\": 1}, {\"a\": 2}, {\"b\": {\"a\": 3}, \"a\": 4}]"), "");
  EXPECT_NE(errorOf("{\"a\": 1, \"\\u0061\": 2}").find("duplicate key a"), std::string::npos);
}

TEST(JsonText, OtherEncodingsAndRawBytesAreNamedNeverPrinted) {
  const std::string utf16le("\xFF\xFE{\0}\0", 6);
  EXPECT_EQ(errorOf(utf16le),
            "x.json: not UTF-8 text: it looks like UTF-16 little-endian (byte-order mark FF FE); "
            "save it as UTF-8");
  EXPECT_NE(errorOf(std::string("\0{\0\"\0a", 6)).find("UTF-16 big-endian"), std::string::npos);
  EXPECT_NE(errorOf(std::string("\xFF\xFE\0\0{\0\0\0", 8)).find("UTF-32 little-endian"),
            std::string::npos);
  const std::string latin1 = errorOf("{\"name\": \"caf\xE9\"}");
  EXPECT_EQ(latin1,
            "x.json:1:14: not UTF-8 text (byte 0xE9 does not belong to a UTF-8 character); save "
            "it as UTF-8");
  // Valid UTF-8 outside a string: nlohmann quotes what it read; we escape it.
  const std::string e = errorOf("{\"a\": \xC3\xA9}");
  EXPECT_TRUE(oneShortLine(e)) << e;
  EXPECT_EQ(e.rfind("x.json:1:7: invalid JSON: syntax error", 0), 0u) << e;
  EXPECT_NE(e.find("\\xC3"), std::string::npos) << e;
  EXPECT_EQ(errorOf("\xEF\xBB\xBF{\"name\": \"caf\xC3\xA9\"}"), "");  // a UTF-8 BOM is fine
  // An unterminated megabyte string: nlohmann's "last read" is cut short.
  const std::string open = errorOf("{\"a\": \"" + std::string(1000000, 'x'));
  EXPECT_TRUE(oneShortLine(open)) << open.substr(0, 400);
}

// A NUL byte would end the text for nlohmann, silently dropping the rest of the scene.
TEST(JsonText, ANulByteIsRefusedWithItsPlace) {
  const std::string text("{\"a\": 1}\n\0{\"b\": 2}", 18);
  EXPECT_EQ(errorOf(text),
            "x.json:2:1: a NUL byte (at byte 9); expected JSON text, which has none");
  EXPECT_NE(errorOf(std::string("{\"a\": \"x\0y\"}", 12)).find("a NUL byte (at byte 8)"),
            std::string::npos);
}

TEST(JsonText, SetValuesThatAreNotJsonAreStringsButLimitsStillHold) {
  EXPECT_FALSE(io::scene::parseJsonIfJson("pour", "--set name").has_value());
  EXPECT_FALSE(io::scene::parseJsonIfJson("[1, 2", "--set x").has_value());
  EXPECT_EQ(*io::scene::parseJsonIfJson("[1, 2]", "--set x"), nlohmann::json::array({1, 2}));
  EXPECT_THROW(io::scene::parseJsonIfJson(std::string(100, '['), "--set x"), InputError);
  EXPECT_THROW(io::scene::parseJsonIfJson("{\"a\": 1, \"a\": 2}", "--set x"), InputError);
}

TEST(MessageText, QuotesAreShortAndPrintableNumbersReadable) {
  EXPECT_EQ(io::printable("abc"), "abc");
  EXPECT_EQ(io::printable("a\xFF\n"), "a\\xFF\\x0A");
  EXPECT_EQ(io::printable(std::string(100, 'k')), std::string(37, 'k') + "...");
  EXPECT_EQ(io::printable(std::string(40, 'k')), std::string(40, 'k'));
  EXPECT_EQ(io::readableNumber(1e308), "1e308");
  EXPECT_EQ(io::readableNumber(-2.5e-5), "-2.5e-5");
  EXPECT_EQ(io::readableNumber(0.25), "0.25");
  EXPECT_EQ(io::readableNumber(1.7976931348623157e308), "1.79769e308");
  EXPECT_EQ(io::readableNumber(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(io::readableCount(123456), "123456");
  EXPECT_EQ(io::readableCount(1.9e8), "1.9e8");
  EXPECT_EQ(io::readableCount(9.3e18), "9.3e18");  // was "-9223372036854775808 particles"
}

TEST(MessageText, APathIsQuotedWholeUnderADeepDirectory) {
  const std::string deep = "/tmp/sphsplat-test-Ab12Cd/" + std::string(150, 'd') + "/frame.h5";
  EXPECT_EQ(io::printablePath(deep), deep);  // printable() would cut the file name off
  const std::string huge(1000, 'p');
  EXPECT_EQ(io::printablePath(huge), std::string(237, 'p') + "...");
}

}  // namespace
}  // namespace sph
