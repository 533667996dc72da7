// The one reader of option values from text (ndtom/map/option_text.h): the texts the MRPT
// plugin's .ini reading took for something else (#38) are refused, naming the option and
// showing the text; plain values read as themselves.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ndtom/map/option_table.h"
#include "ndtom/map/option_text.h"
#include "support/thrown_message.h"

using ndtom::NonFinite;
using ndtom::testing::thrownMessage;

namespace {

std::string realError(const std::string& text, NonFinite allowed = NonFinite::Refused) {
  return thrownMessage<std::invalid_argument>([&] { ndtom::realFromText("k", text, allowed); });
}
std::string integerError(const std::string& text, int64_t min_value, int64_t max_value) {
  return thrownMessage<std::invalid_argument>(
      [&] { ndtom::integerFromText("k", text, min_value, max_value); });
}

const ndtom::OptionRow& row(const char* name) {
  return *ndtom::findOptionRow(name);
}

}  // namespace

TEST(OptionText, RealsAreTheWholeText) {
  EXPECT_EQ(ndtom::realFromText("k", "0.2"), 0.2);
  EXPECT_EQ(ndtom::realFromText("k", "-3"), -3.0);
  EXPECT_EQ(ndtom::realFromText("k", "+1e-3"), 1e-3);
  EXPECT_EQ(ndtom::realFromText("k", ".5"), 0.5);
  EXPECT_EQ(realError("0.2abc"), "k: not a number: '0.2abc'");
  EXPECT_EQ(realError("100m"), "k: not a number: '100m'");
  EXPECT_EQ(realError(""), "k: not a number: ''");
  for (const std::string text : {" 0.2", "0.2 ", "0x10", "1,5", "++1", "+-1", "-", "e3", "nan"})
    EXPECT_EQ(realError(text), "k: not a number: '" + text + "'") << text;
}

TEST(OptionText, RealsBeyondADoubleAreRefusedNotRounded) {
  // strtod gives inf and 0 here; the option would silently take them.
  EXPECT_EQ(realError("1e400"), "k: out of a double's range: '1e400'");
  EXPECT_EQ(realError("-1e400", NonFinite::Infinity), "k: out of a double's range: '-1e400'");
  EXPECT_EQ(realError("1e-400"), "k: out of a double's range: '1e-400'");
  EXPECT_EQ(ndtom::realFromText("k", "1.7e308"), 1.7e308);
}

TEST(OptionText, NonFiniteOnlyWhereTheOptionTakesIt) {
  EXPECT_EQ(realError("inf"), "k: must be finite, got 'inf'");
  EXPECT_EQ(realError("-Infinity"), "k: must be finite, got '-Infinity'");
  EXPECT_EQ(ndtom::realFromText("k", "inf", NonFinite::Infinity), INFINITY);
  EXPECT_EQ(ndtom::realFromText("k", "-INF", NonFinite::Infinity), -INFINITY);
  EXPECT_EQ(realError("nan", NonFinite::Infinity), "k: not a number: 'nan'");
  EXPECT_TRUE(std::isnan(ndtom::realFromText("k", "nan", NonFinite::Nan)));
  EXPECT_NE(realError("inf", NonFinite::Nan), "");
}

TEST(OptionText, IntegersAreExactAndInRange) {
  EXPECT_EQ(ndtom::integerFromText("k", "12", 1, 20), 12);
  EXPECT_EQ(ndtom::integerFromText("k", "+3", 1, 20), 3);
  EXPECT_EQ(ndtom::integerFromText("k", "-0", 0, 20), 0);
  EXPECT_EQ(ndtom::integerFromText("k", "9223372036854775807", 0, INT64_MAX), INT64_MAX);
  // atoi reads the first two as 2, the next ones as 2, 1, 3 and 0.
  EXPECT_EQ(integerError("4294967298", 1, 2147483647),
            "k = 4294967298: must be in [1, 2147483647]");
  EXPECT_EQ(integerError("99999999999999999999", 1, 20),
            "k = 99999999999999999999: must be in [1, 20]");
  EXPECT_EQ(integerError("-0", 1, 20), "k = -0: must be in [1, 20]");
  for (const std::string text : {"2.5", "1e3", "3x", "0x10", " 4", "4 ", "", "two", "2 threads"})
    EXPECT_EQ(integerError(text, 1, 20), "k: not an integer: '" + text + "'") << text;
}

TEST(OptionText, BoolsAreTheSixWordsInAnyCase) {
  // Any case, as MRPT's read_bool and the programs' flags took them before.
  for (const std::string text : {"true", "TRUE", "Yes", "1"})
    EXPECT_TRUE(ndtom::boolFromText("k", text)) << text;
  for (const std::string text : {"false", "False", "NO", "0"})
    EXPECT_FALSE(ndtom::boolFromText("k", text)) << text;
  // read_bool reads the first three as false and "2" as true.
  for (const std::string text : {"on", "off", "maybe", "2", "-1", "", "true ", "y"})
    EXPECT_EQ(thrownMessage<std::invalid_argument>([&] { ndtom::boolFromText("k", text); }),
              "k: expected true or false, got '" + text + "'")
        << text;
}

TEST(OptionText, TableRowsAsTheirType) {
  EXPECT_EQ(ndtom::optionFromText(row("max_range"), "max_range", "inf"), INFINITY);
  EXPECT_EQ(thrownMessage([] { ndtom::optionFromText(row("resolution"), "r", "inf"); }),
            "r: must be finite, got 'inf'");
  EXPECT_EQ(ndtom::optionFromText(row("threads"), "t", "256"), 256.0);
  EXPECT_EQ(thrownMessage([] { ndtom::optionFromText(row("threads"), "t", "257"); }),
            "t = 257: must be in [1, 256]");
  EXPECT_EQ(ndtom::optionFromText(row("occupancy_enabled"), "o", "no"), 0.0);
  EXPECT_EQ(thrownMessage([] { ndtom::optionFromText(row("occupancy_enabled"), "o", "on"); }),
            "o: expected true or false, got 'on'");
  EXPECT_EQ(ndtom::optionFromText(row("ray_mode"), "m", "PerHitCell"), 1.0);
  EXPECT_EQ(ndtom::optionFromText(row("ray_mode"), "m", "0"), 0.0);
  for (const std::string text : {"2", "1x", "PerHitCell x", "perhitcell", ""})
    EXPECT_EQ(thrownMessage([&] { ndtom::optionFromText(row("ray_mode"), "m", text); }),
              "m: expected PerPoint or PerHitCell, got '" + text + "'")
        << text;
}
