#pragma once
/// @file command.hpp
/// Subcommand registry of the `taskmap` tool: each cmd_<name>.cpp defines a static
/// CommandRegistrar that adds its subcommand to the CLI11 app.

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace taskmap::cli {

/// Adds one subcommand to the app; the callback it installs runs the command and returns
/// through exitCode(): 0 on success, non-zero with a message on stderr otherwise.
using CommandSetup = std::function<void(CLI::App& app)>;

/// One registered subcommand: its name, the one line `taskmap --help` lists it with, and the
/// setup that adds it (its own `--help` shows the full description the setup gives it).
struct CommandEntry {
  std::string name;     ///< the subcommand's name ("build")
  std::string summary;  ///< one line, under 80 characters, no full stop
  CommandSetup setup;   ///< adds the subcommand to the app
};

/// All registered subcommands, in registration order, sorted by name at start-up.
std::vector<CommandEntry>& commandRegistry();

/// Registers a subcommand at static-initialisation time.
struct CommandRegistrar {
  CommandRegistrar(const std::string& name, const std::string& summary, CommandSetup setup) {
    commandRegistry().push_back({name, summary, std::move(setup)});
  }
};

/// Exit code the running command sets (default 0).
int& exitCode();

}  // namespace taskmap::cli
