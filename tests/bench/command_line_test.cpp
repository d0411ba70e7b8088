// The benchmarks' command line (bench/command_line.h): values, lists, checks and
// subcommands reach the variables they name, and bad command lines end the program.
#include "bench/command_line.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace pathfarm::bench {
namespace {

// argv from words; the program name first.
std::optional<int> parseWords(CommandLine& app, std::vector<std::string> words) {
  words.insert(words.begin(), "benchmark");
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  return app.parse(int(argv.size()), argv.data());
}

TEST(BenchCommandLine, ValuesListsAndFlagsReachTheirVariables) {
  int spp = 16;
  double seconds = 1;
  std::string scene = "default";
  std::vector<int> counts = {1};
  bool quick = false;
  CommandLine app("test");
  app.option("--spp", spp).positive().option("--seconds", seconds).option("--scene", scene);
  app.option("--counts", counts).commaSeparated().flag("--quick", quick);
  EXPECT_FALSE(parseWords(app, {"--spp", "64", "--seconds", "2.5", "--counts", "32,64,128", "--quick"}));
  EXPECT_EQ(spp, 64);
  EXPECT_EQ(seconds, 2.5);
  EXPECT_EQ(scene, "default") << "an option not given keeps its default";
  EXPECT_EQ(counts, (std::vector<int>{32, 64, 128}));
  EXPECT_TRUE(quick);
}

TEST(BenchCommandLine, ABadCommandLineEndsTheProgramWithAnError) {
  int tiles = 4;
  std::string scene;
  const auto fresh = [&](CommandLine& app) {
    app.option("--tiles", tiles).range(2, 100).option("--scene", scene).required();
  };
  for (const std::vector<std::string>& words : std::vector<std::vector<std::string>>{
           {"--scene", "x", "--tiles", "1"}, {"--tiles", "3"}, {"--scene", "x", "--tiles", "many"}, {"--nope"}}) {
    CommandLine app("test");
    fresh(app);
    const auto exit = parseWords(app, words);
    ASSERT_TRUE(exit) << words[0];
    EXPECT_NE(*exit, 0) << words[0];
  }
  CommandLine help("test");
  fresh(help);
  EXPECT_EQ(parseWords(help, {"--help"}), 0);
}

TEST(BenchCommandLine, ExactlyOneSubcommandIsGivenAndKnowsIt) {
  int repeat = 1;
  std::string scene;
  CommandLine app("test");
  CommandLine& solve = app.subcommand("solve", "one");
  solve.option("--repeat", repeat);
  CommandLine& compare = app.subcommand("compare", "two");
  compare.option("--scene", scene);
  EXPECT_FALSE(parseWords(app, {"solve", "--repeat", "3"}));
  EXPECT_TRUE(solve.given());
  EXPECT_FALSE(compare.given());
  EXPECT_EQ(repeat, 3);

  CommandLine none("test");
  none.subcommand("solve", "one");
  const auto exit = parseWords(none, {});
  ASSERT_TRUE(exit);
  EXPECT_NE(*exit, 0);
}

TEST(BenchCommandLine, AnExceptionOutOfTheBodyEndsTheProgramWithItsMessage) {
  CommandLine app("test");
  ASSERT_FALSE(parseWords(app, {}));
  EXPECT_EQ(app.run([] { return 3; }), 3) << "the body's own status";
  testing::internal::CaptureStderr();
  const int status = app.run([]() -> int { throw std::runtime_error("frames/: not a folder"); });
  const std::string printed = testing::internal::GetCapturedStderr();
  EXPECT_EQ(status, 1);
  EXPECT_EQ(printed, "benchmark: frames/: not a folder\n");
}

}  // namespace
}  // namespace pathfarm::bench
