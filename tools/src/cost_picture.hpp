#pragma once
// The cost terms per optimisation iteration (paper Fig. 1.16) as a PNG.

#include <string>
#include <utility>
#include <vector>

namespace taskmap::cli {

/// One curve: its name and a value per iteration.
using CostSeries = std::pair<std::string, std::vector<double>>;

/// Draws two panels (left: trajectory terms, right: map terms), each curve over the iteration
/// number on the panel's common linear axis, and writes the PNG atomically. Throws Error naming
/// the file when it cannot be written or when the tool was built without cairo.
void writeCostPicture(const std::vector<CostSeries>& left, const std::vector<CostSeries>& right,
                      const std::string& path);

}  // namespace taskmap::cli
