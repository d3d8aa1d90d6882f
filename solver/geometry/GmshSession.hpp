// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file GmshSession.hpp
/// Scoped access to the gmsh library (OpenCASCADE solid modelling and tetrahedral meshing).
/// gmsh keeps one global model, so a session holds a process-wide lock: sessions are serialised
/// and each starts from an empty model. Units are whatever the caller uses (metres here).

#include "geometry/TriangleMesh.hpp"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace armour::geometry {

using GmshEntity = std::pair<int, int>; ///< (dimension, tag) as in the gmsh API

class GmshSession {
public:
  /// Lock gmsh, initialise it on first use, and start a fresh model named `model`.
  explicit GmshSession(const std::string& model);
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

  /// Fuse OpenCASCADE volumes into one; returns the resulting volume entities.
  std::vector<GmshEntity> fuse(const std::vector<GmshEntity>& objects, const std::vector<GmshEntity>& tools);
  /// Cut tools out of objects; returns the resulting volume entities.
  std::vector<GmshEntity> cut(const std::vector<GmshEntity>& objects, const std::vector<GmshEntity>& tools);

  /// Exact CAD volume of the OpenCASCADE volumes (m^3), for reporting and tests.
  double occVolume(const std::vector<GmshEntity>& volumes);

  /// Mesh the boundary of the current OpenCASCADE model (synchronises first) and return it as one
  /// welded triangle mesh (orientation not yet checked: pass it through validateMesh).
  /// @param sizeMax largest element edge (m)
  /// @param elementsPerTwoPi curvature refinement: elements per full turn on curved faces (0 = off)
  TriangleMesh meshSurface(double sizeMax, int elementsPerTwoPi = 24);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace armour::geometry
