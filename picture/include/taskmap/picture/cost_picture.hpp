#pragma once
// Fig. 1.16 as a PNG: the cost terms per optimisation iteration and the map terms over the
// movement.

#include <string>
#include <utility>
#include <vector>

namespace taskmap {

/// One curve: its name and a value per iteration.
using CostSeries = std::pair<std::string, std::vector<double>>;

/// One panel: its title, the label of its x axis (the index of the values, times x_scale) and
/// its curves on a common linear axis.
struct CostPanel {
  std::string title;               ///< drawn above the panel
  std::string x_label;             ///< e.g. "iteration", "time [s]"
  double x_scale = 1.0;            ///< x value of index i is i * x_scale
  std::vector<CostSeries> series;  ///< curves
};

/// Draws the panels side by side and writes the PNG atomically. Throws Error naming the file
/// when it cannot be written or when the library was built without cairo.
void writeCostPicture(const std::vector<CostPanel>& panels, const std::string& path);

}  // namespace taskmap
