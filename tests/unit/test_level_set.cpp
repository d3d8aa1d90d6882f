// SPDX-License-Identifier: GPL-3.0-or-later
// Signed-distance level sets: exact distance and sign against closed forms and an independent
// inside test, interpolation error against its derived bounds, scaling, the outside extension,
// culling, thread safety, and the resolution / memory / build-time figures of the defaults.
#include "contact/LevelSet.hpp"
#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "geometry/SurfaceRefinement.hpp"
#include "support/TestMeshes.hpp"

#include "support/ShapeCache.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace armour::contact {
namespace {

using geometry::Mat3;
using geometry::ShapeRequest;

/// makeShape(name) at V = 1 m^3 (Dn = 1 m), built once per test program.
const TriangleMesh& shape(const std::string& name) { return test::unitShape(name); }

/// Default-resolution level set of shape(name), built once.
const LevelSet& shapeLevelSet(const std::string& name) { return test::perUnitShape<LevelSet>(name); }

/// Signed distance of the box [-a, a]^3 (exact closed form): outside, the length of the positive
/// part of q = |x| - a; inside, the largest (least negative) component of q.
double boxSdf(const Vec3& x, double a) {
  const Vec3 q = x.cwiseAbs() - Vec3::Constant(a);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// Generalised winding number of a closed mesh at x: the sum of the solid angles of its triangles
/// seen from x over 4 pi (Van Oosterom and Strackee 1983 for the solid angle of a triangle):
/// 1 inside, 0 outside. Independent of MeshDistance (no closest points, no normals).
double windingNumber(const TriangleMesh& mesh, const Vec3& x) {
  double total = 0.0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const auto c = mesh.corners(t);
    const Vec3 a = c[0] - x;
    const Vec3 b = c[1] - x;
    const Vec3 d = c[2] - x;
    const double la = a.norm();
    const double lb = b.norm();
    const double ld = d.norm();
    const double numerator = a.dot(b.cross(d));
    const double denominator = la * lb * ld + a.dot(b) * ld + a.dot(d) * lb + b.dot(d) * la;
    total += 2.0 * std::atan2(numerator, denominator);
  }
  return total / (4.0 * std::numbers::pi);
}

bool insideByWinding(const TriangleMesh& mesh, const Vec3& x) { return windingNumber(mesh, x) > 0.5; }

/// Fractional cell coordinates of x in the level set's grid (as the interpolation computes them).
Vec3 cellFractions(const LevelSet& ls, const Vec3& x, std::array<int, 3>* cell = nullptr) {
  Vec3 f;
  for (int k = 0; k < 3; ++k) {
    const double u = (x[k] - ls.origin()[k]) / ls.cellSize();
    const int i = std::clamp(static_cast<int>(std::floor(u)), 0, ls.nodeCounts()[k] - 2);
    f[k] = u - i;
    if (cell != nullptr) {
      (*cell)[k] = i;
    }
  }
  return f;
}

/// Pointwise bound on the trilinear interpolation error of a 1-Lipschitz function f (the exact
/// signed distance): e(x) = sum_i w_i (f(x_i) - f(x)), so |e| <= sum_i w_i |x_i - x|
/// <= sqrt(sum_i w_i |x_i - x|^2) (Jensen), and with the trilinear weights the last sum is the
/// variance of a product of independent Bernoulli(f_k) variables scaled by h:
/// h^2 sum_k f_k (1 - f_k). So |e| <= h sqrt(sum_k f_k (1 - f_k)) <= sqrt(3) h / 2 (cell centre).
double lipschitzBound(const LevelSet& ls, const Vec3& x) {
  const Vec3 f = cellFractions(ls, x);
  return ls.cellSize() * std::sqrt((f.array() * (1.0 - f.array())).sum());
}

/// Rounding of the float node values: each is within 2^-24 |v| of the double distance, and the
/// nodes of the cell holding x have |v| <= |phi(x)| + sqrt(3) h; a factor 2 covers the double
/// arithmetic of the interpolation (unit: m).
double floatTolerance(double phiAbs, double h) { return 2.0 * std::ldexp(1.0, -24) * (phiAbs + 2.0 * h) + 1e-14; }

/// Node x of cell corner (a & 1, a & 2, a & 4).
Vec3 cellNode(const LevelSet& ls, const std::array<int, 3>& cell, int a) {
  return ls.origin() + ls.cellSize() * Vec3(cell[0] + (a & 1), cell[1] + ((a >> 1) & 1), cell[2] + ((a >> 2) & 1));
}

/// Which linear piece of the box SDF holds local point q: phi = +-x_k - a on the union of the
/// inside pyramid under face (k, sign) and the outside slab over it (a convex set), labelled
/// 2k + (x_k > 0); -1 for the edge and corner regions outside, where phi is not linear.
int boxLinearPiece(const Vec3& local, double a) {
  const Vec3 q = local.cwiseAbs() - Vec3::Constant(a);
  int positive = 0;
  int k = 0;
  for (int j = 0; j < 3; ++j) {
    if (q[j] > 0.0) {
      ++positive;
      k = j;
    }
  }
  if (positive > 1) {
    return -1;
  }
  if (positive == 0) {
    q.maxCoeff(&k);
  }
  return 2 * k + (local[k] > 0.0 ? 1 : 0);
}

// ---------------------------------------------------------------------------------------------
// Exact distance

TEST(MeshDistance, MatchesTheClosedFormOfARotatedBox) {
  TriangleMesh cube = test::makeBox(1.0, 1.0, 1.0);
  geometry::translate(cube, Vec3::Constant(-0.5));
  const Mat3 r = test::someRotation();
  const Vec3 t(0.3, -0.2, 0.1);
  geometry::transform(cube, r, t);
  const MeshDistance exact(cube);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int s = 0; s < 5000; ++s) {
    const Vec3 x = t + Vec3(u(rng), u(rng), u(rng));
    const ClosestPoint c = exact.closest(x);
    // Closest point and distance are a few dot products on O(1) numbers: 1e-12 m is round-off.
    EXPECT_NEAR(c.signedDistance, boxSdf(r.transpose() * (x - t), 0.5), 1e-12) << x.transpose();
    EXPECT_NEAR((x - c.point).norm(), c.distance, 1e-12);
  }
}

