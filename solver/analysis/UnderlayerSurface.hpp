// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file UnderlayerSurface.hpp
/// The top of an underlayer: the mean top of its surface stones, the base from which an armour
/// layer's thickness is measured. docs/theory.md, "Pack measures" (layer thickness).
///
/// A rock underlayer is two or three stones thick. The layer thickness of the armour (t = n k_t Dn,
/// the guidance's k_t) is measured from the underlayer's surface, the tops of the stones a survey
/// reaches, not from the mean top of every stone: the buried ones lie up to two stone sizes lower
/// and would add that to the armour's thickness. A stone is a *surface stone* when its top point
/// is exposed: the line from its highest point along the slope normal, outwards, meets no other
/// stone. The rule is ours (a geometric reading of "the tops of the underlayer stones"); its
/// effect on the seed-000 trunk is in docs/placement.md.

#include "analysis/Orientation.hpp"
#include "analysis/PackGeometry.hpp"
#include "geometry/TriangleMesh.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace armour::analysis {

/// A support body as the survey sees it: its shape's mesh (body frame, scale 1), its scale and
/// its pose (body -> world). The mesh is borrowed and must outlive the call.
struct PosedMesh {
  const geometry::TriangleMesh* mesh = nullptr;
  double scale = 1.0;                                          ///< (unit: -)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();           ///< (unit: m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

/// Each support body's top and whether it is a surface stone.
struct SurfaceStones {
  std::vector<Eigen::Vector3d> local; ///< centroids in the slope frame (s, t, n) (unit: m)
  std::vector<double> top;            ///< the highest point's n (unit: m)
  std::vector<bool> exposed;          ///< the line from the top along +n meets no other body
  std::size_t exposedCount = 0;       ///< (unit: -)
};

/// Tops and surface stones of `bodies` in `frame` (whose normal points out of the underlayer).
/// Bodies sharing a mesh share its ray caster. Cost: one ray per body against the bodies whose
/// projected bounding circles contain its top (a 2D bin of the slope plane). Throws
/// core::InputError for a missing mesh or a non-positive scale (naming the body's index).
[[nodiscard]] SurfaceStones surfaceStones(const std::vector<PosedMesh>& bodies, const SlopeFrame& frame);

/// The mean top (n, m) of the surface stones whose centroids project into the window; with
/// `surfaceOnly` false, of every stone there (the old measure, kept for comparison). 0, the frame
/// plane, when none does.
[[nodiscard]] double meanTopIn(const SurfaceStones& stones, const SlopeWindow& window, bool surfaceOnly = true);

} // namespace armour::analysis
