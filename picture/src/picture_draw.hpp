#pragma once
// Shared drawing helpers of the tool's pictures (cairo): the canvas, colours, text, arrows,
// markers, and the map picture's histogram and legend panels. Included only with cairo.

#include <string>
#include <vector>

#include <cairo.h>
#include <Eigen/Core>

#include "taskmap/core/constants.hpp"
#include "taskmap/inspect/map_hand.hpp"
#include "taskmap/inspect/map_summary.hpp"
#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap::picture_draw {

/// RGB colour, components in [0, 1].
struct Rgb {
  double r, g, b;
};

constexpr Rgb kInk{0.12, 0.12, 0.12};         ///< text and outlines
constexpr Rgb kSilhouette{0.80, 0.80, 0.80};  ///< object silhouette (0xcccccc)
constexpr Rgb kFrame{0.55, 0.55, 0.55};       ///< panel frames

/// Axis-aligned rectangle in pixels.
struct Box {
  double x, y, w, h;
};

/// What the panels draw.
struct Scene {
  const TaskMapData* map;
  const MapSummary* summary;
  std::vector<int> labels;  ///< per grasp, -1 outlier (all -1 when not clustered)
  Eigen::Vector3d lo, hi;   ///< bounds of object and palm positions, metres
  double arrow_length;      ///< metres
  /// Per cluster row: the hand's collision shapes posed by the representative (empty when
  /// the map has no hand to draw).
  std::vector<std::vector<PosedShapePoints>> hands;
};

/// Colour of a cluster (clusterColor), grey for outliers (k < 0).
Rgb rgbOf(int cluster);
/// Sets the source colour.
void setColor(cairo_t* cr, const Rgb& c, double alpha = 1.0);
/// Text at (x, y) baseline; align 0 left, 0.5 centred, 1 right.
void text(cairo_t* cr, double x, double y, const std::string& s, double size, bool bold = false,
          double align = 0.0, const Rgb& color = kInk);
/// printf of one number.
std::string format(const char* fmt, double v);
/// A "nice" number (1, 2 or 5 times a power of ten) not above x.
double niceBelow(double x);
/// "5 cm", "2 mm", "1 m".
std::string lengthLabel(double metres);
/// Arrow from (x0, y0) to (x1, y1) in colour c with a dark outline.
void drawArrow(cairo_t* cr, double x0, double y0, double x1, double y1, const Rgb& c, double width);
/// Representative marker: disc in the cluster colour with a dark rim; when axial (approach
/// mostly perpendicular to the view), a dot if it points at the viewer, a cross if away.
void drawRepresentative(cairo_t* cr, double x, double y, const Rgb& c, double toward_viewer,
                        bool axial);
/// Convex hull of 2-D points, counter-clockwise (fewer than 3 points come back as given).
std::vector<Eigen::Vector2d> hull2d(std::vector<Eigen::Vector2d> points);
/// The convex outline of points (pixels): filled in colour c (30 % opaque), a thin dark rim.
void drawOutline(cairo_t* cr, const std::vector<Eigen::Vector2d>& points, const Rgb& c);
/// A panel: white cell with a frame and a bold title at (10, 22) from its corner.
void drawCell(cairo_t* cr, const Box& cell, const std::string& title, double size = 15);
/// An image surface and its cairo context, destroyed together. The constructor throws Error
/// naming the picture when cairo cannot create them (e.g. out of memory).
class Canvas {
 public:
  Canvas(int width, int height, cairo_format_t format, const std::string& path);
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;
  ~Canvas();
  cairo_t* cr() const { return cr_; }                    ///< the drawing context
  cairo_surface_t* surface() const { return surface_; }  ///< the image
  /// Flushes, checks that drawing succeeded and writes the PNG atomically (writePng).
  void write() const;
  /// Flushes, checks that drawing succeeded and returns the PNG bytes (the bytes write() writes).
  std::string png() const;

 private:
  std::string path_;
  cairo_surface_t* surface_;
  cairo_t* cr_;
};
/// Throws Error("cannot draw picture '<path>': <cairo's message>") unless status is success.
void checkStatus(cairo_status_t status, const std::string& path);
/// Writes the surface as PNG atomically (temporary file beside path, then rename); throws Error
/// naming the file when that fails.
void writePng(cairo_surface_t* surface, const std::string& path);
/// Stacked histogram of epsilon per cluster (outliers grey on top).
void drawHistogram(cairo_t* cr, const Scene& s, const Box& cell);
/// Legend: cluster colours and sizes, marker meanings, map facts.
void drawLegend(cairo_t* cr, const Scene& s, const Box& box);

}  // namespace taskmap::picture_draw
