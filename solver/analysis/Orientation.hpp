// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Orientation.hpp
/// Attitude of the units' axes relative to the slope: the "stereographic plot of unit nose axis dip
/// angle and dip azimuth with reference to the average slope plane and breakwater trunk axis" of
/// seed 000 (section 2.1, Fig. 2c). docs/theory.md, "Pack measures".
///
/// The slope frame (axes of the project: x onshore, y along the trunk, z up). The armour slope
/// rises onshore, z = z0 + (x - x0) tan(alpha):
///
///        n (out of the slope: up and offshore)
///         \                 /  s (up-slope: onshore and up)
///          \              /
///           \           /     t = +y points into the page:
///            \        /       the reader stands on the -y
///             \     /         side looking along +y
///              \  /
/// ~~~~~~~~~~~~~ o ------------------> x (onshore)
///    water        o: a point of the plane; alpha between s and x
///
///   s = (cos a, 0, sin a), t = (0, 1, 0), n = s x t = (-sin a, 0, cos a): (s, t, n) is right-handed.
///
/// Attitude of an axis (geology's dip and dip azimuth, with the slope plane in place of the
/// horizontal):
///  - An axis is a line: u and -u are the same axis. Like a geologist's lower-hemisphere pole, the
///    sign is chosen so that the axis points into the slope (u . n <= 0). For an axis in the plane
///    (|u . n| <= 1e-12: round-off) both signs qualify; the one with dip azimuth in [0, pi) is
///    taken.
///  - dip = the angle between the axis and the slope plane, in [0, pi/2]: 0 in the plane, pi/2
///    along -n (normal to the slope, pointing in).
///  - dip azimuth = the direction of the axis' projection on the plane, measured in the plane from
///    the trunk axis t towards the down-slope direction -s, in [0, 2 pi): t is 0, -s (down-slope)
///    pi/2, -t pi, s (up-slope) 3 pi/2. Seen from outside the slope (from +n) the angle turns
///    counter-clockwise, because n x t = -s. For an axis along -n (in-plane part <= 1e-12) it is
///    undefined and set to 0.
///
/// The stereonet (equal-area Schmidt net, lower hemisphere: the axes pointing into the slope) is
/// drawn as seen from outside the slope by someone standing offshore facing it: up-slope at the
/// top, down-slope at the bottom, +t (+y) on the left, -t on the right. A pole at dip d and dip
/// azimuth b plots at radius r = sqrt(2) sin((pi/2 - d)/2) (1 on the rim for d = 0, 0 at the
/// centre for d = pi/2), at
///     X = -r cos b,  Y = -r sin b,
/// so b = 0 (t) is on the left, pi/2 (down-slope) at the bottom. The projection preserves area:
/// the fraction of isotropic axes within radius r is r^2.
///
/// Body axes: the shapes of geometry::ShapeLibrary come out of makeShape() in the generator's
/// natural frame, translated to the centroid and scaled (directions are unchanged); an orientation
/// is the quaternion taking that frame to the world (body -> world), so a body axis a is
/// q * a in the world.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace armour::analysis {

/// The average slope plane with its up-slope direction s, trunk axis t = +y and outward normal
/// n = s x t (up and offshore). s lies in the x-z plane.
struct SlopeFrame {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();   ///< a point of the plane (unit: m)
  Eigen::Vector3d upSlope = Eigen::Vector3d::UnitX(); ///< s, unit vector (unit: -)
  Eigen::Vector3d trunk = Eigen::Vector3d::UnitY();   ///< t, unit vector (unit: -)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< n = s x t, unit vector (unit: -)

  /// The plane z - point.z = (x - point.x) tan(alpha) through `point`; tanAlpha > 0 for a seaward
  /// slope, 0 for a flat floor (a test pack). A negative value (a plane falling onshore, e.g. a
  /// noisy fit of a flat floor) is accepted: s then points onshore and down, n stays up. Throws
  /// core::InputError for a non-finite slope or point.
  [[nodiscard]] static SlopeFrame fromTanAlpha(double tanAlpha, const Eigen::Vector3d& point);

