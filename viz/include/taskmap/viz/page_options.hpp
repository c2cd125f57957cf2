#pragma once
/// @file page_options.hpp
/// Options shared by the interactive pages of taskmap::viz (self-contained HTML with three.js).

#include <string>

namespace taskmap {

/// Title and limits of a page.
struct PageOptions {
  std::string title;  ///< page title ("" picks one from the data)
  /// Decimal places kept for lengths and angles in the page's data (5: 10 micrometres).
  int decimals = 5;
  /// Most hands drawn at once as ghosts (the other grasps are palm glyphs), >= 1.
  int ghost_limit = 60;
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// True when three.js was embedded at build time (libjs-three found); false makes every page
/// function throw Error saying how to install it.
bool viewerAvailable();

}  // namespace taskmap
