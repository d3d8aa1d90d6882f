// SPDX-License-Identifier: GPL-3.0-or-later
// FDEM potential contact (FdemMesh, FdemPotential) against hand-computed integrals: apart bodies
// feel nothing, a flat overlap of depth d is pressed by E_p d / L, actions are equal and opposite,
// and force and torque are the exact negative gradient of the overlap energy (finite differences
// of the independently computed volume integral).

#include "contact/FdemMesh.hpp"
#include "contact/FdemPotential.hpp"
#include "geometry/ShapeLibrary.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

using namespace armour;
using namespace armour::contact;

namespace {

/// A cube [-side/2, side/2]^3 cut into n^3 cells of six tetrahedra each (Kuhn's subdivision along
/// the main diagonal): a structured mesh, so that the expected integrals are known exactly.
geometry::TetMesh structuredCube(int n, double side) {
  geometry::TetMesh m;
  const auto index = [&](int i, int j, int k) { return static_cast<std::int32_t>((k * (n + 1) + j) * (n + 1) + i); };
  for (int k = 0; k <= n; ++k) {
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        m.vertices.emplace_back(side * (static_cast<double>(i) / n - 0.5), side * (static_cast<double>(j) / n - 0.5),
                                side * (static_cast<double>(k) / n - 0.5));
      }
    }
  }
  const std::array<std::array<int, 3>, 6> perms{{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        for (const auto& p : perms) {
          std::array<int, 3> c{i, j, k};
          geometry::Tet t{};
          t[0] = index(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            c[p[s]] += 1;
            t[s + 1] = index(c[0], c[1], c[2]);
          }
          const Vec3 a = m.vertices[t[0]];
          if ((m.vertices[t[1]] - a).dot((m.vertices[t[2]] - a).cross(m.vertices[t[3]] - a)) < 0.0) {
            std::swap(t[2], t[3]);
          }
          m.tets.push_back(t);
        }
      }
    }
  }
  return m;
}

FdemPose pose(const Vec3& x, const Mat3& R = Mat3::Identity(), double scale = 1.0) {
  FdemPose p;
  p.position = x;
  p.rotation = R;
  p.scale = scale;
  return p;
}

struct Totals {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
};

Totals sum(const std::vector<FdemContact>& records) {
  Totals t;
  for (const auto& r : records) {
    t.force += r.force;
    t.torque += r.torque;
  }
  return t;
}

Mat3 rotation(double angle, const Vec3& axis) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

constexpr double kEp = 1.0e9; // penalty modulus (Pa)
constexpr double kL = 1.0;    // length scale (m)

} // namespace

TEST(FdemMesh, StructuredCubeKeepsItsSurfaceLayerAndUnitSurfaceGradient) {
  const FdemMesh mesh(structuredCube(4, 1.0), "cube");
  EXPECT_EQ(mesh.totalTetCount(), 6u * 64u);
  EXPECT_NEAR(mesh.volume(), 1.0, 1e-12);
  double area = 0.0;
  for (const auto& f : mesh.faces()) area += f.area;
  EXPECT_NEAR(area, 6.0, 1e-12) << "the contactor faces are the whole surface";
  // Kept: the elements with a boundary face. Each of the 6 x 16 boundary squares is split into two
  // triangles, each the face of its own tetrahedron (Kuhn tets have at most one face on a cube face,
  // and corner tets can have two or three).
  std::size_t withFaces = 0;
  for (const auto& e : mesh.elements()) withFaces += e.faceCount > 0 ? 1 : 0;
  EXPECT_EQ(withFaces, mesh.elements().size());
  EXPECT_EQ(mesh.faces().size(), 6u * 16u * 2u);
  EXPECT_LE(mesh.elements().size(), mesh.faces().size());
  // Under the middle of a face's element psi is the depth below the surface, to round-off: P_e
  // makes its gradient 1 there. 1e-5 m below the top face, away from element edges.
  EXPECT_NEAR(mesh.potential(Vec3(0.13, 0.07, 0.5 - 1e-5)), 1e-5, 1e-15);
  EXPECT_EQ(mesh.potential(Vec3(0.0, 0.0, 0.0)), 0.0) << "deep elements carry no potential";
  EXPECT_GT(mesh.reach(), 0.0);
}

TEST(FdemMesh, GmshCubeIsClosedWithTheRequestedCount) {
  geometry::ShapeRequest r;
  r.volume = 1.0;
  FdemMeshSettings s;
  s.elementsPerUnit = 600;
  const FdemMesh mesh(geometry::makeShape("cube", r), s, "cube");
  double area = 0.0;
  for (const auto& f : mesh.faces()) area += f.area;
  EXPECT_NEAR(area, 6.0, 1e-9);
  EXPECT_NEAR(mesh.volume(), 1.0, 1e-6);
  // The tetrahedraliser corrects its lattice once from the count obtained: within a factor 1.5.
  EXPECT_GT(mesh.totalTetCount(), 400u);
  EXPECT_LT(mesh.totalTetCount(), 900u);
}