TEST(MeshDistance, SignAtTheAcuteEdgesAndCornersOfAFlatTetrahedron) {
  // Edges with a small interior dihedral angle are where the sign from a single face normal
  // fails: outside such an edge, x - c can lie almost along one face normal and make an obtuse
  // angle with the other. The pseudo-normals must get every point right.
  const TriangleMesh tet = test::makeTetrahedron(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.3, 0.3, 0.06));
  const MeshDistance exact(tet);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  int inside = 0;
  for (int s = 0; s < 4000; ++s) {
    // A point within 0.05 of a random point of a random edge or corner.
    const int e = s % 6;
    static constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    const double t = s % 12 < 6 ? u(rng) : 0.0;
    const Vec3 p = tet.vertices[kEdges[e][0]] + t * (tet.vertices[kEdges[e][1]] - tet.vertices[kEdges[e][0]]);
    const Vec3 x = p + 0.05 * u(rng) * Vec3(g(rng), g(rng), g(rng)).normalized();
    const bool in = insideByWinding(tet, x);
    inside += in ? 1 : 0;
    EXPECT_EQ(exact.signedDistance(x) < 0.0, in) << x.transpose();
  }
  EXPECT_GT(inside, 100); // the test must probe both sides
}

class SignOfShape : public ::testing::TestWithParam<std::string> {};

