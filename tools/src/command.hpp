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

/// All registered subcommands, in registration order, sorted by name at start-up.
std::vector<std::pair<std::string, CommandSetup>>& commandRegistry();

/// Registers a subcommand at static-initialisation time.
struct CommandRegistrar {
  CommandRegistrar(const std::string& name, CommandSetup setup) {
    commandRegistry().emplace_back(name, std::move(setup));
  }
};

/// Exit code the running command sets (default 0).
int& exitCode();

}  // namespace taskmap::cli
