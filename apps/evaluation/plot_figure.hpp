#pragma once

// Internal to cambio_evaluation: a figure of stacked time-series panels, drawn to PNG with
// PLplot (run_plots.cpp builds them from a Trace).

#include <cstdint>
#include <string>
#include <vector>

#include <plplot.h>

namespace cambio::app::detail {

// Colour map 0 entries set when the figure is drawn.
enum Colour : PLINT { kBlack = 1, kRed = 2, kBlue = 3, kGreen = 4, kOrange = 5 };

struct Series {
  std::string label;
  Colour colour = kBlack;
  PLINT line_style = 1;   ///< PLplot's pllsty: 1 solid, 2 dashed...
  std::vector<double> y;  ///< One per x; NaN leaves a gap.
};

struct Panel {
  std::string y_label;
  std::vector<Series> series;
};

struct Figure {
  std::string file;
  std::string title;
  std::vector<double> x;
  std::string x_label = "time (s)";
  std::vector<Panel> panels;
};

/// The figure's PNG bytes. PLplot draws it into a temporary directory, removed after. Throws
/// OutputError naming figure.file when PLplot fails or writes nothing. PLplot keeps global
/// state: one thread at a time.
std::vector<std::uint8_t> draw_png(const Figure& figure);

}  // namespace cambio::app::detail
