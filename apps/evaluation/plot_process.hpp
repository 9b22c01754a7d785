#pragma once

// Figures drawn in a child process. The plotting stack (PLplot's cairo driver, pango, fontconfig,
// GLib) ends the process when it cannot create a thread or allocate (GLib-ERROR: SIGTRAP), as it
// does under an address-space limit; drawn in a child, that costs the plots, never the run's
// results.

#include <cstdint>
#include <string>
#include <vector>

#include "plot_figure.hpp"

namespace cambio::app::detail {

/// One figure as the child drew it: its PNG bytes, or why there are none.
struct DrawnFigure {
  std::string file;
  std::vector<std::uint8_t> png;  ///< Empty when `error` says why.
  std::string error;
};

/// Draws each of `figures` with draw_png() in one forked child, in order, and returns them in the
/// same order. Figures the child finished before it died are kept; the others carry the reason
/// (the signal that ended it, or that no child could be started). Not real-time safe: call after
/// the run, from one thread.
std::vector<DrawnFigure> draw_pngs_in_child(const std::vector<Figure>& figures);

}  // namespace cambio::app::detail