  /// (s, t, n) coordinates of a world point relative to the origin (unit: m).
  [[nodiscard]] Eigen::Vector3d toLocal(const Eigen::Vector3d& world) const;
  /// World point of (s, t, n) coordinates (unit: m).
  [[nodiscard]] Eigen::Vector3d toWorld(const Eigen::Vector3d& local) const;
  /// tan(alpha) of the plane: s_z / s_x (unit: -).
  [[nodiscard]] double tanAlpha() const { return upSlope.z() / upSlope.x(); }
};

/// Least-squares plane through `points` containing the trunk direction: z = a + b x fitted by
/// ordinary least squares (minimising the vertical residuals), tan(alpha) = b, origin = the
/// centroid of the points (which lies on the fitted plane). Fitted through unit centroids it is
/// parallel to the armour layer, about half a layer above the underlayer: for orientations only
/// the direction matters. Throws core::InputError for fewer than 2 points, a non-finite point, or
/// all points at the same x.
[[nodiscard]] SlopeFrame fitSlopeFrame(const std::vector<Eigen::Vector3d>& points);

/// Dip and dip azimuth of an axis (see the file comment for the conventions).
struct AxisAttitude {
  double dip = 0.0;        ///< angle below the slope plane, [0, pi/2] (unit: rad)
  double dipAzimuth = 0.0; ///< in the plane from t towards down-slope, [0, 2 pi) (unit: rad)
};

/// Attitude of a world-frame axis (need not be unit). Throws core::InputError for a zero or
/// non-finite axis.
[[nodiscard]] AxisAttitude attitude(const Eigen::Vector3d& axisWorld, const SlopeFrame& frame);

/// The unit axis pointing into the slope with this attitude (the inverse of attitude()).
[[nodiscard]] Eigen::Vector3d axisFromAttitude(const AxisAttitude& a, const SlopeFrame& frame);

/// World axes q_i * a of one body axis a for every orientation (body -> world). Throws
/// core::InputError, naming the unit, for a zero or non-finite quaternion, or a zero axis.
[[nodiscard]] std::vector<Eigen::Vector3d> noseAxesWorld(const std::vector<Eigen::Quaterniond>& orientations,
                                                         const Eigen::Vector3d& noseAxisBody);

/// Equal-area (Schmidt) lower-hemisphere coordinates (X, Y) of an attitude in the unit disc.
[[nodiscard]] Eigen::Vector2d stereonetPoint(const AxisAttitude& a);

/// A named body-frame axis of a library shape.
struct UnitAxis {
  std::string name;                                ///< e.g. "nose", "shank"
  Eigen::Vector3d body = Eigen::Vector3d::UnitZ(); ///< unit vector in the shape's frame (unit: -)
  std::string description;                         ///< what the axis is, in words
};

/// The named axes of a geometry::ShapeLibrary shape, the stereonet's axis ("nose") first. Rocks
/// have none (empty). Throws core::InputError for an unknown shape name.
///
///   coreloc     nose = +x, the central member's axis (assumption: seed 000 does not define the
///               nose; the central member is the unit's single symmetry axis in its plane);
///               outer = +z, the outer members' axis; normal = +y, normal to the unit's plane
///   xbloc       nose = +y, the noses' axis; up = +z
///   dolos       nose = shank = +z; upper-fluke = +x, lower-fluke = +y (seed 001's axis "normal
///               to the shank" is one of the flukes)
///   antifer     nose = +z, the taper axis (base to the narrower top)
///   cube        nose = +z (the aspect_z edge), x, y
///   accropode   nose = body = +z; upper-horns = +x, lower-horns = +y
///   tetrapod    nose = +z, the upper leg
///   cubipod     nose = +z
///   vcross, vrcross  nose = +z, one arm
[[nodiscard]] const std::vector<UnitAxis>& unitAxesOf(const std::string& shapeName);

/// The body axis called `axisName` of a shape; throws core::InputError naming the shape and
/// listing its axes (or the shapes that have axes, for a rock).
[[nodiscard]] Eigen::Vector3d unitAxisOf(const std::string& shapeName, const std::string& axisName);

/// The stereonet's axis of a shape (the first of unitAxesOf). Throws core::InputError for a shape
/// without one (rocks), naming it and listing the shapes that have one.
[[nodiscard]] Eigen::Vector3d noseAxisOf(const std::string& shapeName);

} // namespace armour::analysis