TEST_P(SignOfShape, ExactSignAgreesWithWindingNumberIncludingNearTheSurface) {
  const TriangleMesh& mesh = shape(GetParam());
  const MeshDistance exact(mesh);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  const Box3 box = mesh.bounds();
  int checked = 0;
  // Random points in the bounding box grown by 10 %.
  for (int s = 0; s < 1500; ++s) {
    const Vec3 x = box.min - 0.1 * box.size() + 1.2 * box.size().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    EXPECT_EQ(exact.signedDistance(x) < 0.0, insideByWinding(mesh, x)) << x.transpose();
    ++checked;
  }
  // Points 1e-4 Dn and 1e-7 Dn from vertices, edge points and face points in random directions:
  // the pseudo-normal sign must hold where the closest feature is an edge or a vertex, at
  // concave corners (the members' joins) as well as convex ones.
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const auto c = mesh.corners(t);
    const double b1 = u(rng);
    const double b2 = u(rng) * (1.0 - b1);
    const Vec3 onSurface[3] = {c[0], c[0] + b1 * (c[1] - c[0]), c[0] + b1 * (c[1] - c[0]) + b2 * (c[2] - c[0])};
    for (const Vec3& p : onSurface) {
      for (double offset : {1e-4, 1e-7}) {
        const Vec3 x = p + offset * Vec3(g(rng), g(rng), g(rng)).normalized();
        const double w = windingNumber(mesh, x);
        ASSERT_TRUE(std::abs(w) < 1e-6 || std::abs(w - 1.0) < 1e-6) << "winding number not settled: " << w;
        EXPECT_EQ(exact.signedDistance(x) < 0.0, w > 0.5) << GetParam() << " triangle " << t << " at " << x.transpose();
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 1500);
}

INSTANTIATE_TEST_SUITE_P(NonConvexUnits, SignOfShape, ::testing::Values("dolos", "coreloc", "vcross"));

// ---------------------------------------------------------------------------------------------
// The cube: interpolation exact on flat faces, bounded at edges and corners

struct CubeCase {
  std::string name;
  Mat3 rotation;
  Vec3 translation;
  double cellsPerDn;
};

/// The unit cube axis-aligned at 23.37 cells per Dn (faces, edges and corners fall between nodes)
/// and rotated and shifted at the default resolution (faces oblique to the grid).
std::vector<CubeCase> cubeCases() {
  return {{"aligned", Mat3::Identity(), Vec3(0.0, 0.0, 0.0), 23.37},
          {"rotated", test::someRotation(), Vec3(0.013, -0.031, 0.007), 24.0}};
}

class CubeLevelSet : public ::testing::TestWithParam<int> {
protected:
  void SetUp() override {
    c_ = cubeCases()[static_cast<std::size_t>(GetParam())];
    TriangleMesh cube = test::makeBox(1.0, 1.0, 1.0);
    geometry::translate(cube, Vec3::Constant(-0.5));
    geometry::transform(cube, c_.rotation, c_.translation);
    LevelSetSettings settings;
    settings.cellsPerDn = c_.cellsPerDn;
    ls_ = LevelSet(cube, settings, "cube");
  }
  [[nodiscard]] Vec3 local(const Vec3& x) const { return c_.rotation.transpose() * (x - c_.translation); }
  [[nodiscard]] double exact(const Vec3& x) const { return boxSdf(local(x), 0.5); }
  /// Random point in the grid box.
  Vec3 randomPoint(std::mt19937_64& rng) const {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    return ls_.gridBounds().min + ls_.gridBounds().size().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
  }
  /// Random point within 1.5 h of a random point of a random cube edge (corners included).
  Vec3 nearEdgePoint(std::mt19937_64& rng) const {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<int> axis(0, 2);
    std::uniform_int_distribution<int> sign(0, 1);
    Vec3 p;
    const int along = axis(rng);
    for (int k = 0; k < 3; ++k) {
      p[k] = k == along ? 0.5 * u(rng) : (sign(rng) ? 0.5 : -0.5);
    }
    if (sign(rng)) { // half of them at a corner
      p[along] = p[along] > 0 ? 0.5 : -0.5;
    }
    return c_.rotation * p + c_.translation + 1.5 * ls_.cellSize() * Vec3(u(rng), u(rng), u(rng));
  }
  /// The linear piece holding all 8 nodes of x's cell, or -1 if they differ.
  [[nodiscard]] int cellPiece(const Vec3& x) const {
    std::array<int, 3> cell{};
    cellFractions(ls_, x, &cell);
    const int first = boxLinearPiece(local(cellNode(ls_, cell, 0)), 0.5);
    for (int a = 1; a < 8; ++a) {
      if (boxLinearPiece(local(cellNode(ls_, cell, a)), 0.5) != first) {
        return -1;
      }
    }
    return first;
  }
  CubeCase c_;
  LevelSet ls_;
};

TEST_P(CubeLevelSet, FlatFacesAreExactAndTheirGradientIsTheFaceNormal) {
  const double h = ls_.cellSize();
  std::mt19937_64 rng(17);
  int flat = 0;
  double worstPhi = 0.0;
  double worstNormal = 0.0;
  for (int s = 0; s < 20000; ++s) {
    const Vec3 x = randomPoint(rng);
    const int piece = cellPiece(x);
    if (piece < 0) {
      continue;
    }
    // All 8 nodes on one linear piece phi = +-x_k - a of the SDF, a convex set: the whole cell is
    // on it, and trilinear interpolation reproduces a linear function exactly. What remains is
    // the float rounding of the node values.
    ++flat;
    const LevelSetQuery q = ls_.query(x);
    const double e = exact(x);
    const Vec3 faceNormal = c_.rotation * ((piece % 2 ? 1.0 : -1.0) * Vec3::Unit(piece / 2));
    EXPECT_NEAR(q.phi, e, floatTolerance(std::abs(e), h)) << x.transpose();
    // Gradient: differences of float nodes over h, so the rounding is amplified by 1 / h.
    EXPECT_NEAR((q.gradient - faceNormal).norm(), 0.0, 4.0 * floatTolerance(std::abs(e), h) / h) << x.transpose();
    EXPECT_NEAR((q.normal - faceNormal).norm(), 0.0, 4.0 * floatTolerance(std::abs(e), h) / h);
    worstPhi = std::max(worstPhi, std::abs(q.phi - e) / h);
    worstNormal = std::max(worstNormal, (q.normal - faceNormal).norm());
  }
  // Most of the grid box is in the face pieces; the test must have looked at many points.
  EXPECT_GT(flat, 8000);
  std::printf("[ cube %s ] %d points in face-region cells: max |phi - exact| = %.2e h, max |n - n_face| = %.2e\n",
              c_.name.c_str(), flat, worstPhi, worstNormal);
}

TEST_P(CubeLevelSet, EdgeAndCornerErrorIsOneSidedAndWithinTheLipschitzBound) {
  const double h = ls_.cellSize();
  std::mt19937_64 rng(19);
  double worst = 0.0;
  double worstRatio = 0.0;
  for (int s = 0; s < 20000; ++s) {
    const Vec3 x = s % 2 ? randomPoint(rng) : nearEdgePoint(rng);
    const double e = exact(x);
    const double phi = ls_.distance(x);
    const double tol = floatTolerance(std::abs(e), h);
    // The SDF of a convex body is convex, and a trilinear interpolant is a convex combination of
    // node values at points whose weighted mean is x: by Jensen, phi >= exact. Near a convex edge
    // the grid reports a shallower penetration (a rounded edge), never a deeper one.
    EXPECT_GE(phi, e - tol) << x.transpose();
    // Lipschitz bound (lipschitzBound above), <= sqrt(3) h / 2 = 0.866 h at the cell centre.
    const double bound = lipschitzBound(ls_, x);
    EXPECT_LE(phi - e, bound + tol) << x.transpose();
    worst = std::max(worst, (phi - e) / h);
    if (bound > 0.05 * h) {
      worstRatio = std::max(worstRatio, (phi - e) / bound);
    }
  }
  std::printf("[ cube %s ] max (phi - exact) = %.3f h; largest share of the pointwise Lipschitz bound used: %.2f\n",
              c_.name.c_str(), worst, worstRatio);
}

INSTANTIATE_TEST_SUITE_P(AlignedAndRotated, CubeLevelSet, ::testing::Values(0, 1));

TEST(CubeLevelSetOutside, CurvatureBoundInTheEdgeAndCornerRegions) {
  // Outside a convex body at distance d the SDF is smooth with second derivatives along any axis
  // between 0 and 1 / d. Trilinear interpolation = three 1D linear interpolations in turn, each
  // with error <= h^2 / 8 max |f''|, so on a cell at distance r from the cube the error is at
  // most 3 h^2 / (8 r): second order in h where the Lipschitz bound is first order.
  TriangleMesh cube = test::makeBox(1.0, 1.0, 1.0);
  geometry::translate(cube, Vec3::Constant(-0.5));
  LevelSetSettings settings;
  settings.cellsPerDn = 23.37;
  const LevelSet ls(cube, settings);
  const double h = ls.cellSize();
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0;
  for (int s = 0; s < 20000; ++s) {
    const Vec3 x = ls.gridBounds().min + ls.gridBounds().size().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    std::array<int, 3> cell{};
    cellFractions(ls, x, &cell);
    const Vec3 lo = cellNode(ls, cell, 0);
    const Vec3 gap = (lo - Vec3::Constant(0.5)).cwiseMax(Vec3::Constant(-0.5) - (lo + Vec3::Constant(h))).cwiseMax(0.0);
    const double r = gap.norm();
    if (r <= 0.0) {
      continue;
    }
    ++checked;
    const double e = boxSdf(x, 0.5);
    EXPECT_LE(ls.distance(x) - e, 3.0 * h * h / (8.0 * r) + floatTolerance(e, h)) << x.transpose();
  }
  EXPECT_GT(checked, 5000);
}

// ---------------------------------------------------------------------------------------------
// Non-convex units

class UnitLevelSet : public ::testing::TestWithParam<std::string> {};

TEST_P(UnitLevelSet, SignOfNodesAndOfTheInterpolantAgreesWithWindingNumber) {
  const TriangleMesh& mesh = shape(GetParam());
  const LevelSet& ls = shapeLevelSet(GetParam());
  const double h = ls.cellSize();
  // Every node within 1.5 h of the surface (where a wrong sign would matter and where a sign
  // method is most easily fooled) must have the winding number's sign.
  int nodes = 0;
  for (int k = 0; k < ls.nodeCounts()[2]; ++k) {
    for (int j = 0; j < ls.nodeCounts()[1]; ++j) {
      for (int i = 0; i < ls.nodeCounts()[0]; ++i) {
        const double v = ls.nodeValue(i, j, k);
        if (std::abs(v) > 1.5 * h) {
          continue;
        }
        const Vec3 x = ls.origin() + h * Vec3(i, j, k);
        EXPECT_EQ(v < 0.0, insideByWinding(mesh, x)) << GetParam() << " node " << i << " " << j << " " << k;
        ++nodes;
      }
    }
  }
  EXPECT_GT(nodes, 1000);
  // At random points, the interpolated phi has the right sign wherever the exact distance exceeds
  // the interpolation error bound (closer than that, the sign of the interpolant is within error).
  const MeshDistance exact(mesh);
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int s = 0; s < 3000; ++s) {
    const Vec3 x = ls.gridBounds().min + ls.gridBounds().size().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    const double e = exact.signedDistance(x);
    const double phi = ls.distance(x);
    const double bound = lipschitzBound(ls, x) + floatTolerance(std::abs(e), h);
    EXPECT_LE(std::abs(phi - e), bound) << x.transpose();
    if (std::abs(e) > bound) {
      EXPECT_EQ(phi < 0.0, insideByWinding(mesh, x)) << x.transpose();
    }
  }
}

