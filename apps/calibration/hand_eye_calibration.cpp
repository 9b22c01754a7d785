#include "hand_eye_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace cambio::app {

namespace {

cv::Mat rotation_mat(const Eigen::Isometry3d& X) {
  cv::Mat R;
  const Eigen::Matrix3d rotation = X.rotation();
  cv::eigen2cv(rotation, R);
  return R;
}

cv::Mat translation_mat(const Eigen::Isometry3d& X) {
  cv::Mat t;
  const Eigen::Vector3d translation = X.translation();
  cv::eigen2cv(translation, t);
  return t;
}

/// X moved by a small twist (rotation vector, translation) in its own frame.
Eigen::Isometry3d moved(const Eigen::Isometry3d& X, const Eigen::Matrix<double, 6, 1>& delta) {
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d w = delta.head<3>();
  if (w.norm() > 0.0)
    step.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  step.translation() = delta.tail<3>();
  return X * step;
}

/// The corners' reprojection residuals of every view (x, y per corner) for the mount X_PC and
/// the board's pose X_BT.
Eigen::VectorXd reprojection_residuals(std::span<const HandEyeView> views,
                                       const HandEyeTarget& target, const Eigen::Isometry3d& X_PC,
                                       const Eigen::Isometry3d& X_BT) {
  const cv::Matx33d K(target.focal_x_px, 0.0, target.principal_x_px, 0.0, target.focal_y_px,
                      target.principal_y_px, 0.0, 0.0, 1.0);
  const std::array<double, 5> d = target.distortion.opencv_order();
  const cv::Mat distortion(1, 5, CV_64F, const_cast<double*>(d.data()));
  std::vector<cv::Point3d> object;
  for (const Eigen::Vector3d& p : target.corners_T_m) object.emplace_back(p.x(), p.y(), p.z());
  const std::size_t corners = object.size();
  Eigen::VectorXd residuals(static_cast<Eigen::Index>(2 * corners * views.size()));
  std::vector<cv::Point2d> projected;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const Eigen::Isometry3d X_CT = (views[v].X_BP * X_PC).inverse() * X_BT;
    cv::Mat R, rvec;
    const Eigen::Matrix3d rotation = X_CT.rotation();
    cv::eigen2cv(rotation, R);
    cv::Rodrigues(R, rvec);
    const cv::Vec3d tvec(X_CT.translation().x(), X_CT.translation().y(), X_CT.translation().z());
    cv::projectPoints(object, rvec, tvec, K, distortion, projected);
    for (std::size_t i = 0; i < corners; ++i) {
      const auto row = static_cast<Eigen::Index>(2 * (v * corners + i));
      residuals[row] = projected[i].x - views[v].corners_px[i].x();
      residuals[row + 1] = projected[i].y - views[v].corners_px[i].y();
    }
  }
  return residuals;
}

/// Levenberg-Marquardt over the mount and the board's pose (12 parameters, a numerical Jacobian).
void refine(std::span<const HandEyeView> views, const HandEyeTarget& target,
            Eigen::Isometry3d& X_PC, Eigen::Isometry3d& X_BT) {
  using Vector12 = Eigen::Matrix<double, 12, 1>;
  const auto apply = [](const Eigen::Isometry3d& mount, const Eigen::Isometry3d& board,
                        const Vector12& delta, Eigen::Isometry3d& mount_out,
                        Eigen::Isometry3d& board_out) {
    mount_out = moved(mount, delta.head<6>());
    board_out = moved(board, delta.tail<6>());
  };
  Eigen::VectorXd r = reprojection_residuals(views, target, X_PC, X_BT);
  double lambda = 1e-3;
  for (int iteration = 0; iteration < 50; ++iteration) {
    Eigen::MatrixXd J(r.size(), 12);
    for (int k = 0; k < 12; ++k) {
      Vector12 delta = Vector12::Zero();
      const double h = k % 6 < 3 ? 1e-7 : 1e-8;  // rad, m
      delta[k] = h;
      Eigen::Isometry3d mount, board;
      apply(X_PC, X_BT, delta, mount, board);
      J.col(k) = (reprojection_residuals(views, target, mount, board) - r) / h;
    }
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Vector12 g = J.transpose() * r;
    bool improved = false;
    while (lambda < 1e6) {
      Eigen::MatrixXd A = JtJ;
      A.diagonal() *= 1.0 + lambda;
      const Vector12 delta = -A.ldlt().solve(g);
      Eigen::Isometry3d mount, board;
      apply(X_PC, X_BT, delta, mount, board);
      const Eigen::VectorXd candidate = reprojection_residuals(views, target, mount, board);
      if (candidate.squaredNorm() < r.squaredNorm()) {
        const bool converged = r.squaredNorm() - candidate.squaredNorm() < 1e-12 * r.squaredNorm();
        X_PC = mount;
        X_BT = board;
        r = candidate;
        lambda = std::max(lambda / 10.0, 1e-9);
        improved = !converged;
        break;
      }
      lambda *= 10.0;
    }
    if (!improved) break;
  }
}

}  // namespace

