// The programs' command-line walker, option tables and lists of named values: flags alone,
// options with one value, a missing value and unknown names refused with a message naming the
// option.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "ndtom_apps/command_line.h"
#include "support/usage_message.h"

using namespace ndtom::apps;
using ndtom::testing::usageMessage;

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

TEST(WithHelpAndQuiet, AddsTheFourFlagsToATable) {
  struct Options {
    std::string out;
    bool help = false, quiet = false;
  };
  const auto table = withHelpAndQuiet<Options>(
      {{"-o", {true, [](Options& o, const std::string& v) { o.out = v; }}}});
  EXPECT_EQ(table.size(), 5u);
  for (const char* flag : {"--help", "-h", "--quiet", "-q"}) {
    SCOPED_TRACE(flag);
    const char* argv[] = {"program", "-o", "x", flag, "input"};
    Options o;
    EXPECT_EQ(applyArguments(5, argv, table, o), std::vector<std::string>{"input"});
    EXPECT_EQ(o.out, "x");
    EXPECT_EQ(o.help, flag[1] == 'h' || flag[2] == 'h');
    EXPECT_EQ(o.quiet, !o.help);
  }
}
