// SPDX-License-Identifier: GPL-3.0-or-later
// Deformable-body building blocks (issue 26): shape functions and quadrature, the quadratic mesh,
// the lumped masses, the stable step against each element's own highest frequency, and the
// refusal of bad material values and too large steps.
#include "core/Error.hpp"
#include "deformable/DeformableBody.hpp"
#include "deformable/StableStep.hpp"
#include "deformable/StressFields.hpp"
#include "deformable/StressHistory.hpp"
#include "deformable/SurfaceLoads.hpp"
#include "deformable/TetElement.hpp"
#include "support/DeformableFixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace armour::deformable {
namespace {

using test::boxMesh;
using test::concrete;

std::string inputErrorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(DeformableElement, ShapeFunctionsAreAPartitionOfUnityAndInterpolateNodes) {
  // Nodes of the reference tet10 in VTK order; N_a(node b) = delta_ab exactly (polynomials of
  // exact binary fractions), sum N = 1 and sum dN = 0 to round-off (1e-15) anywhere.
  const std::array<Vec3, 10> nodes{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0.5, 0, 0),
                                   Vec3(0.5, 0.5, 0), Vec3(0, 0.5, 0), Vec3(0, 0, 0.5), Vec3(0.5, 0, 0.5),
                                   Vec3(0, 0.5, 0.5)};
  for (int b = 0; b < 10; ++b) {
    const NodeVector N = shapeValues(ElementOrder::Quadratic, nodes[b]);
    for (int a = 0; a < 10; ++a) {
      EXPECT_EQ(N[a], a == b ? 1.0 : 0.0) << a << " at node " << b;
    }
  }
  for (const auto order : {ElementOrder::Linear, ElementOrder::Quadratic}) {
    const Vec3 xi(0.1, 0.27, 0.33);
    EXPECT_NEAR(shapeValues(order, xi).sum(), 1.0, 1e-15);
    EXPECT_LT(shapeDerivatives(order, xi).colwise().sum().norm(), 1e-14);
  }
}

TEST(DeformableElement, QuadratureIntegratesQuadraticsExactly) {
  // Reference-tet integrals of monomials: 1 -> 1/6, xi -> 1/24, xi^2 -> 1/60, xi*eta -> 1/120.
  // The 4-point rule is exact to degree 2 (round-off, 1e-16); the 1-point rule to degree 1.
  for (const auto order : {ElementOrder::Linear, ElementOrder::Quadratic}) {
    const auto rule = quadratureRule(order);
    double one = 0.0;
    double x = 0.0;
    double xx = 0.0;
    double xy = 0.0;
    for (int q = 0; q < rule.points; ++q) {
      one += rule.weight[q];
      x += rule.weight[q] * rule.xi[q].x();
      xx += rule.weight[q] * rule.xi[q].x() * rule.xi[q].x();
      xy += rule.weight[q] * rule.xi[q].x() * rule.xi[q].y();
    }
    EXPECT_NEAR(one, 1.0 / 6.0, 1e-16);
    EXPECT_NEAR(x, 1.0 / 24.0, 1e-16);
    if (order == ElementOrder::Quadratic) {
      EXPECT_NEAR(xx, 1.0 / 60.0, 1e-16);
      EXPECT_NEAR(xy, 1.0 / 120.0, 1e-16);
    }
  }
}

TEST(DeformableElement, QuadraticBoxSharesMidEdgeNodesAndLumpsTheWholeMass) {
  // A 2 x 2 x 2 cell box: the 27 corners and one node per edge fill the 5 x 5 x 5 grid of half
  // spacing exactly, so 125 nodes, each mid-edge node at its edge's midpoint.
  const auto mesh = boxMesh(Vec3(2.0, 1.0, 3.0), 2, 2, 2, ElementOrder::Quadratic);
  EXPECT_EQ(mesh.cornerCount, 27U);
  EXPECT_EQ(mesh.nodeCount(), 125U);
  EXPECT_EQ(mesh.elementCount(), 48U);
  for (std::size_t e = 0; e < mesh.elementCount(); ++e) {
    for (int k = 0; k < 6; ++k) {
      const auto* n = mesh.element(e);
      const Vec3 mid = 0.5 * (mesh.nodes[n[kTet10Edges[k][0]]] + mesh.nodes[n[kTet10Edges[k][1]]]);
      EXPECT_LT((mesh.nodes[n[4 + k]] - mid).norm(), 1e-15);
    }
  }
  // Same input, same numbering.
  EXPECT_EQ(boxMesh(Vec3(2.0, 1.0, 3.0), 2, 2, 2, ElementOrder::Quadratic).connectivity, mesh.connectivity);
  // Lumped masses: all positive (HRZ), summing to rho V within round-off (1e-12 relative).
  const DeformableBody body(mesh, DeformableSettings{});
  double total = 0.0;
  for (const double m : body.masses()) {
    EXPECT_GT(m, 0.0);
    total += m;
  }
  EXPECT_NEAR(total, 2340.0 * 6.0, 1e-12 * 2340.0 * 6.0);
}

