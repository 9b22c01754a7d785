#include "rendered_stereo_views.hpp"

#include <numbers>
#include <random>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

namespace cambio::testing {

namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

Eigen::Matrix3d rotation_rpy_deg(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw * kRadPerDeg, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch * kRadPerDeg, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll * kRadPerDeg, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

bool inside(const TrueCamera& camera, const std::optional<Eigen::Vector2d>& p_px) {
  constexpr double kMargin_px = 10.0;
  return p_px && p_px->x() > kMargin_px && p_px->y() > kMargin_px &&
         p_px->x() < camera.width_px - 1 - kMargin_px &&
         p_px->y() < camera.height_px - 1 - kMargin_px;
}

/// The board's outer corners (its white margin's), which bound everything on it.
std::vector<Eigen::Vector3d> outline_B(const TrueBoard& board) {
  const double s = board.square_m;
  const double x0 = -2 * s;
  const double y0 = -2 * s;
  const double x1 = (board.inner_columns + 1) * s;
  const double y1 = (board.inner_rows + 1) * s;
  return {{x0, y0, 0}, {x1, y0, 0}, {x0, y1, 0}, {x1, y1, 0}};
}

}  // namespace

TrueStereoPair true_stereo_pair() {
  TrueStereoPair pair;
  pair.left = {640, 480, 612.0, 608.5, 323.4, 236.8, {-0.21, 0.09, 0.0008, -0.0012, -0.015}};
  pair.right = {640, 480, 605.2, 603.9, 316.9, 243.1, {-0.18, 0.06, -0.0006, 0.0009, 0.0}};
  pair.X_LR.linear() = rotation_rpy_deg(0.6, -0.9, 0.4);
  pair.X_LR.translation() = Eigen::Vector3d(0.1195, 0.0015, -0.0010);
  return pair;
}

std::vector<Eigen::Isometry3d> board_poses(const TrueStereoPair& pair, const TrueBoard& board,
                                           int count) {
  std::mt19937 random(21);
  std::uniform_real_distribution<double> x_m(-0.06, 0.18);
  std::uniform_real_distribution<double> y_m(-0.13, 0.13);
  std::uniform_real_distribution<double> z_m(0.5, 0.85);
  std::uniform_real_distribution<double> tilt_deg(-30.0, 30.0);
  std::uniform_real_distribution<double> spin_deg(-15.0, 15.0);
  const Eigen::Vector3d centre_B((board.inner_columns - 1) * board.square_m / 2.0,
                                 (board.inner_rows - 1) * board.square_m / 2.0, 0.0);
  const Eigen::Isometry3d X_RL = pair.X_LR.inverse();
  std::vector<Eigen::Isometry3d> poses;
  for (int attempt = 0; attempt < 100000 && static_cast<int>(poses.size()) < count; ++attempt) {
    Eigen::Isometry3d X_LB = Eigen::Isometry3d::Identity();
    X_LB.linear() = rotation_rpy_deg(tilt_deg(random), tilt_deg(random), spin_deg(random));
    const Eigen::Vector3d centre_L(x_m(random), y_m(random), z_m(random));
    X_LB.translation() = centre_L - X_LB.linear() * centre_B;
    bool seen = true;
    for (const auto& p_B : outline_B(board)) {
      seen = seen && inside(pair.left, project_px(pair.left, X_LB * p_B)) &&
             inside(pair.right, project_px(pair.right, X_RL * X_LB * p_B));
    }
    if (seen) poses.push_back(X_LB);
  }
  if (static_cast<int>(poses.size()) < count) throw std::runtime_error("board_poses: too few");
  return poses;
}

void write_rendered_views(const TrueStereoPair& pair, const TrueBoard& board,
                          const std::vector<Eigen::Isometry3d>& poses,
                          const std::filesystem::path& directory) {
  std::filesystem::create_directories(directory);
  const BoardRenderer left(pair.left, 3);
  const BoardRenderer right(pair.right, 3);
  const Eigen::Isometry3d X_RL = pair.X_LR.inverse();
  for (std::size_t v = 0; v < poses.size(); ++v) {
    const std::string id = (v + 1 < 10 ? "0" : "") + std::to_string(v + 1);
    const std::string left_path = (directory / ("left" + id + ".png")).string();
    const std::string right_path = (directory / ("right" + id + ".png")).string();
    if (!cv::imwrite(left_path, left.render(board, poses[v])) ||
        !cv::imwrite(right_path, right.render(board, X_RL * poses[v]))) {
      throw std::runtime_error("write_rendered_views: cannot write into " + directory.string());
    }
  }
}

}  // namespace cambio::testing
