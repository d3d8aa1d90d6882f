// SPDX-License-Identifier: GPL-3.0-or-later
// The interlocking units built from members: Dolos, Core-Loc-like, Accropode-like, Xbloc-like.
// Every face of these shapes is planar, so the mesh is the exact polyhedron: volumes, centroids,
// inertias and cross-sections computed from it are exact to round-off, and the tolerances below
// are round-off bounds (1e-9) unless a calibrated constant is involved (stated where it is).

#include "core/Error.hpp"
#include "geometry/MassProperties.hpp"
#include "geometry/MeshValidation.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "support/TestMeshes.hpp"

#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <utility>

using namespace armour::geometry;

namespace {

constexpr double kVolume = 5.0; // m^3, seed 000's Core-Loc size; any positive volume would do

/// makeShape(name) at kVolume with default parameters, built once per test program (each OCC build
/// costs about 0.1 s and the file must stay fast).
const TriangleMesh& unit(const std::string& name) {
  static std::map<std::string, TriangleMesh> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    ShapeRequest request;
    request.volume = kVolume;
    it = cache.emplace(name, makeShape(name, request)).first;
  }
  return it->second;
}

TriangleMesh dolos(double waist) {
  ShapeRequest request;
  request.volume = kVolume;
  request.params = {{"waist", waist}};
  return makeShape("dolos", request);
}

/// Extent of the mesh's cross-section by the plane z = z0 along x and along y (m): the span of the
/// points where edges cross the plane (vertices on the plane included).
std::pair<double, double> sectionWidths(const TriangleMesh& mesh, double z0) {
  Box3 box;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const auto c = mesh.corners(t);
    for (int i = 0; i < 3; ++i) {
      const Vec3& a = c[i];
      const Vec3& b = c[(i + 1) % 3];
      const double da = a.z() - z0;
      const double db = b.z() - z0;
      if (da == 0.0) {
        box.extend(a);
      }
      if (da * db < 0.0) {
        box.extend(a + (b - a) * (da / (da - db)));
      }
    }
  }
  return {box.size().x(), box.size().y()};
}

/// Total area of the triangles whose outward normal is `normal` (a unit vector; to 1e-9) (m^2).
/// With `supportOnly`, only triangles on the supporting plane (the plane normal to `normal` that
/// touches the mesh from outside) count: the end face a member shows in that direction.
double areaFacing(const TriangleMesh& mesh, const Vec3& normal, bool supportOnly = false) {
  double support = -std::numeric_limits<double>::infinity();
  for (const Vec3& v : mesh.vertices) {
    support = std::max(support, normal.dot(v));
  }
  const double tolerance = 1e-9 * mesh.bounds().size().norm();
  double area = 0.0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 n = mesh.doubleAreaNormal(t);
    bool counts = n.normalized().dot(normal) > 1.0 - 1e-9;
    if (supportOnly) {
      for (const Vec3& v : mesh.corners(t)) {
        counts = counts && std::abs(normal.dot(v) - support) < tolerance;
      }
    }
    if (counts) {
      area += 0.5 * n.norm();
    }
  }
  return area;
}

/// Area of a regular octagon `width` across flats.
double octagonArea(double width) { return 2.0 * (std::sqrt(2.0) - 1.0) * width * width; }

class SlenderUnit : public ::testing::TestWithParam<std::string> {};

} // namespace

TEST_P(SlenderUnit, HitsRequestedVolumeAndIsAValidSolid) {
  const TriangleMesh& mesh = unit(GetParam());
  const MassProperties mp = computeMassProperties(mesh);
  // makeShape scales the exact polyhedron: the volume is met to round-off.
  EXPECT_NEAR(mp.volume, kVolume, 1e-9 * kVolume);
  const MeshInspection inspection = inspectMesh(mesh);
  EXPECT_TRUE(inspection.valid());
  EXPECT_EQ(inspection.components, 1u);
  EXPECT_TRUE(inspection.openEdges.empty());
  // Flat faces need few triangles; these meshes drive contact and load integration later.
  EXPECT_GE(mesh.triangleCount(), 200u);
  EXPECT_LE(mesh.triangleCount(), 3000u);
}

TEST_P(SlenderUnit, VolumeInvariantUnderRigidTransform) {
  TriangleMesh mesh = unit(GetParam());
  transform(mesh, armour::test::someRotation(), Vec3(250.0, -40.0, 12.0));
  // Reference-point-relative accumulation keeps round-off at 1e-10 even 250 m from the origin.
  EXPECT_NEAR(computeMassProperties(mesh).volume, kVolume, 1e-10 * kVolume);
}