TEST(DeformableElement, StableStepIsBelowEachElementsOwnLimit) {
  // l / c_d (StableStep.hpp, safety 1) against 2 / omega_max of single elements with lumped mass,
  // linearised at rest: the element bound is above the mesh's limit, so the estimate is stable
  // when l / c_d <= 2 / omega_max. Measured ratios 1.00-1.86; the 1e-3 allows for the finite
  // differences of the stiffness.
  const std::vector<std::array<Vec3, 4>> shapes{
      {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)},              // regular
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1, 1, 1)},                    // cube split
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0.866, 0), Vec3(0.5, 0.3, 0.1)},        // flat
      {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.05, 0.0866, 0), Vec3(0.05, 0.03, 1.0)},  // needle
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0.05), Vec3(0, 1, 0)}};                // sliver
  for (const double nu : {0.0, 0.205, 0.49}) {
    const auto material = concrete(nu);
    for (const auto order : {ElementOrder::Linear, ElementOrder::Quadratic}) {
      for (const bool fBar : {false, true}) {
        const ElementModel model{lameConstants(material), 0.0, fBar};
        for (const auto& corners : shapes) {
          geometry::TetMesh tets;
          tets.vertices.assign(corners.begin(), corners.end());
          tets.tets = {{0, 1, 2, 3}};
          if (tets.volume(0) < 0.0) {
            std::swap(tets.tets[0][1], tets.tets[0][2]);
          }
          const auto mesh = makeDeformableMesh(tets, order);
          NodeMatrix X(mesh.nodesPerElement(), 3);
          for (int a = 0; a < mesh.nodesPerElement(); ++a) {
            X.row(a) = mesh.nodes[mesh.element(0)[a]].transpose();
          }
          const double omega = test::elementMaxFrequency(order, X, model, material.density);
          const auto estimate = stableStep(mesh, material, 1.0);
          EXPECT_LE(estimate.dt, (2.0 / omega) * (1.0 + 1e-3))
              << "nu " << nu << " nodes " << mesh.nodesPerElement() << " F-bar " << fBar;
        }
      }
    }
  }
}

TEST(DeformableElement, BadMaterialValuesAreRefusedWithTheLimitNamed) {
  const auto refuse = [](MaterialSettings m) { return inputErrorOf([&] { validateMaterial(m, "unit.yaml: material"); }); };
  auto m = concrete();
  m.poissonRatio = 0.5;
  EXPECT_NE(refuse(m).find("unit.yaml: material.poisson_ratio: 0.5: Poisson's ratio must be below 0.5"),
            std::string::npos)
      << refuse(m);
  m.poissonRatio = -1.0;
  EXPECT_NE(refuse(m).find("must be above -1"), std::string::npos) << refuse(m);
  m = concrete();
  m.youngModulus = 0.0;
  EXPECT_NE(refuse(m).find("material.young_modulus: 0 Pa: Young's modulus must be positive"), std::string::npos)
      << refuse(m);
  m = concrete();
  m.density = -2340.0;
  EXPECT_NE(refuse(m).find("material.density: -2340 kg/m^3"), std::string::npos) << refuse(m);
  m = concrete();
  m.viscosity = -1.0;
  EXPECT_NE(refuse(m).find("material.viscosity"), std::string::npos) << refuse(m);
  m = concrete();
  m.youngModulus = std::nan("");
  EXPECT_NE(refuse(m).find("must be a finite number"), std::string::npos) << refuse(m);
  // The body refuses them too, naming its source.
  DeformableSettings settings;
  settings.material.poissonRatio = 0.7;
  const auto mesh = boxMesh(Vec3(1, 1, 1), 1, 1, 1, ElementOrder::Linear);
  EXPECT_NE(inputErrorOf([&] { DeformableBody(mesh, settings, "dolos.vtu"); }).find("dolos.vtu: material.poisson_ratio"),
            std::string::npos);
}

