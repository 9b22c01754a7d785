#pragma once

// `cambio can-bench`'s PDO figure: frames packed and unpacked per second on one core, with
// pdo_layout's minimum set (RPDO1 and TPDO1 of a CSP drive).

namespace cambio::app {

/// Packs and unpacks RPDO1 and TPDO1 of a CSP drive `frame_pairs` times; returns frames (one
/// pack plus one unpack each) per second.
double pdo_frames_per_s(long long frame_pairs);

}  // namespace cambio::app