TEST_P(UnitLevelSet, GradientHasUnitLengthAwayFromTheMedialAxis) {
  const TriangleMesh& mesh = shape(GetParam());
  const LevelSet& ls = shapeLevelSet(GetParam());
  const MeshDistance exact(mesh);
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> deviation;
  double worstAnywhere = 0.0;
  for (int s = 0; s < 6000; ++s) {
    const Vec3 x = ls.gridBounds().min + ls.gridBounds().size().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    const LevelSetQuery q = ls.query(x);
    // Each component of the gradient is a weighted mean of node differences over one cell edge.
    EXPECT_LE(q.gradient.cwiseAbs().maxCoeff(), 1.0 + 1e-5);
    worstAnywhere = std::max(worstAnywhere, std::abs(q.gradient.norm() - 1.0));
    // Away from the medial axis: the exact SDF gradients (unit vectors from the closest point) at
    // the 8 nodes of the cell agree within 10 degrees (no ridge, edge or corner crosses the cell).
    std::array<int, 3> cell{};
    cellFractions(ls, x, &cell);
    std::array<Vec3, 8> g;
    for (int a = 0; a < 8; ++a) {
      const Vec3 node = cellNode(ls, cell, a);
      const ClosestPoint c = exact.closest(node);
      g[static_cast<std::size_t>(a)] = (c.signedDistance < 0.0 ? -1.0 : 1.0) * (node - c.point).normalized();
    }
    double minCos = 1.0;
    for (const Vec3& a : g) {
      for (const Vec3& b : g) {
        minCos = std::min(minCos, a.dot(b));
      }
    }
    if (minCos >= std::cos(10.0 * std::numbers::pi / 180.0)) {
      deviation.push_back(std::abs(q.gradient.norm() - 1.0));
      // The normal there is within about 10 degrees of the exact one at any node.
      EXPECT_GT(q.normal.dot(g[0]), std::cos(12.0 * std::numbers::pi / 180.0)) << x.transpose();
    }
  }
  ASSERT_GT(deviation.size(), 2000u);
  std::sort(deviation.begin(), deviation.end());
  const double worst = deviation.back();
  // If all gradients over the cell lay within a 10-degree cone the trilinear gradient would be
  // within sqrt(3) x 2 sin(5 deg) = 0.30 of the cone axis; measured worst 0.04 (dolos, coreloc);
  // the tolerance 0.1 guards against regressions with room for other shapes.
  EXPECT_LT(worst, 0.1);
  std::printf("[ %s ] | |grad phi| - 1 | off the medial axis (%zu points): median %.1e, max %.3f; anywhere: max %.3f\n",
              GetParam().c_str(), deviation.size(), deviation[deviation.size() / 2], worst, worstAnywhere);
}