TEST_P(SlenderUnit, CentroidAtTheCentreOfItsBoxAndInertiaAlignedWithTheFrame) {
  // Every unit here is symmetric about the centre of its bounding box (Dolos and Accropode by the
  // 90-degree rotoreflection about z that swaps their ends; Core-Loc and Xbloc by three mirror
  // planes), so the centroid (put at the origin by makeShape) is the box centre, and z (the shank
  // or height axis) is a principal axis.
  const TriangleMesh& mesh = unit(GetParam());
  const MassProperties mp = computeMassProperties(mesh);
  const Box3 box = mesh.bounds();
  const double size = box.size().maxCoeff();
  EXPECT_LT((box.centre() - mp.centroid).norm(), 1e-9 * size);
  const double scale = mp.inertia.trace();
  EXPECT_LT(std::abs(mp.inertia(0, 2)), 1e-9 * scale);
  EXPECT_LT(std::abs(mp.inertia(1, 2)), 1e-9 * scale);
  double alignment = 0.0; // the principal axis closest to z
  for (int i = 0; i < 3; ++i) {
    alignment = std::max(alignment, std::abs(mp.principalAxes.col(i).z()));
  }
  EXPECT_GT(alignment, 1.0 - 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Shapes, SlenderUnit, ::testing::Values("dolos", "coreloc", "accropode", "xbloc"));

// Documented volume relations, V / size^3 with size = the unit's extent along z (C, H or D). The
// member thickness of each shape is a 4-digit constant calibrated to the relation; rounding it
// moves V by under 0.05 %, so 0.2 % is asserted (the relations themselves are quoted to 2 digits).
TEST(SlenderUnitVolume, CoreLocIs022CCubed) {
  const TriangleMesh& mesh = unit("coreloc");
  const double c = mesh.bounds().size().z();
  EXPECT_NEAR(computeMassProperties(mesh).volume / (c * c * c), 0.22, 0.002 * 0.22);
}

TEST(SlenderUnitVolume, AccropodeIs034HCubed) {
  const TriangleMesh& mesh = unit("accropode");
  const double h = mesh.bounds().size().z();
  EXPECT_NEAR(computeMassProperties(mesh).volume / (h * h * h), 0.34, 0.002 * 0.34);
}

TEST(SlenderUnitVolume, XblocIsDCubedOverThree) {
  const TriangleMesh& mesh = unit("xbloc");
  const double d = mesh.bounds().size().z();
  EXPECT_NEAR(computeMassProperties(mesh).volume / (d * d * d), 1.0 / 3.0, 0.002 / 3.0);
}

TEST(SlenderUnitVolume, DolosIs016CCubedAtWaist032) {
  // Shore Protection Manual (1984): V = 0.16 C^3 for the standard waist ratio 0.32.
  const TriangleMesh mesh = dolos(0.32);
  const double c = mesh.bounds().size().z();
  EXPECT_NEAR(computeMassProperties(mesh).volume / (c * c * c), 0.16, 0.002 * 0.16);
}

TEST(SlenderUnitBox, EachUnitFillsItsDocumentedBox) {
  // Dolos, Accropode and Xbloc reach the same extent along all three axes; the Core-Loc-like H is
  // one member width (0.3561 C, its documented proportion) thick.
  for (const char* name : {"dolos", "accropode", "xbloc"}) {
    const Vec3 size = unit(name).bounds().size();
    EXPECT_NEAR(size.x() / size.z(), 1.0, 1e-9) << name;
    EXPECT_NEAR(size.y() / size.z(), 1.0, 1e-9) << name;
  }
  const Vec3 size = unit("coreloc").bounds().size();
  EXPECT_NEAR(size.x() / size.z(), 1.0, 1e-9);
  EXPECT_NEAR(size.y() / size.z(), 0.3561, 1e-9);
}

TEST(Dolos, WaistParameterSetsTheShankWidth) {
  // Measured from the mesh: the section through the shank centre (the box centre) is the shank's
  // octagon, B = waist x C across flats along both x and y.
  double previousRatio = 0.0;
  for (double waist : {0.32, 0.36, 0.42}) {
    const TriangleMesh mesh = dolos(waist);
    const Box3 box = mesh.bounds();
    const double c = box.size().z();
    const auto [bx, by] = sectionWidths(mesh, box.centre().z());
    EXPECT_NEAR(bx / c, waist, 1e-9) << "waist " << waist;
    EXPECT_NEAR(by / c, waist, 1e-9) << "waist " << waist;
    // A thicker waist puts more concrete in a unit of the same height.
    const double ratio = computeMassProperties(mesh).volume / (c * c * c);
    EXPECT_GT(ratio, previousRatio) << "waist " << waist;
    previousRatio = ratio;
  }
}

TEST(Dolos, FlukesAreTaperedWithFlatOctagonalEnds) {
  // The flukes' flat ends are the faces the unit shows towards -/+x (upper fluke) and -/+y (lower
  // fluke): each a regular octagon 0.5562 B across flats, the documented taper.
  const TriangleMesh& mesh = unit("dolos");
  const double c = mesh.bounds().size().z();
  const double b = 0.33 * c; // default waist
  for (const Vec3& direction : {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0)}) {
    EXPECT_NEAR(areaFacing(mesh, direction, true), octagonArea(0.5562 * b), 1e-9 * c * c) << direction.transpose();
  }
  // The top is the upper fluke's flat over its full-width middle: B long, one octagon side wide.
  EXPECT_NEAR(areaFacing(mesh, Vec3(0, 0, 1), true), b * (std::sqrt(2.0) - 1.0) * b, 1e-9 * c * c);
  // The S4 symmetry makes the two transverse moments equal: the flukes weigh the same.
  const MassProperties mp = computeMassProperties(mesh);
  EXPECT_NEAR(mp.inertia(0, 0), mp.inertia(1, 1), 1e-9 * mp.inertia.trace());
}

