// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ReadOrientation.hpp
/// The `orientation:` block shared by the scene files (internal to io): a rotation from the body's
/// frame to the world as a quaternion or Tait-Bryan angles (docs/scene-file.md).

#include "io/Scene.hpp"
#include "io/YamlSchema.hpp"

#include <cmath>
#include <numbers>

namespace armour::io::schema {

inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;

inline const KeyList kOrientationKeys{"quaternion", "euler_deg"};

/// `orientation: {quaternion: [w, x, y, z]} | {euler_deg: [phi, theta, psi]}`; identity if absent.
inline Quat readOrientation(const Block& parent, std::string_view key) {
  if (!parent.has(key)) return Quat::Identity();
  const Block b(parent.context(), parent.get(key), parent.path(key), kOrientationKeys);
  const int which = b.oneOf(kOrientationKeys, false, "a rotation from the body frame to the world");
  if (which == 0) {
    const auto q = b.numbers("quaternion", 4, {"-", kAnyNumber, "[1, 0, 0, 0] for no rotation, [w, x, y, z]"});
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    // 1e-300 catches an all-zero quaternion; anything representable above it can be normalised.
    if (!(norm > 1e-300))
      b.failValue("quaternion", "a zero quaternion is not a rotation; give [w, x, y, z] with w^2 + x^2 + y^2 + z^2 = 1, "
                                "e.g. [1, 0, 0, 0] for no rotation");
    Quat result(q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm);
    // 1e-6 lets values typed to 7 digits (0.7071068) pass silently while a real slip ([1, 0, 0, 1]) is reported.
    if (std::abs(norm - 1.0) > 1e-6)
      b.warnValue("quaternion", fmt::format("not a unit quaternion (norm {:.9g}); normalised to [{:.9g}, {:.9g}, {:.9g}, {:.9g}]",
                                            norm, result.w(), result.x(), result.y(), result.z()));
    return result;
  }
  const auto a = b.numbers("euler_deg", 3, {"deg", kAnyNumber, "[0, 90, 0]: phi about x, theta about y', psi about z''"});
  return quaternionFromTaitBryan(a[0] * kRadPerDeg, a[1] * kRadPerDeg, a[2] * kRadPerDeg);
}

} // namespace armour::io::schema
