#pragma once
// The --only filter of the bench CLIs that run a list of hand x object pairs.

#include <string>

namespace taskmap::testing {

/// True when `only` is empty or one of its '|'-separated substrings occurs in `name` (a pair's
/// "hand object" name); empty parts select nothing.
inline bool selectedByOnly(const std::string& only, const std::string& name) {
  if (only.empty()) return true;
  std::size_t from = 0;
  while (true) {
    const std::size_t bar = only.find('|', from);
    const std::string part = only.substr(from, bar == std::string::npos ? bar : bar - from);
    if (!part.empty() && name.find(part) != std::string::npos) return true;
    if (bar == std::string::npos) return false;
    from = bar + 1;
  }
}

}  // namespace taskmap::testing