TEST(CoreLoc, JoinsCarry45DegreeChamfers) {
  // The chamfer faces are the only faces whose normals lie at 45 degrees in the x-z plane (the
  // outer members' tapers are far steeper): above and below the central member at both joins,
  // one face per sign combination of (x, z), all of equal area by symmetry.
  const TriangleMesh& mesh = unit("coreloc");
  const double c = mesh.bounds().size().z();
  const double first = areaFacing(mesh, Vec3(1.0, 0.0, 1.0).normalized());
  EXPECT_GT(first, 1e-3 * c * c) << "no chamfer at the joins";
  for (double sx : {-1.0, 1.0}) {
    for (double sz : {-1.0, 1.0}) {
      EXPECT_NEAR(areaFacing(mesh, Vec3(sx, 0.0, sz).normalized()), first, 1e-9 * c * c) << sx << ", " << sz;
    }
  }
}

TEST(Xbloc, LegsFormAnXInTheFrontView) {
  // The leg end faces face the four diagonals of the x-z plane, each one square leg section
  // (0.3671 D wide, the documented proportion).
  const TriangleMesh& mesh = unit("xbloc");
  const double d = mesh.bounds().size().z();
  const double t = 0.3671 * d;
  for (double sx : {-1.0, 1.0}) {
    for (double sz : {-1.0, 1.0}) {
      EXPECT_NEAR(areaFacing(mesh, Vec3(sx, 0.0, sz).normalized(), true), t * t, 1e-9 * d * d);
    }
  }
}

TEST(Dolos, RefusesAWaistOutsideItsRange) {
  for (double waist : {0.2, 0.5}) {
    ShapeRequest request;
    request.params = {{"waist", waist}};
    EXPECT_THROW(makeShape("dolos", request), armour::core::InputError) << waist;
  }
}

TEST(GmshShapes, BuiltAgainInOneProcessOnTwoThreadsTheMeshIsTheSame) {
  // The OpenCASCADE units are meshed by gmsh, which was left on the caller's thread count after its
  // first session and then gave another mesh each time (session 13: the second Core-Loc of a
  // process differed from the first in all 404 vertices on 2 threads). Every build must give the
  // first one's mesh, bit for bit, on any thread count.
  const int saved = omp_get_max_threads();
  omp_set_num_threads(2);
  ShapeRequest r;
  r.volume = 1.0;
  for (const char* name : {"coreloc", "dolos"}) {
    const auto first = makeShape(name, r);
    for (int k = 0; k < 2; ++k) {
      const auto again = makeShape(name, r);
      ASSERT_EQ(first.vertices.size(), again.vertices.size()) << name;
      for (std::size_t i = 0; i < first.vertices.size(); ++i) {
        ASSERT_EQ(first.vertices[i], again.vertices[i]) << name << " vertex " << i << ", build " << k + 2;
      }
    }
  }
  EXPECT_EQ(omp_get_max_threads(), 2) << "the caller's thread count is put back";
  omp_set_num_threads(saved);
}