TEST(DeformableElement, TooLargeAStepIsRefusedWithTheLimitNamed) {
  DeformableBody body(boxMesh(Vec3(1, 1, 1), 2, 2, 2, ElementOrder::Quadratic), DeformableSettings{}, "cube");
  const auto& limit = body.stableStep();
  // The limit is the default safety 0.9 times l_min / c_d (elastic: no viscous reduction).
  EXPECT_NEAR(limit.dt, 0.9 * limit.lengthMin / dilatationalWaveSpeed(concrete()), 1e-18);
  const std::string message = inputErrorOf([&] { body.step(1.01 * limit.dt); });
  EXPECT_NE(message.find("cube: time step"), std::string::npos) << message;
  EXPECT_NE(message.find("is above the stable limit"), std::string::npos) << message;
  EXPECT_NE(message.find(fmt::format("use a step of at most {} s", limit.dt)), std::string::npos) << message;
  EXPECT_NE(inputErrorOf([&] { body.step(-1e-6); }).find("must be positive"), std::string::npos);
  EXPECT_NO_THROW(body.step(limit.dt));
  // Mass damping is explicit: alpha dt above 1 is refused with the largest allowed step named.
  DeformableSettings damped;
  damped.massDamping = 2.0 / limit.dt;
  DeformableBody heavy(boxMesh(Vec3(1, 1, 1), 2, 2, 2, ElementOrder::Quadratic), damped, "cube");
  const std::string dampingMessage = inputErrorOf([&] { heavy.step(limit.dt); });
  EXPECT_NE(dampingMessage.find("cube: mass_damping"), std::string::npos) << dampingMessage;
  EXPECT_NE(dampingMessage.find(fmt::format("use a step of at most {} s", 0.5 * limit.dt)), std::string::npos)
      << dampingMessage;
}

} // namespace
} // namespace armour::deformable

namespace armour::deformable {
namespace {

TEST(DeformableStress, PrincipalDifferentialAndVonMisesOfAKnownTensor) {
  // diag(3, -1, 2) MPa turned by 0.7 rad about (1, 2, 3): principal 3, 2, -1 MPa (tension
  // positive, largest first), differential 4 MPa, von Mises sqrt((1 + 9 + 16) / 2) = sqrt(13)
  // MPa; round-off of the eigen-solver, 1e-9 of 1 MPa.
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Mat3 stress = R * Vec3(3e6, -1e6, 2e6).asDiagonal() * R.transpose();
  const auto summary = summarizeStress(stress);
  EXPECT_NEAR(summary.principal[0], 3e6, 1e-3);
  EXPECT_NEAR(summary.principal[1], 2e6, 1e-3);
  EXPECT_NEAR(summary.principal[2], -1e6, 1e-3);
  EXPECT_NEAR(summary.differential, 4e6, 1e-3);
  EXPECT_NEAR(summary.vonMises, std::sqrt(13.0) * 1e6, 1e-3);
}

} // namespace
} // namespace armour::deformable

namespace armour::deformable {
namespace {

TEST(DeformableSurface, BoundaryFacesAndTractionLoadsOfABox) {
  // A 1 x 2 x 3 m box of 2 x 2 x 3 cells: its boundary is 2 (1*2 + 1*3 + 2*3) = 22 m^2 in 2 x 2
  // triangles per cell face (2 (4 + 6 + 6) x 2 = 64 faces), with outward normals. A traction on
  // the top face (z = 3) adds up to traction x 2 m^2, exactly (1e-12); on 10-node faces the
  // corners take nothing and the mid-edge nodes A/3 each; pressure on the whole closed surface
  // adds up to zero.
  for (const auto order : {ElementOrder::Linear, ElementOrder::Quadratic}) {
    const auto mesh = boxMesh(Vec3(1.0, 2.0, 3.0), 2, 2, 3, order);
    const auto faces = boundaryFaces(mesh);
    ASSERT_EQ(faces.size(), 64U);
    double area = 0.0;
    for (const auto& face : faces) {
      area += face.area;
      const Vec3 outward = face.centroid - Vec3(0.5, 1.0, 1.5);
      EXPECT_GT(face.normal.dot(outward), 0.0);
    }
    EXPECT_NEAR(area, 22.0, 1e-12);
    const Vec3 traction(1e5, -2e5, 3e5);
    const auto onTop = [](const BoundaryFace& face) { return face.normal.z() > 0.5; };
    const auto loads = tractionLoads(mesh, faces, onTop, traction);
    Vec3 total = Vec3::Zero();
    for (std::size_t n = 0; n < loads.size(); ++n) {
      total += loads[n];
      if (order == ElementOrder::Quadratic && n < mesh.cornerCount) {
        EXPECT_EQ(loads[n].norm(), 0.0);
      }
    }
    EXPECT_LT((total - 2.0 * traction).norm(), 1e-12 * traction.norm());
    const auto pressure = pressureLoads(mesh, faces, [](const BoundaryFace&) { return true; }, 1e6);
    Vec3 net = Vec3::Zero();
    for (const auto& f : pressure) {
      net += f;
    }
    EXPECT_LT(net.norm(), 1e-9 * 1e6);
  }
}

} // namespace
} // namespace armour::deformable

