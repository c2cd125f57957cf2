// Text reports of a build and a data set (builder/build_report.hpp).
#include "taskmap/builder/build_report.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace taskmap {
namespace {

std::string percent(double part, double whole) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f%%", whole > 0 ? 100.0 * part / whole : 0.0);
  return buffer;
}

using ull = unsigned long long;

/// The time line and the work line of a summary.
std::string timingText(const BuildTiming& t, double write_seconds) {
  const double stages =
      t.sampling_seconds + t.simulation_seconds + t.quality_seconds + t.hold_test_seconds;
  const double trial_wall = t.wall_seconds - t.setup_seconds - t.clustering_seconds;
  char line[512];
  std::snprintf(line, sizeof line,
                "  time      wall %.2f s: setup %.2f s, trials %.2f s (%llu simulated, %.1f "
                "trials/s), clustering %.2f s, writing %.2f s\n"
                "  work      sampling %s, simulation %s, quality %s, hold test %s (CPU seconds "
                "%.2f)\n",
                t.wall_seconds + write_seconds, t.setup_seconds, trial_wall,
                static_cast<ull>(t.trials_simulated),
                trial_wall > 0 ? static_cast<double>(t.trials_simulated) / trial_wall : 0.0,
                t.clustering_seconds, write_seconds, percent(t.sampling_seconds, stages).c_str(),
                percent(t.simulation_seconds, stages).c_str(),
                percent(t.quality_seconds, stages).c_str(),
                percent(t.hold_test_seconds, stages).c_str(), stages);
  std::string text = line;
  if (t.closing_checks > 0) {
    std::snprintf(line, sizeof line,
                  "  closing   %llu force-closure grasps checked with the object free, %.1f ms "
                  "CPU each (part of quality)\n",
                  static_cast<ull>(t.closing_checks),
                  1e3 * t.closing_check_seconds / static_cast<double>(t.closing_checks));
    text += line;
  }
  if (t.hold_tests > 0) {
    std::snprintf(
        line, sizeof line,
        "  physics   %llu force-closure grasps of the simulated trials tested in MuJoCo, %.1f ms "
        "CPU and %.0f steps each\n",
        static_cast<ull>(t.hold_tests),
        1e3 * t.hold_test_seconds / static_cast<double>(t.hold_tests),
        static_cast<double>(t.hold_test_steps) / static_cast<double>(t.hold_tests));
    text += line;
  }
  return text;
}

/// The funnel of a build that tested its grasps in physics: trials simulated, force closure,
/// tested, kept (the map's outcome counts over its counted trials).
std::string funnelText(const TaskMapData& map) {
  const auto count = [&map](const char* name) -> unsigned long long {
    const auto it = map.sampling.outcomes.find(name);
    return it == map.sampling.outcomes.end() ? 0ULL : it->second;
  };
  const unsigned long long kept = count("force_closure"), refused = count("not_holding");
  if (refused == 0 && !map.validation) return "";
  char line[256];
  std::snprintf(line, sizeof line,
                "  funnel    %llu trials, %llu force closure, %llu tested in physics, %llu kept "
                "(they hold)\n",
                static_cast<ull>(map.sampling.trials), kept + refused, kept + refused, kept);
  return line;
}

/// Why a default build runs mixed where the hand's default is palm_enclose.
std::string samplerChoiceText(const SamplerChoice& c) {
  return c.enclose_refused ? " (palm_enclose cannot place the hand on this object)" : "";
}

}  // namespace

std::string clockString(double seconds) {
  if (!(seconds >= 0.0) || seconds > 359999.0) return "--:--:--";
  const auto s = static_cast<long>(seconds + 0.5);
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%02ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  return buffer;
}

double buildProgressFraction(const BuildProgress& p) {
  const std::uint64_t valid = std::min(p.valid_found, p.valid_target);
  const double by_valid =
      p.valid_target > 0 ? static_cast<double>(valid) / static_cast<double>(p.valid_target) : 0.0;
  const double by_trials =
      p.max_trials > 0 ? static_cast<double>(p.trials_done) / static_cast<double>(p.max_trials)
                       : 0.0;
  return std::min(1.0, std::max(by_valid, by_trials));
}

