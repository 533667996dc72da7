// Strict option values: everything that is not exactly a value is refused, with a message
// that names the option and shows the text.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ndtom_apps/option_values.h"
#include "support/usage_message.h"

using namespace ndtom::apps;
using ndtom::testing::usageMessage;

TEST(ParseReal, AcceptsWholeNumbers) {
  EXPECT_EQ(parseReal("--x", "0.25"), 0.25);
  EXPECT_EQ(parseReal("--x", "-3"), -3.0);
  EXPECT_EQ(parseReal("--x", "1e-3"), 1e-3);
  EXPECT_TRUE(std::isinf(parseReal("--x", "inf", /*allow_infinity=*/true)));
}

TEST(ParseReal, RefusesAnythingElseNamingTheOption) {
  for (const std::string text :
       {"0.3x", "0.25m", "nan", "NaN", "1e999", "-1e999", "", "abc", "0.3 ", "1,5", "--"}) {
    const std::string message = usageMessage([&] { parseReal("--resolution", text); });
    EXPECT_EQ(message.rfind("--resolution: ", 0), 0u) << "'" << text << "': " << message;
    EXPECT_NE(message.find("'" + text + "'"), std::string::npos) << message;
  }
  EXPECT_EQ(usageMessage([] { parseReal("--x", "nan", true); }), "--x: not a number: 'nan'");
  EXPECT_EQ(usageMessage([] { parseReal("--x", "1e999", true); }),
            "--x: out of a double's range: '1e999'");
  EXPECT_EQ(usageMessage([] { parseReal("--x", ""); }), "--x: not a number: ''");
}

TEST(ParseReal, RefusesInfinityUnlessAllowed) {
  EXPECT_EQ(usageMessage([] { parseReal("--max-range", "inf"); }),
            "--max-range: must be finite, got 'inf'");
  EXPECT_NE(usageMessage([] { parseReal("--max-range", "-inf"); }), "");
}

TEST(ParseInteger, AcceptsIntegersInRange) {
  EXPECT_EQ(parseInteger("--n", "12", 1, 20), 12);
  EXPECT_EQ(parseInteger("--n", "1", 1, 20), 1);
  EXPECT_EQ(parseInteger("--n", "20", 1, 20), 20);
  EXPECT_EQ(parseInteger("--n", "-5", -10, 0), -5);
}

TEST(ParseInteger, RefusesNonIntegersAndValuesOutOfRange) {
  for (const std::string text : {"1.5", "2.0", "1e3", "3x", "", "abc", " 4", "0x10"})
    EXPECT_EQ(usageMessage([&] { parseInteger("--passes", text, 1, 20); }),
              "--passes: not an integer: '" + text + "'");
  EXPECT_EQ(usageMessage([] { parseInteger("--passes", "99999999999999999999", 1, 20); }),
            "--passes = 99999999999999999999: must be in [1, 20]");
  EXPECT_EQ(usageMessage([] { parseInteger("--passes", "21", 1, 20); }),
            "--passes = 21: must be in [1, 20]");
  EXPECT_EQ(usageMessage([] { parseInteger("--passes", "0", 1, 20); }),
            "--passes = 0: must be in [1, 20]");
}

TEST(ParseBool, TheWordsMrptUnderstands) {
  EXPECT_TRUE(parseBool("--b", "Yes"));
  EXPECT_TRUE(parseBool("--b", "TRUE"));
  EXPECT_TRUE(parseBool("--b", "1"));
  EXPECT_FALSE(parseBool("--b", "0"));
  EXPECT_FALSE(parseBool("--b", "no"));
  EXPECT_EQ(usageMessage([] { parseBool("--b", "on"); }),  // MRPT's read_bool would read false
            "--b: expected true or false, got 'on'");
  EXPECT_NE(usageMessage([] { parseBool("--b", ""); }), "");
}

TEST(ParseOnOff, OnOrOffExactly) {
  EXPECT_TRUE(parseOnOff("--s", "on"));
  EXPECT_FALSE(parseOnOff("--s", "off"));
  EXPECT_EQ(usageMessage([] { parseOnOff("--s", "ON"); }), "--s: expected on or off, got 'ON'");
  EXPECT_EQ(usageMessage([] { parseOnOff("--s", "true"); }),
            "--s: expected on or off, got 'true'");
}

TEST(SplitList, LeavesOutEmptyItems) {
  EXPECT_EQ(splitList("0.1,,0.2,"), (std::vector<std::string>{"0.1", "0.2"}));
  EXPECT_EQ(splitList("octomap"), (std::vector<std::string>{"octomap"}));
  EXPECT_EQ(splitList("1, 2 , ,"), (std::vector<std::string>{"1", "2"}));
  EXPECT_TRUE(splitList("").empty());
  EXPECT_TRUE(splitList(",,").empty());
}

TEST(Trim, RemovesBlanksAtBothEnds) {
  EXPECT_EQ(trim("  p_hit \t\r\n"), "p_hit");
  EXPECT_EQ(trim("a b"), "a b");
  EXPECT_EQ(trim(" \t "), "");
  EXPECT_EQ(trim(""), "");
}

TEST(ParseIntegerList, IntegersInRangeOnceEach) {
  EXPECT_EQ(parseIntegerList("--t", "1,2,8", 1, 8), (std::vector<int64_t>{1, 2, 8}));
  EXPECT_EQ(usageMessage([] { parseIntegerList("--t", "1,9", 1, 8); }),
            "--t = 9: must be in [1, 8]");
  EXPECT_EQ(usageMessage([] { parseIntegerList("--t", "2,2", 1, 8); }), "--t: 2 is listed twice");
  EXPECT_EQ(usageMessage([] { parseIntegerList("--t", "", 1, 8); }), "--t: empty list");
  EXPECT_EQ(usageMessage([] { parseIntegerList("--t", "1,x", 1, 8); }), "--t: not an integer: 'x'");
}
