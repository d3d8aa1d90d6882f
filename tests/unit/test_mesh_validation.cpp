// SPDX-License-Identifier: GPL-3.0-or-later
// Every broken-mesh kind produces its own specific error; orientation is repaired only where that
// is unambiguous.

#include "geometry/MassProperties.hpp"
#include "geometry/MeshValidation.hpp"
#include "support/TestMeshes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <optional>
#include <set>

using namespace armour::geometry;
using namespace armour::test;

namespace {

/// Validate and return the defect, or nullopt when the mesh is accepted.
std::optional<MeshDefect> defectOf(TriangleMesh mesh, ValidationOptions options = {}, std::string* message = nullptr) {
  try {
    validateMesh(mesh, "test.stl", options);
  } catch (const MeshError& e) {
    if (message != nullptr) {
      *message = e.what();
    }
    return e.defect();
  }
  return std::nullopt;
}

/// The hemi-icosahedron: the icosahedron with antipodal vertices identified, a closed triangulation
/// of the projective plane (6 vertices, 10 faces, 15 edges, each edge in two faces): watertight,
/// manifold and non-orientable.
TriangleMesh makeProjectivePlane() {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> ico;
  for (double s1 : {-1.0, 1.0}) {
    for (double s2 : {-1.0, 1.0}) {
      ico.emplace_back(0, s1, s2 * phi);
      ico.emplace_back(s1, s2 * phi, 0);
      ico.emplace_back(s2 * phi, 0, s1);
    }
  }
  // Faces of the icosahedron: triples of mutually adjacent vertices (edge length 2).
  std::vector<std::array<int, 3>> faces;
  const auto adjacent = [&](int i, int j) { return std::abs((ico[i] - ico[j]).norm() - 2.0) < 1e-9; };
  for (int i = 0; i < 12; ++i)
    for (int j = i + 1; j < 12; ++j)
      for (int k = j + 1; k < 12; ++k)
        if (adjacent(i, j) && adjacent(j, k) && adjacent(i, k)) faces.push_back({i, j, k});
  // Identify v with -v: representative = the one with the lexicographically positive coordinates.
  std::map<int, int> rep;
  std::vector<Vec3> kept;
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < i; ++j) {
      if ((ico[i] + ico[j]).norm() < 1e-9) {
        rep[i] = rep[j];
      }
    }
    if (!rep.count(i)) {
      rep[i] = static_cast<int>(kept.size());
      kept.push_back(ico[i]);
    }
  }
  TriangleMesh m;
  m.vertices = kept;
  std::set<std::array<int, 3>> seen;
  for (const auto& f : faces) {
    std::array<int, 3> g{rep[f[0]], rep[f[1]], rep[f[2]]};
    auto key = g;
    std::sort(key.begin(), key.end());
    if (seen.insert(key).second) {
      m.triangles.push_back({g[0], g[1], g[2]});
    }
  }
  return m;
}

} // namespace

TEST(MeshValidation, ValidBoxPasses) {
  auto box = makeBox(1, 2, 3);
  const auto report = validateMesh(box, "box");
  EXPECT_EQ(report.flippedFaces, 0u);
  EXPECT_FALSE(report.inverted);
  EXPECT_TRUE(inspectMesh(box).valid());
}

TEST(MeshValidation, EmptyMesh) { EXPECT_EQ(defectOf(TriangleMesh{}), MeshDefect::Empty); }

TEST(MeshValidation, NonFiniteCoordinate) {
  auto box = makeBox(1, 1, 1);
  box.vertices[3].y() = std::nan("");
  EXPECT_EQ(defectOf(box), MeshDefect::NonFinite);
}

TEST(MeshValidation, IndexOutOfRange) {
  auto box = makeBox(1, 1, 1);
  box.triangles[5][2] = 8;
  EXPECT_EQ(defectOf(box), MeshDefect::BadIndex);
}

