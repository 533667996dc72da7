// The programs' command-line walker and list options: flags alone, options with one value,
// a missing value and unknown names refused with a message naming the option.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "ndtom_apps/command_line.h"

using namespace ndtom::apps;

namespace {

enum class Fruit { Apple, Pear };
constexpr NamedValue<Fruit> kFruits[] = {{"apple", Fruit::Apple}, {"pear", Fruit::Pear}};

/// What forEachArgument reported, in order: "flag NAME" or "NAME=VALUE".
std::vector<std::string> walk(std::vector<const char*> args) {
  args.insert(args.begin(), "program");
  std::vector<std::string> seen;
  forEachArgument(
      int(args.size()), args.data(), {"--quiet", "-h"},
      [&](const std::string& name) { seen.push_back("flag " + name); },
      [&](const std::string& name, const std::string& value) {
        seen.push_back(name + "=" + value);
      });
  return seen;
}

std::string usageMessage(const std::function<void()>& f) {
  try {
    f();
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ForEachArgument, FlagsAloneOptionsWithTheirValue) {
  EXPECT_EQ(walk({}), std::vector<std::string>{});
  EXPECT_EQ(walk({"--quiet", "--n", "3", "-h", "--name", "--quiet"}),
            (std::vector<std::string>{"flag --quiet", "--n=3", "flag -h", "--name=--quiet"}));
  EXPECT_EQ(usageMessage([] { walk({"--quiet", "--n"}); }), "--n: missing value (see --help)");
}

TEST(ForEachArgument, CallbacksRefuseWhatTheyDoNotKnow) {
  const char* argv[] = {"program", "--bogus", "1"};
  EXPECT_EQ(usageMessage([&] {
              forEachArgument(
                  3, argv, {}, [](const std::string&) {},
                  [](const std::string& name, const std::string&) { throw unknownOption(name); });
            }),
            "unknown option '--bogus' (see --help)");
}

TEST(ParseNamedList, ValuesInTheListsOrder) {
  EXPECT_EQ(parseNamedList("--fruit", "pear,apple", kFruits),
            (std::vector<Fruit>{Fruit::Pear, Fruit::Apple}));
  EXPECT_EQ(parseNamedList("--fruit", "apple,", kFruits), std::vector<Fruit>{Fruit::Apple});
  EXPECT_STREQ(nameOf(Fruit::Pear, kFruits), "pear");
}

TEST(ParseNamedList, RefusesUnknownRepeatedAndEmpty) {
  EXPECT_EQ(usageMessage([] { parseNamedList("--fruit", "apple,plum", kFruits); }),
            "--fruit: unknown name 'plum' (see --help)");
  EXPECT_EQ(usageMessage([] { parseNamedList("--fruit", "pear,pear", kFruits); }),
            "--fruit: pear is listed twice");
  EXPECT_EQ(usageMessage([] { parseNamedList("--fruit", ",", kFruits); }), "--fruit: empty list");
}

TEST(ParseIntegerList, IntegersInRangeOnceEach) {
  EXPECT_EQ(parseIntegerList("--t", "1,2,8", 1, 8), (std::vector<int64_t>{1, 2, 8}));
  EXPECT_EQ(usageMessage([] { parseIntegerList("--t", "1,9", 1, 8); }),
            "--t = 9: must be in [1, 8]");
  EXPECT_EQ(usageMessage([] { parseIntegerList("--t", "2,2", 1, 8); }), "--t: 2 is listed twice");
  EXPECT_EQ(usageMessage([] { parseIntegerList("--t", "", 1, 8); }), "--t: empty list");
  EXPECT_EQ(usageMessage([] { parseIntegerList("--t", "1,x", 1, 8); }), "--t: not an integer: 'x'");
}
