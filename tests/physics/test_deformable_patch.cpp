// SPDX-License-Identifier: GPL-3.0-or-later
// Patch test of the deformable elements (issue 26): a uniform deformation F (stretch, shear and
// rotation, strains of 5-20 %) imposed on a box with displaced interior nodes gives, in every
// element, the analytic Neo-Hookean Cauchy stress of seed 002 eq. 7 to round-off; interior nodes
// are in equilibrium (zero internal force) and the internal forces on a face add up to the
// traction T n da of the deformed face. For 4- and 10-node tets, with and without F-bar.
#include "deformable/DeformableBody.hpp"
#include "geometry/Tetrahedralizer.hpp"
#include "support/DeformableFixtures.hpp"
#include "support/ShapeCache.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <cmath>
#include <random>

namespace armour::deformable {
namespace {

/// A 3 x 3 x 3 cell box of 1.5 x 1.2 x 0.9 m whose 8 interior corners are moved by up to 30 % of a
/// cell (seeded), so elements are irregular; mid-edge nodes stay at their edges' midpoints.
DeformableMesh irregularBox(ElementOrder order) {
  auto tets = structuredBox(Vec3(1.5, 1.2, 0.9), 3, 3, 3);
  std::mt19937 random(26);
  std::uniform_real_distribution<double> offset(-0.3, 0.3);
  for (auto& p : tets.vertices) {
    const bool interior = p.x() > 1e-9 && p.x() < 1.5 - 1e-9 && p.y() > 1e-9 && p.y() < 1.2 - 1e-9 &&
                          p.z() > 1e-9 && p.z() < 0.9 - 1e-9;
    if (interior) {
      p += Vec3(0.5 * offset(random), 0.4 * offset(random), 0.3 * offset(random));
    }
  }
  return makeDeformableMesh(tets, order, "irregular box");
}

struct PatchCase {
  ElementOrder order;
  bool fBar;
};

class DeformablePatch : public ::testing::TestWithParam<PatchCase> {};

TEST_P(DeformablePatch, UniformDeformationGivesTheAnalyticStressEverywhere) {
  const auto [order, fBar] = GetParam();
  DeformableSettings settings;
  settings.material = test::concrete(0.3);
  settings.fBar = fBar;
  settings.gravity = Vec3::Zero();
  DeformableBody body(irregularBox(order), settings);
  // Stretch 1.2 / 0.95 / 1.05, shear 0.1, and a rotation of 0.3 rad about z.
  Mat3 U;
  U << 1.2, 0.1, 0.0, 0.1, 0.95, 0.05, 0.0, 0.05, 1.05;
  const Mat3 R = Eigen::AngleAxisd(0.3, Vec3::UnitZ()).toRotationMatrix();
  const Mat3 F = R * U;
  std::vector<Vec3> x(body.nodeCount());
  for (std::size_t n = 0; n < x.size(); ++n) {
    x[n] = F * body.mesh().nodes[n];
  }
  body.setPositions(x);
  const Mat3 analytic = cauchyStress(F, Mat3::Zero(), lameConstants(settings.material), 0.0);
  // Round-off: stresses of order 1e10 Pa from F with entries O(1) and a few dozen operations:
  // 1e-12 of the stress norm (measured below 1e-14).
  double worst = 0.0;
  for (const auto& T : body.elementStresses()) {
    worst = std::max(worst, (T - analytic).norm() / analytic.norm());
  }
  EXPECT_LT(worst, 1e-12);
  // Equilibrium of interior nodes, and face x = 1.5 carries T n da with n da = J F^-T N dA.
  const auto f = body.internalForces();
  const double forceScale = analytic.norm() * 1.5 * 1.2;
  Vec3 faceForce = Vec3::Zero();
  for (std::size_t n = 0; n < body.nodeCount(); ++n) {
    const Vec3& X = body.mesh().nodes[n];
    const bool onBoundary = X.x() < 1e-9 || X.x() > 1.5 - 1e-9 || X.y() < 1e-9 || X.y() > 1.2 - 1e-9 ||
                            X.z() < 1e-9 || X.z() > 0.9 - 1e-9;
    if (!onBoundary) {
      EXPECT_LT(f[n].norm(), 1e-12 * forceScale) << "node " << n;
    }
    if (X.x() > 1.5 - 1e-9) {
      faceForce += f[n];
    }
  }
  const Vec3 area = F.determinant() * F.inverse().transpose() * Vec3(1.2 * 0.9, 0.0, 0.0);
  EXPECT_LT((faceForce - analytic * area).norm(), 1e-12 * forceScale);
  std::cout << "patch test, " << body.mesh().nodesPerElement() << " nodes, F-bar " << fBar
            << ": worst element stress error / |T| = " << worst << "\n";
}

INSTANTIATE_TEST_SUITE_P(AllElements, DeformablePatch,
                         ::testing::Values(PatchCase{ElementOrder::Linear, false}, PatchCase{ElementOrder::Linear, true},
                                           PatchCase{ElementOrder::Quadratic, false},
                                           PatchCase{ElementOrder::Quadratic, true}),
                         [](const auto& info) {
                           return std::string(info.param.order == ElementOrder::Linear ? "Tet4" : "Tet10") +
                                  (info.param.fBar ? "FBar" : "Plain");
                         });

TEST(DeformablePatch, GmshMeshOfAVcrossPassesInQuadraticForm) {
  // The path a unit takes: library shape (seed 002's Vcross, 1 m^3) -> gmsh tets (about 2 000) ->
  // 10-node mesh. Its volume is the shape's, the lumped masses sum to rho V, and a uniform
  // deformation gives the analytic stress in every element (1e-12, round-off, as above) on this
  // unstructured mesh with its slivers.
  geometry::TetrahedralizeOptions options;
  options.targetTetCount = 2000;
  options.keepSurface = false;
  const auto tets = geometry::tetrahedralize(armour::test::unitShape("vcross"), options);
  DeformableSettings settings;
  settings.gravity = Vec3::Zero();
  DeformableBody body(makeDeformableMesh(tets, ElementOrder::Quadratic, "vcross"), settings, "vcross");
  double mass = 0.0;
  for (const double m : body.masses()) {
    mass += m;
  }
  EXPECT_NEAR(mass, settings.material.density * tets.totalVolume(), 1e-9 * mass);
  EXPECT_NEAR(tets.totalVolume(), 1.0, 1e-6);
  Mat3 F;
  F << 1.001, 0.0005, 0.0, 0.0002, 0.999, 0.0003, 0.0, 0.0001, 1.002;
  std::vector<Vec3> x(body.nodeCount());
  for (std::size_t n = 0; n < x.size(); ++n) {
    x[n] = F * body.mesh().nodes[n];
  }
  body.setPositions(x);
  const Mat3 analytic = cauchyStress(F, Mat3::Zero(), lameConstants(settings.material), 0.0);
  double worst = 0.0;
  for (const auto& T : body.elementStresses()) {
    worst = std::max(worst, (T - analytic).norm() / analytic.norm());
  }
  std::cout << "vcross: " << body.mesh().elementCount() << " tet10, " << body.nodeCount()
            << " nodes, stable step " << body.stableStep().dt << " s, worst stress error / |T| " << worst << "\n";
  // Small strains (1e-3) lose three digits: F - I is formed from x^T G, positions of about 1 m
  // against displacements of 1 mm (measured 2.3e-12).
  EXPECT_LT(worst, 1e-9);
}

} // namespace
} // namespace armour::deformable
