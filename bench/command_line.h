#pragma once
// A benchmark's command line. CLI11 parses it, in command_line.cpp only: CLI11's inline code
// costs about 8 s of compiler time in every file that includes it, and there are a dozen
// benchmark programs.
//
//   bench::CommandLine app("what the program measures");
//   app.option("--spp", spp).option("--repeat", repeat, "runs").positive();
//   if (const auto exit = app.parse(argc, argv)) return *exit;
//   return app.run([&] { return measure(spp, repeat); });
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace pathfarm::bench {

class CommandLine {
 public:
  explicit CommandLine(const std::string& description);
  ~CommandLine();
  CommandLine(const CommandLine&) = delete;
  CommandLine& operator=(const CommandLine&) = delete;

  // An option with a value (int, int64_t, float, double, std::string, or a std::vector of int
  // or std::string), and a flag.
  template <typename T>
  CommandLine& option(const std::string& name, T& value, const std::string& help = "");
  CommandLine& flag(const std::string& name, bool& value, const std::string& help = "");

  // What the option added last must be: given, above zero, within [low, high]; a list that
  // may also be given comma-separated.
  CommandLine& required();
  CommandLine& positive();
  CommandLine& range(double low, double high);
  CommandLine& commaSeparated();

  // A subcommand with options of its own; a program with subcommands takes exactly one.
  CommandLine& subcommand(const std::string& name, const std::string& description);
  // Whether this subcommand was the one given.
  bool given() const;

  // Parses the command line. After --help or an error (printed as CLI11 prints them) it
  // returns the exit status the program should end with, and nothing otherwise.
  std::optional<int> parse(int argc, char** argv);

  // Runs the program's body after parse(): an exception out of it (a folder that does not
  // exist, a frame that cannot be read) ends the program with "NAME: message" and status 1
  // instead of std::terminate.
  int run(const std::function<int()>& body) const;

 private:
  struct State;
  explicit CommandLine(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace pathfarm::bench