TEST(MeshValidation, OpenEdgesAreListed) {
  auto box = makeBox(1, 1, 1);
  box.triangles.pop_back(); // a hole: three edges now have one face only
  std::string message;
  EXPECT_EQ(defectOf(box, {}, &message), MeshDefect::OpenEdges);
  EXPECT_NE(message.find("test.stl"), std::string::npos) << message;
  EXPECT_NE(message.find("3 edge(s)"), std::string::npos) << message;
  EXPECT_EQ(inspectMesh(box).openEdges.size(), 3u);
}

TEST(MeshValidation, NonManifoldEdge) {
  // A fin: an extra triangle on an existing cube edge makes that edge shared by three faces.
  auto box = makeBox(1, 1, 1);
  box.vertices.emplace_back(0.5, -1.0, 0.5);
  box.triangles.push_back({0, 1, 8});
  std::string message;
  EXPECT_EQ(defectOf(box, {}, &message), MeshDefect::NonManifoldEdges);
  EXPECT_NE(message.find("(0, 1)"), std::string::npos) << message;
}

TEST(MeshValidation, DegenerateFaces) {
  auto repeated = makeBox(1, 1, 1);
  repeated.triangles[0] = {0, 0, 3};
  EXPECT_EQ(defectOf(repeated), MeshDefect::DegenerateFace);

  // A sliver: a vertex on the middle of an edge splits a face into a zero-area triangle.
  auto sliver = makeBox(1, 1, 1);
  sliver.vertices.emplace_back(0.5, 0.0, 0.0);
  sliver.triangles.push_back({0, 8, 1});
  EXPECT_EQ(defectOf(sliver), MeshDefect::DegenerateFace);
}

TEST(MeshValidation, InconsistentOrientationIsRepaired) {
  auto box = makeBox(1, 2, 3);
  std::swap(box.triangles[4][1], box.triangles[4][2]);
  std::swap(box.triangles[7][1], box.triangles[7][2]);
  EXPECT_FALSE(inspectMesh(box).consistentlyOriented);
  EXPECT_EQ(defectOf(box, {.repairOrientation = false}), MeshDefect::InconsistentOrientation);
  const auto report = validateMesh(box, "box");
  EXPECT_EQ(report.flippedFaces, 2u); // the minority is flipped
  EXPECT_FALSE(report.inverted);
  EXPECT_NEAR(signedVolume(box), 6.0, 1e-12);
}

TEST(MeshValidation, InwardOrientationIsRepaired) {
  auto box = makeBox(1, 2, 3);
  flipOrientation(box);
  EXPECT_EQ(defectOf(box, {.repairOrientation = false}), MeshDefect::InwardOrientation);
  const auto report = validateMesh(box, "box");
  EXPECT_TRUE(report.inverted);
  EXPECT_NEAR(signedVolume(box), 6.0, 1e-12);
}

TEST(MeshValidation, NonOrientableSurfaceIsRefused) {
  const auto rp2 = makeProjectivePlane();
  ASSERT_EQ(rp2.vertices.size(), 6u);
  ASSERT_EQ(rp2.triangles.size(), 10u);
  const auto inspection = inspectMesh(rp2);
  EXPECT_TRUE(inspection.watertight());
  EXPECT_FALSE(inspection.orientable);
  EXPECT_EQ(defectOf(rp2), MeshDefect::NonOrientable);
}

TEST(MeshValidation, MultipleComponents) {
  auto two = makeBox(1, 1, 1);
  auto other = makeBox(1, 1, 1);
  translate(other, Vec3(3, 0, 0));
  two.append(other);
  std::string message;
  EXPECT_EQ(defectOf(two, {}, &message), MeshDefect::MultipleComponents);
  EXPECT_NE(message.find("2 disconnected pieces"), std::string::npos) << message;
  EXPECT_EQ(defectOf(two, {.allowMultipleComponents = true}), std::nullopt);
}

TEST(MeshValidation, ZeroVolume) {
  // A closed, consistently oriented, flat double-sided sheet encloses nothing.
  TriangleMesh sheet;
  sheet.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  sheet.triangles = {{0, 1, 2}, {0, 2, 1}};
  EXPECT_EQ(defectOf(sheet), MeshDefect::NonPositiveVolume);
}