INSTANTIATE_TEST_SUITE_P(NonConvexUnits, UnitLevelSet, ::testing::Values("dolos", "coreloc", "vcross"));

// ---------------------------------------------------------------------------------------------
// Scaling, outside the grid, culling, threads

TEST(LevelSetScale, ScaledQueryEqualsTheLevelSetOfTheScaledMesh) {
  const TriangleMesh& dolos = shape("dolos");
  const LevelSet& base = shapeLevelSet("dolos");
  std::mt19937_64 rng(37);
  std::uniform_real_distribution<double> u(-0.2, 1.2); // a tenth of the points outside the grid box
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  {
    // s = 2 is exact in binary: the scaled mesh's grid is the base grid times 2 node for node (same
    // cellsPerDn, same counts), so the two agree to the float rounding of the node values.
    const double s = 2.0;
    TriangleMesh big = dolos;
    geometry::scale(big, s);
    const LevelSet scaled(big);
    ASSERT_EQ(scaled.nodeCounts(), base.nodeCounts());
    for (int t = 0; t < 2000; ++t) {
      const Vec3 x = scaled.gridBounds().min + scaled.gridBounds().size().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
      const double direct = scaled.distance(x);
      EXPECT_NEAR(base.distance(x, s), direct, floatTolerance(std::abs(direct), scaled.cellSize())) << x.transpose();
      const LevelSetQuery q = base.query(x, s);
      EXPECT_NEAR((q.gradient - scaled.gradient(x)).norm(), 0.0, 1e-5);
    }
  }
  {
    // A generic factor: compare with the exact SDF of the scaled mesh. The base grid seen at scale
    // s has cells s h, so the error bound is the Lipschitz bound of the base grid at x / s, times s.
    const double s = 0.37;
    TriangleMesh small = dolos;
    geometry::scale(small, s);
    const MeshDistance exact(small);
    for (int t = 0; t < 2000; ++t) {
      const Vec3 f(u01(rng), u01(rng), u01(rng));
      const Vec3 x = s * (base.gridBounds().min + base.gridBounds().size().cwiseProduct(f));
      const double e = exact.signedDistance(x);
      const double bound = s * lipschitzBound(base, x / s) + floatTolerance(std::abs(e), s * base.cellSize());
      EXPECT_LE(std::abs(base.distance(x, s) - e), bound) << x.transpose();
    }
  }
}

