// taskmap: build, inspect and query grasp task maps.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <iostream>
#include <memory>
#include <sstream>

#include <CLI/CLI.hpp>

#include "command.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap::cli {

std::vector<CommandEntry>& commandRegistry() {
  static std::vector<CommandEntry> registry;
  return registry;
}

namespace {

/// `taskmap --help` lists each command with its one-line summary; `taskmap CMD --help` keeps
/// the command's full description (CLI11 copies the formatter into the subcommands, where this
/// override is not used: it only formats the list of subcommands).
class SummaryFormatter : public CLI::Formatter {
 public:
  std::string make_subcommand(const CLI::App* sub) const override {
    std::string summary = sub->get_description();
    for (const CommandEntry& e : commandRegistry())
      if (e.name == sub->get_name()) summary = e.summary;
    std::stringstream out;
    CLI::detail::format_help(out, sub->get_display_name(true), summary, 14);
    return out.str();
  }
};

}  // namespace

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
            [](const auto& a, const auto& b) { return a.name < b.name; });
  for (auto& entry : registry) entry.setup(app);
  app.formatter(std::make_shared<SummaryFormatter>());
  app.footer(
      "Run `taskmap COMMAND --help` for a command's options. Hands and objects are files or "
      "bundled names (--hand barrett, --object basket). Documentation: README.md and docs/ in "
      "the source tree.");
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
