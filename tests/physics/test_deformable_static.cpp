// SPDX-License-Identifier: GPL-3.0-or-later
// Static verification of the deformable body (issue 26), each damped to rest: a column under its
// own weight against the small-strain solution; a thick-walled cylinder under internal pressure
// (Lame) with nu = 0.49, where 4-node tets lock and 10-node tets with F-bar do not; and the
// convergence of the cylinder with the mesh size.
//
// The column: a x a x H (a = 1 m, H = 8 m), base on rollers (u_z = 0, one corner pinned in x and y,
// a second in y), sides and top free, gravity 9.81 m/s^2. Small-strain solution: sigma_zz =
// -rho g (H - z), the other stresses 0; the top sinks by rho g H^2 / (2 E) relative to the base
// (the lateral terms nu rho g r^2 / (2 E) are the same at top and base, and the rollers' mismatch
// with them, of relative size nu a^2 / H^2 < 0.4 %, stays near the base). rho g H^2 / (2 E) =
// 2.76e-5 m: strains of 7e-6, so the Neo-Hookean response is linear to 1e-5.
#include "deformable/DeformableBody.hpp"
#include "deformable/SurfaceLoads.hpp"
#include "support/DeformableFixtures.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <numbers>

namespace armour::deformable {
namespace {

constexpr double kSide = 1.0;   // a (m)
constexpr double kHeight = 8.0; // H (m)

struct ColumnResult {
  double topSink = 0.0;      ///< mean -u_z of the top nodes (m)
  double midStress = 0.0;    ///< mean sigma_zz of the elements whose centroid is within a cell of z = H/2 (Pa)
  std::uint64_t steps = 0;
};

/// Settle the column (cells n x n x 8n) under gravity with mass damping 2 omega_1 (critical for
/// the first axial mode, omega_1 = pi c_bar / (2 H)) for 14 / omega_1 (the critically damped
/// response is then within 1e-5 of rest).
ColumnResult settleColumn(ElementOrder order, bool fBar, double nu, int n) {
  DeformableSettings settings;
  settings.material = test::concrete(nu);
  settings.fBar = fBar;
  const double cBar = std::sqrt(settings.material.youngModulus / settings.material.density);
  const double omega1 = 0.5 * std::numbers::pi * cBar / kHeight;
  settings.massDamping = 2.0 * omega1;
  DeformableBody body(test::boxMesh(Vec3(kSide, kSide, kHeight), n, n, 8 * n, order), settings, "column");
  for (const auto node : test::nodesWhere(body.mesh(), [](const Vec3& p) { return p.z() < 1e-9; })) {
    const Vec3& p = body.mesh().nodes[node];
    const bool origin = p.x() < 1e-9 && p.y() < 1e-9;
    const bool xAxis = p.x() > kSide - 1e-9 && p.y() < 1e-9;
    body.fixNode(node, Vec3::Zero(), origin ? 7U : (xAxis ? 6U : 4U));
  }
  const double dt = body.stableStep().dt;
  const auto steps = static_cast<std::uint64_t>(std::ceil(14.0 / omega1 / dt));
  for (std::uint64_t s = 0; s < steps; ++s) {
    body.step(dt);
  }
  ColumnResult out;
  out.steps = steps;
  const auto top = test::nodesWhere(body.mesh(), [](const Vec3& p) { return p.z() > kHeight - 1e-9; });
  for (const auto node : top) {
    out.topSink -= (body.positions()[node].z() - body.mesh().nodes[node].z()) / static_cast<double>(top.size());
  }
  const auto stresses = body.elementStresses();
  double weight = 0.0;
  const double cell = kHeight / (8 * n);
  for (std::size_t e = 0; e < body.mesh().elementCount(); ++e) {
    Vec3 centroid = Vec3::Zero();
    for (int a = 0; a < 4; ++a) {
      centroid += 0.25 * body.mesh().nodes[body.mesh().element(e)[a]];
    }
    if (std::abs(centroid.z() - 0.5 * kHeight) < cell) {
      out.midStress += body.geometry()[e].volume * stresses[e](2, 2);
      weight += body.geometry()[e].volume;
    }
  }
  out.midStress /= weight;
  return out;
}

double analyticSink(double nu) {
  const auto m = test::concrete(nu);
  return m.density * 9.81 * kHeight * kHeight / (2.0 * m.youngModulus);
}

TEST(DeformableStatic, ColumnUnderOwnWeightMatchesTheSmallStrainSolutionWithTet10) {
  // Target 1 % (issue 26). Quadratic tets hold the exact (quadratic) displacement; what remains is
  // the lumped gravity load (HRZ shares instead of the consistent ones), the base rollers, and
  // the residual motion after damping (< 1e-5).
  const auto result = settleColumn(ElementOrder::Quadratic, true, 0.205, 1);
  const double sink = analyticSink(0.205);
  const double stress = -2340.0 * 9.81 * 0.5 * kHeight;
  std::cout << "column tet10 (n = 1, " << result.steps << " steps): top sink " << result.topSink << " m, analytic "
            << sink << " m (" << 100.0 * (result.topSink / sink - 1.0) << " %); sigma_zz(H/2) " << result.midStress
            << " Pa, analytic " << stress << " Pa (" << 100.0 * (result.midStress / stress - 1.0) << " %)\n";
  EXPECT_NEAR(result.topSink, sink, 0.01 * sink);
  EXPECT_NEAR(result.midStress, stress, 0.01 * std::abs(stress));
}

TEST(DeformableStatic, ColumnAtThreeMeshSizes) {
  // Issue 26: each verification at three mesh sizes, within 1 % at each. tet10 holds the exact
  // (quadratic) displacement; its error is the lumped gravity load (HRZ shares, not the
  // consistent ones), which shrinks with the cells: measured 0.35, 0.05, 0.008 % at n = 1, 2, 3,
  // asserted to fall by more than 2 times per refinement. tet4's nodal sink is nearly exact at
  // every size (a 1D bar's linear elements are exact at the nodes; measured -0.02 to -0.03 %, the
  // floor of the damped residual and the rollers), and its mid-height stress within 0.02 %.
  const double sink = analyticSink(0.205);
  const double stress = -2340.0 * 9.81 * 0.5 * kHeight;
  std::array<double, 3> error{};
  for (const int n : {1, 2, 3}) {
    const auto r = settleColumn(ElementOrder::Quadratic, true, 0.205, n);
    error[static_cast<std::size_t>(n - 1)] = std::abs(r.topSink / sink - 1.0);
    std::cout << "column tet10, n = " << n << " (" << r.steps << " steps): sink " << 100.0 * (r.topSink / sink - 1.0)
              << " %, sigma_zz(H/2) " << 100.0 * (r.midStress / stress - 1.0) << " %\n";
    EXPECT_NEAR(r.topSink, sink, 0.01 * sink) << "n = " << n;
    EXPECT_NEAR(r.midStress, stress, 0.01 * std::abs(stress)) << "n = " << n;
  }
  EXPECT_GT(error[0], 2.0 * error[1]);
  EXPECT_GT(error[1], 2.0 * error[2]);
  for (const int n : {1, 2, 4}) {
    const auto r = settleColumn(ElementOrder::Linear, true, 0.205, n);
    std::cout << "column tet4, n = " << n << " (" << r.steps << " steps): sink " << 100.0 * (r.topSink / sink - 1.0)
              << " %, sigma_zz(H/2) " << 100.0 * (r.midStress / stress - 1.0) << " %\n";
    EXPECT_NEAR(r.topSink, sink, 0.01 * sink) << "n = " << n;
    EXPECT_NEAR(r.midStress, stress, 0.01 * std::abs(stress)) << "n = " << n;
  }
}

/// The thick-walled cylinder (Lame): inner radius a = 1 m, outer b = 2 m, internal pressure
/// p = 1 MPa, plane strain (u_z = 0 everywhere), a quarter with symmetry planes x = 0 and y = 0.
/// Small-strain solution at the bore: u(a) = (1 + nu) p a / (E (b^2 - a^2)) ((1 - 2 nu) a^2 + b^2).
/// Mesh: a box of (b - a) x pi/2 x t cells mapped to r, theta, z (corners on the circles, straight
/// edges), nr = 2 n radial cells, 4 n round, one layer of thickness t = (b - a) / nr.
constexpr double kBore = 1.0;    // a (m)
constexpr double kOuter = 2.0;   // b (m)
constexpr double kPressure = 1e6; // p (Pa)

double lameBoreDisplacement(double nu) {
  const auto m = test::concrete(nu);
  return (1.0 + nu) * kPressure * kBore / (m.youngModulus * (kOuter * kOuter - kBore * kBore)) *
         ((1.0 - 2.0 * nu) * kBore * kBore + kOuter * kOuter);
}

struct CylinderResult {
  double bore = 0.0; ///< mean radial displacement of the corner nodes on r = a (m)
  std::uint64_t steps = 0;
};

/// Settle the pressurised quarter cylinder with mass damping 2 omega_1, omega_1 = c_s / (b - a)
/// (the lowest mode of the bore's expansion is a shear mode when nu -> 0.5), for 30 / omega_1.
CylinderResult settleCylinder(ElementOrder order, bool fBar, double nu, int n) {
  const int nr = 2 * n;
  const double thickness = (kOuter - kBore) / nr;
  auto tets = structuredBox(Vec3(kOuter - kBore, 0.5 * std::numbers::pi, thickness), nr, 4 * n, 1);
  for (auto& p : tets.vertices) {
    const double r = kBore + p.x();
    p = Vec3(r * std::cos(p.y()), r * std::sin(p.y()), p.z());
  }
  DeformableSettings settings;
  settings.material = test::concrete(nu);
  settings.fBar = fBar;
  settings.gravity = Vec3::Zero();
  const auto lame = lameConstants(settings.material);
  const double omega1 = std::sqrt(lame.mu / settings.material.density) / (kOuter - kBore);
  settings.massDamping = 2.0 * omega1;
  DeformableBody body(makeDeformableMesh(tets, order, "cylinder"), settings, "cylinder");
  const auto& nodes = body.mesh().nodes;
  for (std::size_t node = 0; node < body.nodeCount(); ++node) {
    const unsigned axes = 4U | (std::abs(nodes[node].y()) < 1e-9 ? 2U : 0U) | (std::abs(nodes[node].x()) < 1e-9 ? 1U : 0U);
    body.fixNode(node, Vec3::Zero(), axes);
  }
  const auto faces = boundaryFaces(body.mesh());
  const auto onBore = [&](const BoundaryFace& face) {
    for (const auto c : face.corners) {
      if (std::abs(nodes[c].head<2>().norm() - kBore) > 1e-9) {
        return false;
      }
    }
    return true;
  };
  const auto loads = pressureLoads(body.mesh(), faces, onBore, kPressure);
  for (std::size_t node = 0; node < body.nodeCount(); ++node) {
    body.setExternalForce(node, loads[node]);
  }
  const double dt = body.stableStep().dt;
  CylinderResult out;
  out.steps = static_cast<std::uint64_t>(std::ceil(30.0 / omega1 / dt));
  for (std::uint64_t s = 0; s < out.steps; ++s) {
    body.step(dt);
  }
  int count = 0;
  for (std::size_t node = 0; node < body.mesh().cornerCount; ++node) {
    const Vec3 r0 = Vec3(nodes[node].x(), nodes[node].y(), 0.0);
    if (std::abs(r0.norm() - kBore) < 1e-9) {
      out.bore += (body.positions()[node] - nodes[node]).dot(r0.normalized());
      ++count;
    }
  }
  out.bore /= count;
  return out;
}

TEST(DeformableStatic, NearlyIncompressibleCylinderLocksWithTet4ButNotWithTet10FBar) {
  // nu = 0.49 (issue 26): 10-node tets with F-bar within 5 % of Lame's solution (measured 0.7 %).
  // 4-node tets on the same cells lock: each constant-strain element carries its own volume
  // constraint, so as nu -> 0.5 the bore expands less and less. Measured on n = 2: 0.966 of Lame
  // at nu = 0.3, 0.837 at 0.49, 0.746 at 0.499. Asserted: below 0.9 at nu = 0.49 and an error at
  // least 3 times that at nu = 0.3 on the same mesh (measured 4.7 times): stiffer by locking, not
  // by coarseness. (10-node tets without F-bar do not lock much in this problem: 0.992 at 0.49,
  // 0.991 at 0.499 against 0.993 with F-bar.)
  const double exact = lameBoreDisplacement(0.49);
  const auto fBar = settleCylinder(ElementOrder::Quadratic, true, 0.49, 2);
  const auto plain = settleCylinder(ElementOrder::Quadratic, false, 0.49, 2);
  const auto linear = settleCylinder(ElementOrder::Linear, false, 0.49, 2);
  const double linearCompressible = settleCylinder(ElementOrder::Linear, false, 0.3, 2).bore / lameBoreDisplacement(0.3);
  std::cout << "nu 0.49 cylinder (n = 2, " << fBar.steps << " steps): bore u / Lame = tet10 F-bar "
            << fBar.bore / exact << ", tet10 plain " << plain.bore / exact << ", tet4 " << linear.bore / exact
            << " (tet4 at nu 0.3: " << linearCompressible << "; Lame u(a) = " << exact << " m)\n";
  EXPECT_NEAR(fBar.bore, exact, 0.05 * exact);
  EXPECT_LT(linear.bore, 0.9 * exact);
  EXPECT_GT(1.0 - linear.bore / exact, 3.0 * (1.0 - linearCompressible));
}

TEST(DeformableStatic, CylinderConvergesAtSecondOrder) {
  // nu = 0.3, tet10 with F-bar at n = 1, 2, 4: the error in u(a) falls as h^2 (faceted bore,
  // straight edges: the geometry error is second order); observed order 2 within 0.4.
  const double exact = lameBoreDisplacement(0.3);
  double errors[3] = {};
  for (int i = 0; i < 3; ++i) {
    errors[i] = std::abs(settleCylinder(ElementOrder::Quadratic, true, 0.3, 1 << i).bore / exact - 1.0);
  }
  const double order = std::log2(errors[1] / errors[2]);
  std::cout << "cylinder tet10 errors " << errors[0] << ", " << errors[1] << ", " << errors[2] << ": order " << order
            << "\n";
  EXPECT_GT(errors[0], errors[1]);
  EXPECT_GT(errors[1], errors[2]);
  EXPECT_NEAR(order, 2.0, 0.4);
}

} // namespace
} // namespace armour::deformable
