// taskmap: build, inspect and query grasp task maps.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <iostream>

#include <CLI/CLI.hpp>

#include "command.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap::cli {

std::vector<std::pair<std::string, CommandSetup>>& commandRegistry() {
  static std::vector<std::pair<std::string, CommandSetup>> registry;
  return registry;
}

int& exitCode() {
  static int code = 0;
  return code;
}

}  // namespace taskmap::cli

int main(int argc, char** argv) {
  using namespace taskmap::cli;
  CLI::App app{"taskmap " TASKMAP_VERSION ": build grasp task maps and query them"};
  app.set_version_flag("--version", std::string("taskmap ") + TASKMAP_VERSION);
  app.require_subcommand(1);
  auto& registry = commandRegistry();
  std::sort(registry.begin(), registry.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& entry : registry) entry.second(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const taskmap::Error& e) {
    std::cerr << "taskmap: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "taskmap: internal error: " << e.what() << "\n";
    return 3;
  }
  return exitCode();
}
