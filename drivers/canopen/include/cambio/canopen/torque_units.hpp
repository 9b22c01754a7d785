#pragma once

// Joint-side torque <-> a CiA 402 drive's torque objects (0x6077 torque actual value, 0x60B2
// torque offset), which count per mille of the motor's rated torque (0x6076, read in mN m).
//
// Convention: an ideal gear (rigid, lossless) of `gear_ratio` motor turns per joint turn, the
// ratio cia402::Units uses for positions. Power balance, tau_joint * omega_joint =
// tau_motor * omega_motor with omega_motor = gear_ratio * omega_joint, gives
//   tau_joint_nm = tau_motor_nm * gear_ratio
//   per_mille    = 1000 * tau_motor_nm / rated_torque_nm
//                = 1000 * tau_joint_nm / (gear_ratio * rated_torque_nm)
// A negative gear ratio turns the motor the other way: the torque's sign flips with the
// position's. Header-only, no allocation: the loop side converts every cycle.

#include <cmath>
#include <cstdint>

namespace cambio::canopen {

struct TorqueUnits {
  double rated_torque_nm = 0.0;  ///< 0: unknown; both conversions then give 0.
  double gear_ratio = 1.0;

  /// Rounded to the nearest per mille; saturates at the INTEGER16 range; 0 for a non-finite
  /// torque or an unknown rated torque.
  std::int16_t to_per_mille(double joint_torque_nm) const {
    const double scale = gear_ratio * rated_torque_nm;
    if (scale == 0.0 || !std::isfinite(joint_torque_nm)) return 0;
    const double per_mille = std::round(1000.0 * joint_torque_nm / scale);
    if (!(per_mille > -32768.0)) return INT16_MIN;
    if (!(per_mille < 32767.0)) return INT16_MAX;
    return static_cast<std::int16_t>(per_mille);
  }
  double to_joint_nm(std::int16_t per_mille) const {
    return static_cast<double>(per_mille) * 1e-3 * rated_torque_nm * gear_ratio;
  }
};

}  // namespace cambio::canopen