TEST(LevelSetOutside, PositiveBoundedAndContinuousAtTheGridBox) {
  const TriangleMesh& mesh = shape("coreloc");
  const LevelSet& ls = shapeLevelSet("coreloc");
  const MeshDistance exact(mesh);
  const Box3 grid = ls.gridBounds();
  const Box3 meshBox = ls.meshBounds();
  std::mt19937_64 rng(41);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> r(0.01, 10.0);
  const auto boxDistance = [](const Box3& b, const Vec3& x) {
    return ((b.min - x).cwiseMax(0.0) + (x - b.max).cwiseMax(0.0)).norm();
  };
  for (int t = 0; t < 3000; ++t) {
    // A point outside the grid box at distance 0.01 to 10 Dn in a random direction.
    const Vec3 dir = Vec3(g(rng), g(rng), g(rng)).normalized();
    Vec3 x = grid.centre() + dir.cwiseProduct(0.5 * grid.size());
    x += r(rng) * dir;
    if (boxDistance(grid, x) <= 0.0) {
      continue;
    }
    const LevelSetQuery q = ls.query(x);
    const double e = exact.signedDistance(x);
    // phi = |x - c| + phi(c): positive, at least the distance to the mesh box (a lower bound of the
    // true distance), and, since e(x) <= |x - c| + e(c), at least e(x) minus the interpolation
    // error at c (at most the Lipschitz bound at c, and c is >= 3 h from the mesh).
    const Vec3 c = x.cwiseMax(grid.min).cwiseMin(grid.max);
    EXPECT_GT(q.phi, 0.0);
    EXPECT_GE(q.phi, boxDistance(meshBox, x) - lipschitzBound(ls, c)) << x.transpose();
    EXPECT_GE(q.phi, e - lipschitzBound(ls, c) - floatTolerance(e, ls.cellSize())) << x.transpose();
    // The extension's gradient: unit along the clamped axes, the grid's along the free ones.
    EXPECT_GT(q.normal.dot((x - c).normalized()), 0.0);
  }
  // Continuity across the box face: phi is 1-Lipschitz in the 1-norm inside and outside, so a
  // step of 1e-9 m across the boundary changes phi by at most 2e-9 m (plus float rounding).
  for (int k = 0; k < 3; ++k) {
    Vec3 inside = grid.centre();
    inside[k] = grid.max[k] - 1e-9;
    Vec3 outside = inside;
    outside[k] = grid.max[k] + 1e-9;
    EXPECT_NEAR(ls.distance(inside), ls.distance(outside), 2e-9 + 1e-12);
  }
  // Far away the extension is cheap and close to the distance to the grid box plus a margin.
  EXPECT_GT(ls.distance(Vec3(1e3, 0.0, 0.0)), 1e3 - grid.max.x());
}

