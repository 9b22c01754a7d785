#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "cambio/config/echoed_text.hpp"
#include "console_session.hpp"
#include "console_session_detail.hpp"
#include "image_files.hpp"

// The console's `capture CAMERA DIR`: the stereo camera's newest image and the joints' readings,
// saved as the next viewNN.png with viewNN.yaml in DIR (what `cambio calibrate hand-eye` reads);
// `capture stereo DIR`: both images of the newest pair as leftNN.png and rightNN.png (what
// `cambio calibrate stereo` reads), the readings in pairNN.yaml.

namespace cambio::app {

using console::detail::format;

namespace {

/// The next free view number in `directory`: one above the highest <prefix>NN.* there.
int next_view(const std::filesystem::path& directory, const std::string& prefix) {
  int highest = 0;
  std::error_code error;
  const std::size_t n_prefix = prefix.size();
  for (const auto& entry : std::filesystem::directory_iterator(directory, error)) {
    const std::string stem = entry.path().stem().string();
    if (stem.size() <= n_prefix || !stem.starts_with(prefix)) continue;
    try {
      std::size_t used = 0;
      const int n = std::stoi(stem.substr(n_prefix), &used);
      if (used == stem.size() - n_prefix) highest = std::max(highest, n);
    } catch (const std::exception&) {
      // Not one of ours.
    }
  }
  return highest + 1;
}

/// Writes `bytes` to `path` through a temporary file renamed over it: a reader never sees half.
void write_whole(const std::filesystem::path& path, const std::string& bytes) {
  const std::filesystem::path partial = path.string() + ".partial";
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) throw std::runtime_error("cannot write " + partial.string());
  }
  std::error_code error;
  std::filesystem::rename(partial, path, error);
  if (error) throw std::runtime_error("cannot rename " + partial.string() + ": " + error.message());
}

}  // namespace

void ConsoleSession::capture(const std::string& camera, const std::string& directory,
                             std::int64_t now_ns) {
  const hal::HardwareInfo& hardware = job_.hardware();
  const bool both = camera == "stereo";
  if (!hardware.stereo || (!both && camera != hardware.stereo->left_camera &&
                           camera != hardware.stereo->right_camera)) {
    ++lines_refused_;
    out_ << "refused: capture takes a camera of the stereo pair"
         << (hardware.stereo ? " (" + hardware.stereo->left_camera + " or " +
                                   hardware.stereo->right_camera + ") or stereo for both"
                             : std::string(": this rig has none"))
         << ", found " << config::in_quotes(camera) << "\n";
    return;
  }
  if (images_ == nullptr) {
    ++lines_refused_;
    out_ << "refused: capture: the stereo images have another reader in this run (the ROS 2 "
            "bridge's images)\n";
    return;
  }
  (void)images_->acquire();
  const hal::StereoFrame& pair = images_->front();
  const hal::Image& image = camera == hardware.stereo->right_camera ? pair.right : pair.left;
  if (image.sequence == 0 || (both && pair.right.sequence == 0)) {
    out_ << "capture: no image yet (wait a little)\n";
    return;
  }
  if (!believed_.read(q_believed_rig_)) {
    out_ << "capture: the joints have not all reported yet (wait a little)\n";
    return;
  }
  try {
    const std::filesystem::path folder(directory);
    std::filesystem::create_directories(folder);
    const int view = next_view(folder, both ? "left" : "view");
    const std::string number = format("%02d", view);
    const std::string id = (both ? "pair" : "view") + number;
    std::string yaml = format(
        "# cambio console capture: camera %s, image stamp %.6f s, readings at %.6f s (run "
        "clock)\ncamera: %s\nimage_stamp_s: %.9f\n",
        camera.c_str(), static_cast<double>(image.stamp_ns) * 1e-9,
        static_cast<double>(now_ns) * 1e-9, camera.c_str(),
        static_cast<double>(image.stamp_ns) * 1e-9);
    if (both) {
      yaml +=
          format("right_image_stamp_s: %.9f\n", static_cast<double>(pair.right.stamp_ns) * 1e-9);
    }
    yaml += "joints_rad:\n";
    for (std::size_t i = 0; i < job_.joint_order().size(); ++i) {
      yaml += format("  %s: %.17g\n", job_.joint_order()[i].c_str(), q_believed_rig_[i]);
    }
    // The images first: a view is whole once its readings are there.
    std::string images;
    if (both) {
      const std::vector<std::uint8_t> left = encode_png(pair.left);
      const std::vector<std::uint8_t> right = encode_png(pair.right);
      write_whole(folder / ("left" + number + ".png"), std::string(left.begin(), left.end()));
      write_whole(folder / ("right" + number + ".png"), std::string(right.begin(), right.end()));
      images = (folder / ("left" + number + ".png")).string() + ", right" + number + ".png";
    } else {
      const std::vector<std::uint8_t> png = encode_png(image);
      write_whole(folder / (id + ".png"), std::string(png.begin(), png.end()));
      images = (folder / (id + ".png")).string();
    }
    write_whole(folder / (id + ".yaml"), yaml);
    out_ << "capture: wrote " << images << " and " << id << ".yaml (image at "
         << format("%.3f", static_cast<double>(image.stamp_ns) * 1e-9) << " s)\n";
  } catch (const std::exception& error) {
    ++lines_refused_;
    out_ << "refused: capture: " << error.what() << "\n";
  }
}

}  // namespace cambio::app
