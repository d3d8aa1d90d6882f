// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file PackAnalysis.hpp
/// The measures of a pack as `armour analyse` and `armour ensemble` report them: the scene's
/// World is built at the given state, its contacts evaluated (contact number, coordination
/// number, largest contact force), and the plain-data measures of armour::analysis applied
/// (orientation of a unit axis against the slope, P2 in both forms, packing density, layer
/// thickness and porosity, displacements from a reference state). docs/placement.md, "Analysis".
///
/// Units are the scene's movable bodies (or those whose name starts with a prefix); fixed bodies
/// (underlayer rocks) and the static geometry are supports. The slope frame is the scene's slope
/// (its face plane) when it has one, else the plane fitted through the units' centroids.

#include "analysis/Displacement.hpp"
#include "analysis/OrderParameters.hpp"
#include "analysis/Orientation.hpp"
#include "analysis/PackGeometry.hpp"
#include "io/Scene.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace armour::measure {

/// A pose per body name (from final_state.csv or a scene).
struct BodyPose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity(); ///< natural shape frame -> world
};
using PoseMap = std::map<std::string, BodyPose>;

/// Poses from a run's final_state.csv (columns name, x, y, z, qw, qx, qy, qz) or from a scene
/// file (its bodies). Throws core::InputError naming the file and line.
PoseMap readPoses(const std::filesystem::path& path);

/// The poses of a scene's bodies, by name.
PoseMap posesOf(const io::Scene& scene);

struct AnalyseSettings {
  std::string unitPrefix;          ///< units are the movable bodies whose name starts with it (empty: all)
  std::string axis = "nose";       ///< the unit axis for orientations and P2 (analysis::unitAxesOf)
  std::string stateName;           ///< where the state's poses came from, for messages (e.g. its file)
  analysis::DisplacementSettings displacement;
};

/// One unit's row of units.csv.
struct UnitRow {
  std::string name;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d local = Eigen::Vector3d::Zero(); ///< (s, t, n) in the slope frame (unit: m)
  double dn = 0.0;
  analysis::AxisAttitude attitude;
  Eigen::Vector2d stereo = Eigen::Vector2d::Zero();
  std::size_t contactNumber = 0, unitNeighbours = 0, supportNeighbours = 0;
  double maxContactForce = 0.0;   ///< unit: N
  /// Slope-normal height of the centroid above the underlayer's top under it (the highest top of
  /// the support bodies whose centroids lie within 1 Dn of the unit's in the slope plane, or the
  /// frame plane where there is none) (unit: Dn).
  double heightAboveUnderlayer = 0.0;
  /// Slope-normal height of the unit's highest point above the layer's base (the mean top of the
  /// underlayer's surface stones in the window, as the layer thickness is measured), NaN when the
  /// layer was not measured: the per-unit terms of the layer thickness (unit: Dn).
  double topAboveUnderlayer = std::nan("");
  /// The same for the unit's lowest point: below zero where it reaches into the underlayer's
  /// voids (unit: Dn).
  double bottomAboveUnderlayer = std::nan("");
  /// No support touched and the centroid more than 1 Dn above the underlayer: a unit lying on
  /// others (issue 24; the guidance wants every unit of a single layer on the underlayer).
  bool stacked = false;
  std::optional<analysis::UnitDisplacement> displacement;
};

struct PackReport {
  std::vector<UnitRow> units;
  analysis::SlopeFrame frame;
  bool frameFromSlope = false;
  analysis::OrderParameter p2Mean, p2Q;
  analysis::PackContacts contacts;
  analysis::PackingDensity packingHull;
  std::optional<analysis::LayerThickness> thickness;
  /// 1 - N V / (A t) over the hull (unit: -); 0 without a thickness; NaN when that falls outside
  /// [0, 1) (porosityNote says why: a hull of a few centroids is smaller than the units' footprint).
  double porosity = 0.0;
  std::string porosityNote;
  /// The layer's base for the thickness: the mean top of the surface stones (support bodies whose
  /// top no other support covers, analysis/UnderlayerSurface) whose centroids lie in the thickness
  /// window, slope-normal above the frame plane; 0 without any (unit: m).
  double underlayerTop = 0.0;
  double underlayerTopAllStones = 0.0; ///< the same over every support in the window, buried or not (unit: m)
  std::size_t surfaceStones = 0;      ///< supports whose top is exposed (unit: -)
  std::size_t supportStones = 0;      ///< supports (unit: -)
  std::size_t touchingUnderlayer = 0; ///< units that touch a support: rocks, the slope, the toe (unit: -)
  std::size_t stackedUnits = 0;       ///< units with UnitRow::stacked (unit: -)
  /// Units whose centroid lies past an edge of the static domain (StaticDomain::beyondEdge): they
  /// fell off the cut end of the scene's unbounded items (a slope's crest, a height field's plane).
  std::size_t unitsOffDomain = 0;
  std::optional<analysis::PackDisplacement> displacement;
  std::string axis;
  double rockingAngle = 0.0;        ///< the rocking threshold used (unit: rad)
};

/// Analyse `scene` at its bodies' poses (optionally overridden by `state`), with displacements
/// from `reference` when given. The World is built from the scene's own poses and its bodies then
/// moved to the state's, so that the static domain (where the unbounded items are cut) is the one
/// a run of the scene had: a unit that fell off its edge is not put inside a longer crest.
/// Throws core::InputError when the contacts at the state cannot be evaluated (bodies deep inside
/// each other or the static geometry), naming the state (AnalyseSettings::stateName).
PackReport analysePack(const io::Scene& scene, const AnalyseSettings& settings, const PoseMap* state = nullptr,
                       const PoseMap* reference = nullptr);

/// units.csv (the columns utilities/plot_pack.py reads), pack.json and pack.txt into `folder`.
void writePackReport(const PackReport& report, const std::filesystem::path& folder);

/// The pack summary as text lines.
std::string packText(const PackReport& report);

} // namespace armour::measure