TEST(LevelSetLookup, FinishingAQueryFromTheValueTestGivesTheSameBits) {
  // The narrow phase tests value(x, at) against the margin and finishes only the samples that pass
  // with query(at): a query made that way must equal query(x) bit for bit, and its phi the value
  // tested, inside the grid box and outside it (where phi = |x - c| + phi(c)); otherwise a sample
  // could pass the test with one value and be pushed with another.
  const LevelSet& ls = shapeLevelSet("coreloc");
  const Box3 grid = ls.gridBounds();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.3, 1.3); // 30 % beyond the box on each side
  int outside = 0;
  for (int t = 0; t < 20000; ++t) {
    const Vec3 x = grid.min + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(grid.size());
    LevelSet::Lookup at;
    const double v = ls.value(x, at);
    const LevelSetQuery finished = ls.query(at);
    const LevelSetQuery direct = ls.query(x);
    ASSERT_EQ(v, ls.value(x)) << x.transpose();
    ASSERT_EQ(finished.phi, v) << x.transpose();
    ASSERT_EQ(direct.phi, v) << x.transpose();
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(finished.gradient[k], direct.gradient[k]) << x.transpose();
      ASSERT_EQ(finished.normal[k], direct.normal[k]) << x.transpose();
    }
    outside += at.away.squaredNorm() > 0.0 ? 1 : 0;
  }
  EXPECT_GT(outside, 5000) << "the points must cover the outside of the grid box too";
}

TEST(LevelSetCulling, MayPenetrateIsConservative) {
  const LevelSet& ls = shapeLevelSet("dolos");
  const double s = 1.7; // a scaled instance
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::uniform_real_distribution<double> size(0.01, 0.3);
  std::uniform_real_distribution<double> w(0.0, 1.0);
  int culled = 0;
  int kept = 0;
  for (int t = 0; t < 3000; ++t) {
    Box3 box;
    box.min = s * Vec3(u(rng), u(rng), u(rng));
    box.max = box.min + s * Vec3(size(rng), size(rng), size(rng));
    if (ls.mayPenetrate(box, s)) {
      ++kept;
      continue;
    }
    ++culled;
    // A culled box must have no point inside: check its corners, centre and random points.
    for (int p = 0; p < 20; ++p) {
      const Vec3 x = box.min + box.size().cwiseProduct(Vec3(w(rng), w(rng), w(rng)));
      EXPECT_GE(ls.distance(x, s), 0.0) << x.transpose();
    }
    EXPECT_GE(ls.distance(box.min, s), 0.0);
    EXPECT_GE(ls.distance(box.max, s), 0.0);
  }
  // The cull must actually cull (far boxes) and keep (boxes over the unit).
  EXPECT_GT(culled, 300);
  EXPECT_GT(kept, 300);
  EXPECT_TRUE(ls.mayPenetrate(Box3{Vec3::Constant(-0.01), Vec3::Constant(0.01)}, 1.0));
  EXPECT_FALSE(ls.mayPenetrate(Box3{Vec3::Constant(5.0), Vec3::Constant(6.0)}, 1.0));
}

TEST(LevelSetThreads, ConcurrentQueriesMatchSerialOnesAndBuildsRepeat) {
  const LevelSet& ls = shapeLevelSet("dolos");
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  std::vector<Vec3> points(20000);
  for (auto& p : points) {
    p = Vec3(u(rng), u(rng), u(rng));
  }
  std::vector<double> serial(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    serial[i] = ls.query(points[i], 1.3).phi;
  }
  std::vector<double> parallel(points.size());
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (std::size_t i = t; i < points.size(); i += 4) {
        parallel[i] = ls.query(points[i], 1.3).phi;
      }
    });
  }
  for (auto& t : threads) {
    t.join();
  }
  EXPECT_EQ(serial, parallel); // const queries share nothing mutable: bitwise equal
  // The (OpenMP) build writes each node once from exact data: two builds are bitwise equal.
  const LevelSet again(shape("dolos"));
  EXPECT_EQ(again.values(), ls.values());
}

TEST(LevelSetInput, BadSettingsAndMeshesAreRefusedWithTheKey) {
  const TriangleMesh& cube = shape("cube");
  LevelSetSettings bad;
  bad.cellsPerDn = -3.0;
  EXPECT_THROW(LevelSet(cube, bad, "cube"), core::InputError);
  LevelSetSettings huge;
  huge.cellSize = 1e-5; // 1e15 nodes: a size in the wrong unit
  try {
    LevelSet ls(cube, huge, "cube");
    FAIL() << "expected InputError";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("maxNodes"), std::string::npos) << e.what();
  }
  LevelSetSettings noMargin;
  noMargin.marginCells = 0;
  EXPECT_THROW(LevelSet(cube, noMargin, "cube"), core::InputError);
  TriangleMesh inverted = cube;
  geometry::flipOrientation(inverted);
  EXPECT_THROW(LevelSet(inverted, {}, "cube"), core::InputError);
}