namespace armour::deformable {
namespace {

TEST(DeformableStress, HistoryFindsTheLargestTensionWhereAndWhenItOccurs) {
  // A 1 x 1 x 4 m bar stretched along z with a strain growing linearly up the bar,
  // eps_zz = s z / H (u_z = s z^2 / (2 H)): the largest tension must be found in the top layer of
  // cells (centroid z > 3.5 m). Recorded at s = 1e-3, 2e-3, 1e-3 (positions set, no steps): twice
  // the strain gives about twice the stress, and the record's extreme is the second sample's.
  DeformableSettings settings;
  settings.gravity = Vec3::Zero();
  DeformableBody body(boxMesh(Vec3(1.0, 1.0, 4.0), 2, 2, 8, ElementOrder::Quadratic), settings, "bar");
  StressHistory history;
  const auto stretch = [&](double s) {
    std::vector<Vec3> x(body.nodeCount());
    for (std::size_t n = 0; n < x.size(); ++n) {
      const Vec3& X = body.mesh().nodes[n];
      x[n] = X + Vec3(0.0, 0.0, s * X.z() * X.z() / (2.0 * 4.0));
    }
    body.setPositions(x);
  };
  for (const double s : {1e-3, 2e-3, 1e-3}) {
    stretch(s);
    history.record(body);
  }
  ASSERT_EQ(history.samples().size(), 3U);
  const auto& first = history.samples()[0];
  EXPECT_GT(first.tension.location.z(), 3.5);
  EXPECT_GT(first.tension.value, 0.0);
  // Twice the strain, about twice the stress (1 % for the Neo-Hookean's nonlinearity at 2e-3).
  EXPECT_NEAR(history.samples()[1].tension.value / first.tension.value, 2.0, 0.02);
  EXPECT_EQ(history.extremes().tension.value, history.samples()[1].tension.value);
  EXPECT_GE(history.extremes().differential.value, history.samples()[2].differential.value);
  const auto file = std::filesystem::temp_directory_path() / ("armour_stress_history_" + std::to_string(::getpid()) + ".csv");
  history.writeCsv(file);
  std::ifstream in(file);
  std::string line;
  int lines = 0;
  while (std::getline(in, line)) {
    ++lines;
  }
  EXPECT_EQ(lines, 4);
  // Read back (a restart continues the history): the same samples to the last bit, and the extremes.
  const StressHistory back = StressHistory::readCsv(file);
  ASSERT_EQ(back.samples().size(), 3U);
  for (std::size_t k = 0; k < 3; ++k) {
    for (const auto& [a, b] : {std::pair{&history.samples()[k].tension, &back.samples()[k].tension},
                               std::pair{&history.samples()[k].differential, &back.samples()[k].differential},
                               std::pair{&history.samples()[k].vonMises, &back.samples()[k].vonMises}}) {
      EXPECT_EQ(a->value, b->value);
      EXPECT_EQ(a->time, b->time);
      EXPECT_EQ(a->element, b->element);
      EXPECT_EQ(a->location, b->location);
    }
  }
  EXPECT_EQ(back.extremes().tension.value, history.extremes().tension.value);
  // keepUpTo drops the later samples and their extremes: all three share t = 0 here, so keeping up
  // to a time before it leaves none.
  StressHistory cut = back;
  cut.keepUpTo(-1.0);
  EXPECT_TRUE(cut.samples().empty());
  EXPECT_EQ(cut.extremes().tension.value, 0.0);
  std::filesystem::remove(file);
}

TEST(DeformableStress, ADamagedHistoryIsRefusedNamingTheFileAndLine) {
  const auto file = std::filesystem::temp_directory_path() / ("armour_bad_history_" + std::to_string(::getpid()) + ".csv");
  const std::string header = "time_s,tension_Pa,tension_element,tension_x_m,tension_y_m,tension_z_m,differential_Pa,"
                             "differential_element,differential_x_m,differential_y_m,differential_z_m,von_mises_Pa,"
                             "von_mises_element,von_mises_x_m,von_mises_y_m,von_mises_z_m\n";
  const std::string good = "0.001,1e6,3,0,0,1,2e6,4,0,0,1,2e6,4,0,0,1\n";
  for (const auto& [text, expected] :
       {std::pair<std::string, std::string>{"time,x\n", "not a stress history"},
        {header + good + "0.002,1e6,3,0,0\n", "line 3 has 5 fields, a sample has 16"},
        {header + "0.001,abc,3,0,0,1,2e6,4,0,0,1,2e6,4,0,0,1\n", "line 2: 'abc' is not a finite number"},
        {header + "0.001,nan,3,0,0,1,2e6,4,0,0,1,2e6,4,0,0,1\n", "line 2: 'nan' is not a finite number"}}) {
    std::ofstream(file) << text;
    try {
      (void)StressHistory::readCsv(file);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const core::InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(expected), std::string::npos) << message;
      EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    }
  }
  std::filesystem::remove(file);
}

} // namespace
} // namespace armour::deformable
