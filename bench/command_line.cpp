#include "bench/command_line.h"

#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <vector>

namespace pathfarm::bench {

struct CommandLine::State {
  std::unique_ptr<CLI::App> owned;  // the program's; a subcommand's belongs to its parent
  CLI::App* app = nullptr;
  CLI::Option* last = nullptr;
  std::vector<std::unique_ptr<CommandLine>> subcommands;
};

CommandLine::CommandLine(const std::string& description) : state_(std::make_unique<State>()) {
  state_->owned = std::make_unique<CLI::App>(description);
  state_->app = state_->owned.get();
}

CommandLine::CommandLine(std::unique_ptr<State> state) : state_(std::move(state)) {}

CommandLine::~CommandLine() = default;

template <typename T>
CommandLine& CommandLine::option(const std::string& name, T& value, const std::string& help) {
  state_->last = state_->app->add_option(name, value, help);
  return *this;
}

template CommandLine& CommandLine::option(const std::string&, int&, const std::string&);
template CommandLine& CommandLine::option(const std::string&, int64_t&, const std::string&);
template CommandLine& CommandLine::option(const std::string&, float&, const std::string&);
template CommandLine& CommandLine::option(const std::string&, double&, const std::string&);
template CommandLine& CommandLine::option(const std::string&, std::string&, const std::string&);
template CommandLine& CommandLine::option(const std::string&, std::vector<int>&, const std::string&);
template CommandLine& CommandLine::option(const std::string&, std::vector<std::string>&, const std::string&);

CommandLine& CommandLine::flag(const std::string& name, bool& value, const std::string& help) {
  state_->last = state_->app->add_flag(name, value, help);
  return *this;
}

CommandLine& CommandLine::required() {
  state_->last->required();
  return *this;
}

CommandLine& CommandLine::positive() {
  state_->last->check(CLI::PositiveNumber);
  return *this;
}

CommandLine& CommandLine::range(double low, double high) {
  state_->last->check(CLI::Range(low, high));
  return *this;
}

CommandLine& CommandLine::commaSeparated() {
  state_->last->delimiter(',');
  return *this;
}

CommandLine& CommandLine::subcommand(const std::string& name, const std::string& description) {
  state_->app->require_subcommand(1);
  auto state = std::make_unique<State>();
  state->app = state_->app->add_subcommand(name, description);
  state_->subcommands.push_back(std::unique_ptr<CommandLine>(new CommandLine(std::move(state))));
  return *state_->subcommands.back();
}

bool CommandLine::given() const { return state_->app->parsed(); }

std::optional<int> CommandLine::parse(int argc, char** argv) {
  try {
    state_->app->parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return state_->app->exit(error);
  }
  return std::nullopt;
}

int CommandLine::run(const std::function<int()>& body) const {
  try {
    return body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", state_->app->get_name().c_str(), e.what());
    return 1;
  }
}

}  // namespace pathfarm::bench