std::string buildProgressLine(const BuildProgress& p, const std::string& label, bool bar) {
  const double rate = p.elapsed_seconds > 0 ? p.trials_done / p.elapsed_seconds : 0.0;
  const std::uint64_t valid = std::min(p.valid_found, p.valid_target);
  const double fraction = buildProgressFraction(p);
  const double eta = fraction > 0 ? p.elapsed_seconds * (1.0 - fraction) / fraction : -1.0;
  char blocks[64] = "";
  if (p.blocks_total > 0)
    std::snprintf(blocks, sizeof blocks, "blocks %llu/%llu  ", static_cast<ull>(p.blocks_done),
                  static_cast<ull>(p.blocks_total));
  char line[320];
  if (bar) {
    constexpr int kWidth = 30;
    std::string drawn(static_cast<std::size_t>(fraction * kWidth), '#');
    drawn.resize(kWidth, '-');
    std::snprintf(
        line, sizeof line, "\r[%s] %3.0f%%  %strials %llu  valid %llu/%llu  %.0f trials/s  ETA %s ",
        drawn.c_str(), 100.0 * fraction, blocks, static_cast<ull>(p.trials_done),
        static_cast<ull>(valid), static_cast<ull>(p.valid_target), rate, clockString(eta).c_str());
  } else {
    std::snprintf(line, sizeof line,
                  "%s: %s elapsed, %s%llu trials, %llu/%llu valid, %.0f trials/s, ETA %s\n",
                  label.c_str(), clockString(p.elapsed_seconds).c_str(), blocks,
                  static_cast<ull>(p.trials_done), static_cast<ull>(valid),
                  static_cast<ull>(p.valid_target), rate, clockString(eta).c_str());
  }
  return line;
}

std::string buildSummaryText(const std::string& label, const BuildResult& result,
                             double write_seconds, const std::string& threads_note,
                             const std::string& output) {
  const TaskMapData& map = result.map;
  std::ostringstream os;
  os << label << ": " << toString(result.status) << ": " << result.message << "\n";
  os << "  object    " << map.object.name << " (" << map.object.vertices.rows()
     << " vertices, scale " << map.object.scale << "), hand " << map.hand.name << ", sampler "
     << map.sampling.sampler << samplerChoiceText(result.sampler_choice) << "\n";
  os << "  outcomes ";
  for (const auto& [name, count] : map.sampling.outcomes) os << " " << name << " " << count;
  os << "\n";
  os << funnelText(map);
  os << "  stored    " << map.grasps.size() << " grasps";
  if (map.clustering) {
    std::size_t outliers = 0;
    for (int l : map.clustering->labels) outliers += l < 0;
    os << ", " << map.clustering->clusters.size() << " clusters (" << outliers << " outliers)";
  }
  os << "\n";
  os << "  threads   " << threads_note << "\n";
  os << timingText(result.timing, write_seconds);
  os << "  wrote     " << output << "\n";
  return os.str();
}

std::string buildBudgetWarning(const std::string& label, const BuildResult& result) {
  if (result.status != BuildStatus::kTrialBudgetExhausted) return "";
  return label + ": warning: " + result.message + "; raise --trials or check the object and hand\n";
}

std::string holdLabelsText(const std::string& label, const std::optional<HoldLabels>& labels,
                           bool keep_holding) {
  if (!labels) return "";
  const HoldLabels& s = *labels;
  char line[256];
  std::snprintf(
      line, sizeof line,
      "%s: physics validation: %zu of %zu grasps hold (%.1f %%), %.1f grasps per CPU-second\n",
      label.c_str(), s.holding, s.tested,
      s.tested ? 100.0 * static_cast<double>(s.holding) / static_cast<double>(s.tested) : 0.0,
      s.cpu_seconds > 0 ? static_cast<double>(s.tested) / s.cpu_seconds : 0.0);
  std::string text = line;
  if (keep_holding)
    text += label + ": --keep-holding: kept " + std::to_string(s.kept) + " of " +
            std::to_string(s.before) + " grasps (the others do not hold)\n";
  return text;
}

std::string datasetProgressLine(std::size_t done, std::size_t total, double elapsed_seconds,
                                const DatasetEntry& e) {
  const double eta =
      done > 0 ? elapsed_seconds / static_cast<double>(done) * static_cast<double>(total - done)
               : -1.0;
  std::string line = "[" + std::to_string(done) + "/" + std::to_string(total) + ", ETA " +
                     clockString(eta) + "] " + e.object + " x " + e.hand + ": " +
                     toString(e.status);
  if (e.status == DatasetJobStatus::kFailed) return line + ": " + e.error.value_or("");
  return line + ", " + std::to_string(e.valid.value_or(0)) + " valid in " +
         std::to_string(e.trials.value_or(0)) + " trials -> " + e.file;
}

}  // namespace taskmap