double largest_motion_axis_angle_rad(std::span<const HandEyeView> views) {
  // The axes of the link's rotations from the first view to each other one.
  std::vector<Eigen::Vector3d> axes;
  for (std::size_t i = 1; i < views.size(); ++i) {
    const Eigen::AngleAxisd motion((views[0].X_BP.inverse() * views[i].X_BP).rotation());
    if (motion.angle() > 1e-3) axes.push_back(motion.axis());
  }
  double largest = 0.0;
  for (std::size_t i = 0; i < axes.size(); ++i) {
    for (std::size_t j = i + 1; j < axes.size(); ++j) {
      // Axes, not directions: a turn about -a is a turn about a.
      const double angle = std::acos(std::clamp(std::abs(axes[i].dot(axes[j])), 0.0, 1.0));
      largest = std::max(largest, angle);
    }
  }
  return largest;
}

HandEyeCalibration calibrate_hand_eye(std::span<const HandEyeView> views,
                                      const HandEyeTarget& target) {
  if (views.size() < kMinHandEyeViews) {
    throw std::invalid_argument("hand-eye calibration: " + std::to_string(views.size()) +
                                " views, at least " + std::to_string(kMinHandEyeViews));
  }
  // OpenCV's names: the gripper is the camera's link, the target the board.
  std::vector<cv::Mat> R_gripper2base, t_gripper2base, R_target2cam, t_target2cam;
  for (const HandEyeView& view : views) {
    R_gripper2base.push_back(rotation_mat(view.X_BP));
    t_gripper2base.push_back(translation_mat(view.X_BP));
    R_target2cam.push_back(rotation_mat(view.X_CT));
    t_target2cam.push_back(translation_mat(view.X_CT));
  }
  cv::Mat R_cam2gripper, t_cam2gripper;
  cv::calibrateHandEye(R_gripper2base, t_gripper2base, R_target2cam, t_target2cam, R_cam2gripper,
                       t_cam2gripper, cv::CALIB_HAND_EYE_PARK);
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  cv::cv2eigen(R_cam2gripper, R);
  cv::cv2eigen(t_cam2gripper, t);

  HandEyeCalibration result;
  result.X_PC.linear() = R;
  result.X_PC.translation() = t;
  // The board where the views put it on average (the first view's orientation), then both refined.
  Eigen::Isometry3d board = views[0].X_BP * result.X_PC * views[0].X_CT;
  Eigen::Vector3d sum_m = Eigen::Vector3d::Zero();
  for (const HandEyeView& view : views)
    sum_m += (view.X_BP * result.X_PC * view.X_CT).translation();
  board.translation() = sum_m / static_cast<double>(views.size());
  refine(views, target, result.X_PC, board);
  const Eigen::VectorXd residuals = reprojection_residuals(views, target, result.X_PC, board);
  result.reprojection_rms_px =
      std::sqrt(residuals.squaredNorm() / (0.5 * static_cast<double>(residuals.size())));
  Eigen::Vector3d mean_m = Eigen::Vector3d::Zero();
  for (const HandEyeView& view : views) {
    result.X_BT.push_back(view.X_BP * result.X_PC * view.X_CT);
    mean_m += result.X_BT.back().translation();
  }
  mean_m /= static_cast<double>(views.size());
  double sum_m2 = 0.0;
  double sum_rad2 = 0.0;
  for (const Eigen::Isometry3d& X_BT : result.X_BT) {
    sum_m2 += (X_BT.translation() - mean_m).squaredNorm();
    const double angle = Eigen::AngleAxisd(board.rotation().transpose() * X_BT.rotation()).angle();
    sum_rad2 += angle * angle;
  }
  result.board_spread_m = std::sqrt(sum_m2 / static_cast<double>(views.size()));
  result.board_spread_rad = std::sqrt(sum_rad2 / static_cast<double>(views.size()));
  return result;
}

}  // namespace cambio::app