TEST(FdemPotential, BodiesApartFeelNothing) {
  const FdemMesh mesh(structuredCube(3, 1.0), "cube");
  std::vector<FdemContact> out;
  fdemBodyPair(mesh, pose(Vec3::Zero()), mesh, pose(Vec3(0.0, 0.0, 1.0 + 1e-9)), kEp / (2 * kL), out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(fdemBodyPairEnergy(mesh, pose(Vec3::Zero()), mesh, pose(Vec3(0.3, 0.2, 1.001)), kEp / (2 * kL)), 0.0);
}

TEST(FdemPotential, FlatOverlapIsPressedByPenaltyTimesDepthOverL) {
  // Two unit cubes face to face, overlapping by d. Each body's potential rises at G = E_p / (2L)
  // per metre below its surface, so each face integral is G d A and the two together E_p d A / L,
  // the level-set law. Short of it by the strips along the surface elements' edges where a
  // neighbouring face's coordinate is the smallest (width ~d), and by the elements touching the
  // surface at an edge only (dropped: psi ~ 0 there): both a relative loss ~ d / h (h = 1/4
  // here), measured 1.9e-3 at d = 1e-4; 3e-3 allowed. The loss must shrink in proportion to d.
  const FdemMesh mesh(structuredCube(4, 1.0), "cube");
  const auto pressed = [&](double d) {
    std::vector<FdemContact> out;
    fdemBodyPair(mesh, pose(Vec3::Zero()), mesh, pose(Vec3(0.0, 0.0, 1.0 - d)), kEp / (2 * kL), out);
    return sum(out);
  };
  const double d = 1e-4;
  const Totals t = pressed(d);
  const double expected = kEp * d * 1.0 / kL;
  EXPECT_NEAR(t.force.z(), -expected, 3e-3 * expected) << "A (below) is pushed down";
  EXPECT_NEAR(t.force.head<2>().norm(), 0.0, 1e-9 * expected);
  const double loss1 = 1.0 + t.force.z() / expected;
  RecordProperty("relative_loss_at_1e-4", std::to_string(loss1));
  const double loss2 = 1.0 + pressed(d / 4).force.z() / (expected / 4);
  EXPECT_GT(loss1, 0.0);
  EXPECT_NEAR(loss2, loss1 / 4, 0.05 * loss1) << "the edge-strip loss is linear in d / h";
}

TEST(FdemPotential, ActionAndReactionAreEqualAndOpposite) {
  const FdemMesh a(structuredCube(3, 1.0), "a");
  const FdemMesh b(structuredCube(4, 0.8), "b");
  const FdemPose pa = pose(Vec3(0.1, -0.2, 0.3), rotation(0.3, Vec3(1, 2, 3)));
  const FdemPose pb = pose(Vec3(0.5, 0.3, 1.15), rotation(-0.5, Vec3(-1, 1, 2)), 1.1);
  std::vector<FdemContact> ab, ba;
  fdemBodyPair(a, pa, b, pb, kEp / 2, ab);
  fdemBodyPair(b, pb, a, pa, kEp / 2, ba);
  ASSERT_FALSE(ab.empty()) << "the test must overlap";
  const Totals onA = sum(ab), onB = sum(ba);
  const double scale = onA.force.norm();
  EXPECT_GT(scale, 0.0);
  EXPECT_LT((onA.force + onB.force).norm(), 1e-10 * scale);
  // Torques about each body's own origin: those on B, moved to A's origin, cancel A's.
  const Vec3 onBaboutA = onB.torque + (pb.position - pa.position).cross(onB.force);
  EXPECT_LT((onA.torque + onBaboutA).norm(), 1e-10 * scale);
}

TEST(FdemPotential, ForceAndTorqueAreMinusTheEnergyGradient) {
  // The force is computed on the surfaces, the energy as a volume integral over clipped
  // sub-tetrahedra: two independent computations. Central differences with h = 1e-7 m (overlap
  // ~0.05 m) have truncation error ~(h / overlap)^2 and round-off ~1e-16 E / h: both far below
  // the 1e-6 relative tolerance (the issue's).
  const FdemMesh a(structuredCube(3, 1.0), "a");
  const FdemMesh b(structuredCube(3, 1.0), "b");
  const double G = kEp / (2 * kL);
  const FdemPose pa = pose(Vec3(0.01, 0.02, -0.03), rotation(0.2, Vec3(1, -1, 0.5)));
  const FdemPose pb = pose(Vec3(0.15, -0.1, 0.97), rotation(0.25, Vec3(0.3, 1, -0.2)), 0.9);
  std::vector<FdemContact> out;
  fdemBodyPair(a, pa, b, pb, G, out);
  const Totals t = sum(out);
  ASSERT_GT(t.force.norm(), 0.0);
  const double h = 1e-7;
  for (int i = 0; i < 3; ++i) {
    FdemPose plus = pa, minus = pa;
    plus.position[i] += h;
    minus.position[i] -= h;
    const double dE = (fdemBodyPairEnergy(a, plus, b, pb, G) - fdemBodyPairEnergy(a, minus, b, pb, G)) / (2 * h);
    EXPECT_NEAR(t.force[i], -dE, 1e-6 * t.force.norm()) << "force component " << i;
  }
  double torqueScale = t.torque.norm();
  for (int i = 0; i < 3; ++i) {
    // Rotate A about its own origin: dE/dtheta = -torque . axis.
    FdemPose plus = pa, minus = pa;
    plus.rotation = rotation(h, Vec3::Unit(i)) * pa.rotation;
    minus.rotation = rotation(-h, Vec3::Unit(i)) * pa.rotation;
    const double dE = (fdemBodyPairEnergy(a, plus, b, pb, G) - fdemBodyPairEnergy(a, minus, b, pb, G)) / (2 * h);
    EXPECT_NEAR(t.torque[i], -dE, 1e-6 * torqueScale + 1e-6 * t.force.norm()) << "torque component " << i;
  }
}

TEST(FdemPotential, CubeOnAPlaneIsPressedExactly) {
  // A half-space's potential is its exact depth: a flat face at depth d takes E_p d A / L with no
  // edge loss (round-off only).
  const FdemMesh mesh(structuredCube(3, 1.0), "cube");
  const Vec3 n = Vec3::UnitZ();
  const double offset = 0.0;
  Box3 region;
  region.extend(Vec3::Constant(-10.0));
  region.extend(Vec3::Constant(10.0));
  const double d = 2e-4;
  std::vector<FdemContact> out;
  fdemHalfSpaces(mesh, pose(Vec3(0, 0, 0.5 - d)), std::span<const Vec3>(&n, 1), std::span<const double>(&offset, 1),
                 region, kEp / kL, out);
  const Totals t = sum(out);
  EXPECT_NEAR(t.force.z(), kEp * d / kL, 1e-9 * kEp * d);
  EXPECT_NEAR(t.force.head<2>().norm(), 0.0, 1e-9 * kEp * d);
  EXPECT_NEAR(t.torque.norm(), 0.0, 1e-9 * kEp * d) << "the pressure is uniform, centred under the body";
}

TEST(FdemPotential, ConvexStaticPieceForceIsMinusTheEnergyGradient) {
  // A tilted cube pressing its corner into a wedge (two faces): the cells nearest each face split
  // the overlap; the force must still be the exact gradient of the depth integral.
  const FdemMesh mesh(structuredCube(3, 1.0), "cube");
  const std::array<Vec3, 3> normals{Vec3(0.6, 0.0, 0.8), Vec3(-0.6, 0.0, 0.8), Vec3(0.0, 0.0, -1.0)};
  const std::array<double, 3> offsets{0.0, 0.0, 3.0};
  Box3 region;
  region.extend(Vec3(-10, -10, -3));
  region.extend(Vec3(10, 10, 1));
  const double G = kEp / kL;
  const FdemPose p = pose(Vec3(0.02, 0.01, 0.62), rotation(0.7, Vec3(1, 0.4, 0.2)));
  std::vector<FdemContact> out;
  fdemHalfSpaces(mesh, p, normals, offsets, region, G, out);
  const Totals t = sum(out);
  ASSERT_GT(t.force.norm(), 0.0);
  const double h = 1e-7;
  for (int i = 0; i < 3; ++i) {
    FdemPose plus = p, minus = p;
    plus.position[i] += h;
    minus.position[i] -= h;
    const double dE =
        (fdemHalfSpacesEnergy(mesh, plus, normals, offsets, G) - fdemHalfSpacesEnergy(mesh, minus, normals, offsets, G)) /
        (2 * h);
    EXPECT_NEAR(t.force[i], -dE, 1e-6 * t.force.norm()) << "force component " << i;
    plus = minus = p;
    plus.rotation = rotation(h, Vec3::Unit(i)) * p.rotation;
    minus.rotation = rotation(-h, Vec3::Unit(i)) * p.rotation;
    const double dR =
        (fdemHalfSpacesEnergy(mesh, plus, normals, offsets, G) - fdemHalfSpacesEnergy(mesh, minus, normals, offsets, G)) /
        (2 * h);
    EXPECT_NEAR(t.torque[i], -dR, 1e-6 * (t.torque.norm() + t.force.norm())) << "torque component " << i;
  }
}

