#include "plot_figure.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <string>
#include <system_error>

#include "output_directory.hpp"

namespace cambio::app::detail {

namespace {

constexpr PLINT kWidthPx = 1200;
constexpr PLINT kPanelHeightPx = 330;

struct Range {
  double low = 0.0, high = 1.0;
};

Range range_of(const std::vector<double>& values) {
  double low = INFINITY, high = -INFINITY;
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    low = std::min(low, v);
    high = std::max(high, v);
  }
  if (!(low <= high)) return {};
  if (high - low < 1e-9 * std::max(1.0, std::abs(high))) {
    const double pad = std::max(0.5, 0.1 * std::abs(high));
    return {low - pad, high + pad};
  }
  const double pad = 0.05 * (high - low);
  return {low - pad, high + pad};
}

/// The file PLplot writes a figure to: an anonymous in-memory file (memfd) that PLplot opens by
/// its /proc/self/fd name. It has no name in any directory, so it is gone with the plotting
/// process however that ends (a crash under a memory limit, a kill when a second signal hurries
/// the stop), where a temporary directory was left behind.
class InMemoryFile {
 public:
  explicit InMemoryFile(const std::string& name) : name_(name) {
    fd_ = ::memfd_create("cambio-plot", MFD_CLOEXEC);
    if (fd_ < 0) fail("cannot make an in-memory file for PLplot");
    path_ = "/proc/self/fd/" + std::to_string(fd_);
    // PLplot exit()s on a file it cannot open: one that cannot be opened is refused here.
    const int probe = ::open(path_.c_str(), O_RDWR | O_CLOEXEC);
    if (probe < 0) fail("cannot open the in-memory file for PLplot as " + path_);
    ::close(probe);
  }
  ~InMemoryFile() { ::close(fd_); }
  InMemoryFile(const InMemoryFile&) = delete;
  InMemoryFile& operator=(const InMemoryFile&) = delete;

  const std::string& path() const { return path_; }

  /// What PLplot wrote (read once it has closed its stream).
  std::vector<std::uint8_t> contents() const {
    struct stat status {};
    if (::fstat(fd_, &status) != 0) fail("cannot read PLplot's file");
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(status.st_size));
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n =
          ::pread(fd_, bytes.data() + done, bytes.size() - done, static_cast<off_t>(done));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) fail("cannot read PLplot's file");
      // A file that shrank since fstat: errno says nothing of it.
      if (n == 0) throw OutputError(name_ + ": PLplot's file ended before its stated size");
      done += static_cast<std::size_t>(n);
    }
    return bytes;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw OutputError(name_ + ": " + what + ": " + std::generic_category().message(errno));
  }

  std::string name_;
  std::string path_;
  int fd_ = -1;
};

/// PLplot reports what plabort() refused through plsError's buffer, and cannot recover from
/// plexit() (it calls exit()): everything that could reach plexit (an unknown device, an
/// unwritable file) is checked before plinit().
class PlotSession {
 public:
  PlotSession(const std::string& name, const std::string& path, PLINT panels) : name_(name) {
    require_device("pngcairo");
    plsError(&code_, message_);
    plsdev("pngcairo");
    plsfnam(path.c_str());
    plspage(0.0, 0.0, kWidthPx, kPanelHeightPx * panels + 60, 0, 0);
    plscolbg(255, 255, 255);
    plssub(1, panels);
    plinit();
    initialised_ = true;
    check("plinit");
    plscol0(kBlack, 0, 0, 0);
    plscol0(kRed, 200, 30, 30);
    plscol0(kBlue, 30, 80, 200);
    plscol0(kGreen, 30, 150, 60);
    plscol0(kOrange, 230, 140, 0);
    check("colours");
  }
  ~PlotSession() {
    if (initialised_) plend();
  }
  PlotSession(const PlotSession&) = delete;
  PlotSession& operator=(const PlotSession&) = delete;

  /// Writes the file (cairo flushes it when the stream ends).
  void finish() {
    plend();
    initialised_ = false;
  }

  void check(const char* step) const {
    if (code_ != 0) {
      throw OutputError(name_ + ": PLplot failed in " + step + ": " + std::string(message_));
    }
  }

 private:
  void require_device(const char* device) const {
    const char* menus[128];
    const char* devices[128];
    const char** menu_list = menus;
    const char** device_list = devices;
    int count = 128;
    plgDevs(&menu_list, &device_list, &count);
    for (int i = 0; i < count; ++i) {
      if (std::string(device_list[i]) == device) return;
    }
    throw OutputError(name_ + ": PLplot has no '" + device + "' device (plplot-driver-cairo)");
  }

  std::string name_;
  PLINT code_ = 0;
  char message_[1024] = {};
  bool initialised_ = false;
};

void draw_axes(PlotSession& session, const Figure& figure, const Panel& panel, bool first) {
  const Range x = range_of(figure.x);
  std::vector<double> all;
  for (const Series& series : panel.series) all.insert(all.end(), series.y.begin(), series.y.end());
  const Range y = range_of(all);
  pladv(0);
  plvpor(0.08, 0.97, 0.16, 0.82);
  plwind(x.low, x.high, y.low, y.high);
  plcol0(kBlack);
  plschr(0.0, 0.9);
  plbox("bcnstg", 0.0, 0, "bcnstvg", 0.0, 0);
  pllab(figure.x_label.c_str(), panel.y_label.c_str(), "");
  if (first) plmtex("t", 2.6, 0.0, 0.0, figure.title.c_str());
  session.check("axes");
}

/// The series' finite runs as lines (a single point as a symbol), its label above the panel in
/// the s-th slot.
void draw_series(PlotSession& session, const Figure& figure, const Series& series, std::size_t s) {
  plcol0(series.colour);
  pllsty(series.line_style);
  plwidth(1.5);
  // Finite runs only: a NaN (no measurement) leaves a gap.
  std::size_t k = 0;
  const std::size_t n = std::min(series.y.size(), figure.x.size());
  while (k < n) {
    while (k < n && !std::isfinite(series.y[k])) ++k;
    const std::size_t begin = k;
    while (k < n && std::isfinite(series.y[k])) ++k;
    if (k - begin >= 2) {
      plline(static_cast<PLINT>(k - begin), figure.x.data() + begin, series.y.data() + begin);
    } else if (k - begin == 1) {
      plsym(1, figure.x.data() + begin, series.y.data() + begin, 210);
    }
  }
  pllsty(1);
  plmtex("t", 0.8, 0.02 + 0.24 * static_cast<double>(s), 0.0, series.label.c_str());
  session.check(series.label.c_str());
}

void draw_panel(PlotSession& session, const Figure& figure, const Panel& panel, bool first) {
  draw_axes(session, figure, panel, first);
  for (std::size_t s = 0; s < panel.series.size(); ++s) {
    draw_series(session, figure, panel.series[s], s);
  }
}

}  // namespace

std::vector<std::uint8_t> draw_png(const Figure& figure) {
  const InMemoryFile file(figure.file);
  {
    PlotSession session(figure.file, file.path(), static_cast<PLINT>(figure.panels.size()));
    for (std::size_t p = 0; p < figure.panels.size(); ++p) {
      draw_panel(session, figure, figure.panels[p], p == 0);
    }
    session.finish();
  }
  std::vector<std::uint8_t> bytes = file.contents();
  if (bytes.size() < 8) throw OutputError(figure.file + ": PLplot wrote no image");
  return bytes;
}

}  // namespace cambio::app::detail
