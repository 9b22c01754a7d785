#include "chessboard_renderer.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

namespace cambio::testing {

namespace {

constexpr double kBlack = 20.0;
constexpr double kWhite = 235.0;
constexpr double kWall = 128.0;

/// The texture's grey level at board point (x, y) in metres.
double board_grey(const TrueBoard& board, double x_m, double y_m) {
  const double column = std::floor(x_m / board.square_m);  // -1 is the first square.
  const double row = std::floor(y_m / board.square_m);
  const bool in_squares =
      column >= -1 && column <= board.inner_columns - 1 && row >= -1 && row <= board.inner_rows - 1;
  if (in_squares) {
    // The square left of and above corner (0, 0) is (-1, -1): black.
    const auto parity = static_cast<long>(column + row) & 1L;
    return parity == 0 ? kBlack : kWhite;
  }
  const bool in_margin =
      column >= -2 && column <= board.inner_columns && row >= -2 && row <= board.inner_rows;
  return in_margin ? kWhite : kWall;
}

}  // namespace

Eigen::Vector2d distort(const hal::PlumbBobDistortion& d, const Eigen::Vector2d& p) {
  const double x = p.x();
  const double y = p.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + d.k1 * r2 + d.k2 * r2 * r2 + d.k3 * r2 * r2 * r2;
  return {x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x),
          y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y};
}

std::optional<Eigen::Vector2d> undistort(const hal::PlumbBobDistortion& d,
                                         const Eigen::Vector2d& distorted) {
  Eigen::Vector2d p = distorted;
  constexpr double kStep = 1e-7;
  for (int iteration = 0; iteration < 50; ++iteration) {
    const Eigen::Vector2d residual = distort(d, p) - distorted;
    if (residual.norm() < 1e-12) return p;
    Eigen::Matrix2d jacobian;
    jacobian.col(0) = (distort(d, p + Eigen::Vector2d(kStep, 0.0)) - distort(d, p)) / kStep;
    jacobian.col(1) = (distort(d, p + Eigen::Vector2d(0.0, kStep)) - distort(d, p)) / kStep;
    p -= jacobian.inverse() * residual;
  }
  return std::nullopt;
}

std::optional<Eigen::Vector2d> project_px(const TrueCamera& camera, const Eigen::Vector3d& p_C) {
  if (!(p_C.z() > 1e-6)) return std::nullopt;
  const Eigen::Vector2d distorted = distort(camera.distortion, p_C.head<2>() / p_C.z());
  return Eigen::Vector2d(camera.focal_x_px * distorted.x() + camera.principal_x_px,
                         camera.focal_y_px * distorted.y() + camera.principal_y_px);
}

BoardRenderer::BoardRenderer(const TrueCamera& camera, int samples_per_side)
    : camera_(camera), samples_per_side_(samples_per_side) {
  const int n = samples_per_side;
  rays_.reserve(static_cast<std::size_t>(camera.width_px) * camera.height_px * n * n);
  for (int v = 0; v < camera.height_px; ++v) {
    for (int u = 0; u < camera.width_px; ++u) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const double u_px = u - 0.5 + (j + 0.5) / n;
          const double v_px = v - 0.5 + (i + 0.5) / n;
          const Eigen::Vector2d distorted((u_px - camera.principal_x_px) / camera.focal_x_px,
                                          (v_px - camera.principal_y_px) / camera.focal_y_px);
          const auto ray = undistort(camera.distortion, distorted);
          if (!ray) throw std::runtime_error("BoardRenderer: the distortion does not invert");
          rays_.emplace_back(ray->x(), ray->y(), 1.0);
        }
      }
    }
  }
}

cv::Mat BoardRenderer::render(const TrueBoard& board, const Eigen::Isometry3d& X_CB) const {
  const Eigen::Isometry3d X_BC = X_CB.inverse();
  // The board's plane in the camera frame: a ray p = s * (x, y, 1) meets it where
  // n . (p - o) = 0, o its origin and n its z axis.
  const Eigen::Vector3d o_C = X_CB.translation();
  const Eigen::Vector3d n_C = X_CB.linear().col(2);
  const int samples = samples_per_side_ * samples_per_side_;
  cv::Mat image(camera_.height_px, camera_.width_px, CV_8UC1);
  std::size_t k = 0;
  for (int v = 0; v < camera_.height_px; ++v) {
    for (int u = 0; u < camera_.width_px; ++u) {
      double sum = 0.0;
      for (int sample = 0; sample < samples; ++sample, ++k) {
        const Eigen::Vector3d& direction = rays_[k];
        const double facing = n_C.dot(direction);
        const double s = std::abs(facing) < 1e-12 ? -1.0 : n_C.dot(o_C) / facing;
        if (s <= 0.0) {
          sum += kWall;
          continue;
        }
        const Eigen::Vector3d p_B = X_BC * (s * direction);
        sum += board_grey(board, p_B.x(), p_B.y());
      }
      image.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(std::lround(sum / samples));
    }
  }
  return image;
}

}  // namespace cambio::testing