// ---------------------------------------------------------------------------------------------
// Figures for the report: resolution across the thinnest member, grid size, memory, build time

/// Thickness of the solid below surface point p along -n: the nearest hit of the ray p - t n,
/// t > 0, with a triangle (Moller-Trumbore ray-triangle intersection), brute force.
double thicknessBelow(const TriangleMesh& mesh, const Vec3& p, const Vec3& n) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const auto c = mesh.corners(t);
    const Vec3 e1 = c[1] - c[0];
    const Vec3 e2 = c[2] - c[0];
    const Vec3 q = (-n).cross(e2);
    const double det = e1.dot(q);
    if (std::abs(det) < 1e-14) {
      continue;
    }
    const Vec3 sv = p - c[0];
    const double b1 = sv.dot(q) / det;
    const Vec3 r = sv.cross(e1);
    const double b2 = (-n).dot(r) / det;
    const double dist = e2.dot(r) / det;
    if (b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 && dist > 1e-9) {
      best = std::min(best, dist);
    }
  }
  return best;
}

TEST(LevelSetReport, DefaultResolutionResolvesTheThinnestMembers) {
  std::mt19937_64 rng(53);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::printf("[ report ] shape      triangles  grid         nodes    kB    build s  h/Dn    thinnest/h\n");
  for (const std::string name : {"cube", "dolos", "coreloc", "vcross", "rock", "tetrapod"}) {
    const TriangleMesh& mesh = shape(name);
    const LevelSet ls(mesh);
    // Thinnest member: the smallest thickness below 2500 random face points (uniform by triangle
    // area, kept 0.02 Dn from the triangle's edges so the ray is not cast along a joint).
    std::vector<double> cumulative;
    double total = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      total += mesh.area(t);
      cumulative.push_back(total);
    }
    double thinnest = std::numeric_limits<double>::infinity();
    for (int s = 0; s < 2500; ++s) {
      const auto t = static_cast<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), u(rng) * total) -
                                              cumulative.begin());
      const auto c = mesh.corners(std::min(t, mesh.triangleCount() - 1));
      double b1 = u(rng);
      double b2 = u(rng);
      if (b1 + b2 > 1.0) {
        b1 = 1.0 - b1;
        b2 = 1.0 - b2;
      }
      const Vec3 p = c[0] + b1 * (c[1] - c[0]) + b2 * (c[2] - c[0]);
      const Vec3 n = (c[1] - c[0]).cross(c[2] - c[0]).normalized();
      thinnest = std::min(thinnest, thicknessBelow(mesh, p, n));
    }
    const auto nc = ls.nodeCounts();
    std::printf("[ report ] %-10s %6zu    %3d x %3d x %3d %7zu %6.0f  %6.3f  1/%.0f  %5.1f (%.3f Dn)\n", name.c_str(),
                mesh.triangleCount(), nc[0], nc[1], nc[2], ls.values().size(), ls.memoryBytes() / 1024.0,
                ls.buildSeconds(), ls.nominalDiameter() / ls.cellSize(), thinnest / ls.cellSize(), thinnest);
    // The brief: at least 6 to 8 cells across the thinnest member at the default resolution. The
    // sampled minimum overestimates the true one slightly (the Dolos fluke end is 0.33 Dn across
    // flats, 8.0 cells), hence the floor of 7.5 rather than 8.
    EXPECT_GE(thinnest / ls.cellSize(), 7.5) << name;
  }
  // A 1000-triangle unit (the Dolos refined by bisection): build time for the record, not timed.
  const TriangleMesh fine = geometry::refineToCount(shape("dolos"), 1000);
  const LevelSet ls(fine);
  std::printf("[ report ] dolos refined to %zu triangles: grid %d^3, build %.3f s\n", fine.triangleCount(),
              ls.nodeCounts()[0], ls.buildSeconds());
  EXPECT_EQ(ls.nodeCounts(), shapeLevelSet("dolos").nodeCounts()); // refinement does not move the surface
  // Query cost for the record (random points over the unit's box, scaled instance).
  std::vector<Vec3> points(200000);
  std::uniform_real_distribution<double> box(-0.9, 0.9);
  for (auto& p : points) {
    p = Vec3(box(rng), box(rng), box(rng));
  }
  const auto start = std::chrono::steady_clock::now();
  double sum = 0.0;
  for (const Vec3& p : points) {
    sum += ls.query(p, 1.1).phi;
  }
  const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() /
                    static_cast<double>(points.size());
  std::printf("[ report ] query (phi, gradient, normal) on the dolos grid: %.0f ns per point (checksum %.3f)\n", ns,
              sum);
}

} // namespace
} // namespace armour::contact
