#include "console_session.hpp"

#include <algorithm>

#include <opencv2/core.hpp>

#include "console_session_detail.hpp"
#include "feature_map_image.hpp"
#include "image_files.hpp"
#include "output_directory.hpp"

namespace cambio::app {
namespace {

using console::detail::format;

// The SSM's latest summary: its frame, disparity, and each eye's motion and moments at the fovea.
void print_ssm_summary(std::ostream& out, const perception::SsmSummary& s) {
  const auto& d = s.disparity;
  out << format("ssm frame %llu at %.3f s: %d levels, %.0f us\n",
                static_cast<unsigned long long>(s.sequence), static_cast<double>(s.stamp_ns) * 1e-9,
                s.levels, s.timings.total_us);
  out << (d.valid ? format("  disparity %.2f px (confidence %.2f, level %d)\n",
                           static_cast<double>(d.disparity_px), static_cast<double>(d.confidence),
                           d.level)
                  : std::string("  disparity invalid (no texture or no match)\n"));
  for (int eye = 0; eye < 2; ++eye) {
    const auto e = static_cast<std::size_t>(eye);
    const auto& m = s.motion[e];
    const auto& moments = s.moments[e][0];
    out << format("  %s eye: fixation (%d, %d) px; motion %s; moments L0 %s\n",
                  eye == 0 ? "left" : "right", s.fixation[e].x, s.fixation[e].y,
                  m.valid ? format("(%.2f, %.2f) px/frame", static_cast<double>(m.flow_x_px),
                                   static_cast<double>(m.flow_y_px))
                                .c_str()
                          : "none",
                  moments.valid
                      ? format("area %.0f px2, centroid (%.1f, %.1f) px", moments.area_px2,
                               moments.centroid_x_px, moments.centroid_y_px)
                            .c_str()
                      : "empty");
  }
}

// Stages every map of `frame`, each eye and level, as a grey PNG named after the eye, the level
// and the map. Throws what OutputDirectory and encode_png throw.
void stage_feature_maps(OutputDirectory& out, const perception::SensoryServo& servo,
                        const perception::SsmFrame& frame) {
  const int w = servo.config().retina.width_px;
  const int h = servo.config().retina.height_px;
  const auto& specs = servo.operators().maps();
  for (int eye = 0; eye < 2; ++eye) {
    for (int k = 0; k < frame.summary.levels; ++k) {
      for (std::size_t i = 0; i < specs.size(); ++i) {
        const bool signed_map = is_signed_map(specs[i]);
        const cv::Mat tile =
            feature_map_tile(frame.maps[static_cast<std::size_t>(eye)].map(k, static_cast<int>(i)),
                             w, h, signed_map, w, h);
        hal::Image png(w, h, hal::PixelFormat::kGrey8);
        std::copy(tile.datastart, tile.dataend, png.pixels.begin());
        out.stage(format("%s_L%d_%s.png", eye == 0 ? "left" : "right", k, specs[i].name.c_str()),
                  encode_png(png));
      }
    }
  }
}

}  // namespace

void ConsoleSession::print_ssm(const std::string& save_directory) {
  perception::SsmServer* ssm = job_.perception();
  if (ssm == nullptr) {
    ++lines_refused_;
    out_ << "refused: this rig has no stereo pair, so no SSM\n";
    return;
  }
  if (!features_requested_) {
    // Everything the SSM computes, from its next frame on (the gaze alone asks for disparity,
    // and motion while pursuing).
    const behaviour::ActionResult asked = actions_.request_features(perception::FeatureRequest{});
    features_requested_ = asked.sent;
    if (asked.sent) {
      out_ << "ssm: every feature (motion, moments, all maps) requested from now on\n";
    }
  }
  perception::SsmSummary s;
  if (!ssm->summaries().read(s) || s.sequence == 0) {
    out_ << "ssm: no frame processed yet (wait a little)\n";
    return;
  }
  print_ssm_summary(out_, s);
  if (save_directory.empty()) return;

  // The maps: the loops are idle, so this thread may read the SSM's frame buffer.
  const perception::SensoryServo* servo = ssm->servo();
  auto& frames = ssm->frames();
  frames.acquire();
  const perception::SsmFrame& frame = frames.front();
  if (servo == nullptr || frame.summary.sequence == 0) {
    out_ << "ssm: no maps yet\n";
    return;
  }
  try {
    OutputDirectory out(save_directory, "console");
    stage_feature_maps(out, *servo, frame);
    out.commit();
    out_ << "ssm: wrote " << out.files().size() << " maps of frame " << frame.summary.sequence
         << " to " << out.path().string() << "\n";
  } catch (const std::exception& error) {
    ++lines_refused_;
    out_ << "refused: ssm save: " << error.what() << "\n";
  }
}

}  // namespace cambio::app
