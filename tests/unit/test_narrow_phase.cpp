// SPDX-License-Identifier: GPL-3.0-or-later
// The narrow phase's near-sample lists (contact/NarrowPhase.hpp): a pair that reuses its list finds
// the same contact points, bit for bit, as a full search, over a walk of poses that keeps the pair
// in contact, crosses the list's slack many times, changes the margin and the scale.

#include "contact/NarrowPhase.hpp"
#include "support/ShapeCache.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <random>

namespace {

using armour::contact::ContactPoint;
using armour::contact::ContactPose;
using armour::contact::ContactShape;
using armour::contact::LevelSet;
using armour::contact::PairSampleCache;
using armour::contact::SampleBuckets;
using armour::contact::SurfaceSamples;
using armour::geometry::Vec3;
using Quat = Eigen::Quaterniond;

struct Shape {
  std::unique_ptr<LevelSet> levelSet;
  std::unique_ptr<SurfaceSamples> samples;
  SampleBuckets buckets;
  ContactShape view;
};

Shape makeShape(const std::string& name) {
  const auto& mesh = armour::test::unitShape(name);
  Shape s;
  s.levelSet = std::make_unique<LevelSet>(mesh);
  s.samples = std::make_unique<SurfaceSamples>(mesh);
  s.buckets = armour::contact::buildBuckets(*s.samples, mesh.bounds());
  double radius = 0.0;
  for (const Vec3& v : mesh.vertices) radius = std::max(radius, v.norm());
  s.view = {s.levelSet.get(), s.samples.get(), &s.buckets, radius};
  return s;
}

std::uint32_t searches(const PairSampleCache& c) { return c.directions[0].searches + c.directions[1].searches; }
std::uint32_t reuses(const PairSampleCache& c) { return c.directions[0].reuses + c.directions[1].reuses; }

ContactPose pose(const Vec3& x, const Quat& q, double scale) {
  ContactPose p;
  p.position = x;
  p.orientation = q.normalized();
  p.rotation = p.orientation.toRotationMatrix();
  p.scale = scale;
  p.dn = scale; // the unit shapes have Dn = 1 m
  return p;
}

void expectSamePoints(const std::vector<ContactPoint>& full, const std::vector<ContactPoint>& listed, int step) {
  ASSERT_EQ(full.size(), listed.size()) << "step " << step;
  for (std::size_t k = 0; k < full.size(); ++k) {
    ASSERT_EQ(full[k].key, listed[k].key) << "step " << step << " point " << k;
    ASSERT_EQ(full[k].point, listed[k].point) << "step " << step;
    ASSERT_EQ(full[k].normal, listed[k].normal) << "step " << step;
    ASSERT_EQ(full[k].depth, listed[k].depth) << "step " << step;
    ASSERT_EQ(full[k].area, listed[k].area) << "step " << step;
  }
}

// A Core-Loc wanders against another (and a cube against a Core-Loc) by steps of up to 0.02 Dn and
// 1 degree, pulled back towards contact; the margin switches between 0 (penalty) and 0.05 Dn.
void walk(const std::string& nameA, const std::string& nameB, double scaleB) {
  const Shape A = makeShape(nameA);
  const Shape B = makeShape(nameB);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const ContactPose pa = pose(Vec3::Zero(), Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized())), 1.0);
  Vec3 xb(0.9, 0.1, 0.2);
  Quat qb(Eigen::AngleAxisd(1.1, Vec3(-1, 0.5, 2).normalized()));
  PairSampleCache cache;
  std::size_t points = 0;
  std::size_t offered = 0; // listed samples in the calls the lists served
  for (int step = 0; step < 600; ++step) {
    const Vec3 pull = -0.004 * (xb.norm() - 0.8) * xb.normalized();
    xb += 0.02 * Vec3(u(rng), u(rng), u(rng)) / std::sqrt(3.0) * (step % 50 < 40 ? 0.1 : 1.0) + pull;
    qb = Quat(Eigen::AngleAxisd(0.0175 * u(rng) * (step % 50 < 40 ? 0.1 : 1.0), Vec3(u(rng), u(rng), u(rng)).normalized())) * qb;
    const ContactPose pb = pose(xb, qb, scaleB);
    const double margin = step % 7 < 4 ? 0.0 : 0.05;
    std::vector<ContactPoint> full, listed;
    const double deepFull = armour::contact::samplesInLevelSets(A.view, pa, B.view, pb, margin, full);
    std::array<std::size_t, 2> sizeBefore{}, reusesBefore{};
    for (int d = 0; d < 2; ++d) {
      sizeBefore[d] = cache.directions[d].samples.size();
      reusesBefore[d] = cache.directions[d].reuses;
    }
    const double deepListed =
        armour::contact::samplesInLevelSets(A.view, pa, B.view, pb, margin, listed, &cache, 0.05);
    for (int d = 0; d < 2; ++d) {
      if (cache.directions[d].reuses > reusesBefore[d]) offered += sizeBefore[d];
    }
    ASSERT_EQ(deepFull, deepListed) << "step " << step;
    expectSamePoints(full, listed, step);
    points += full.size();
  }
  // The walk touched (else it proves nothing), and the lists both served and were made anew.
  EXPECT_GT(points, 600u);
  EXPECT_GT(reuses(cache), 200u);
  EXPECT_GT(searches(cache), 20u);
  // And the skip by value served too: some listed samples were looked up, not all of them.
  const std::size_t lookups = cache.directions[0].lookups + cache.directions[1].lookups;
  EXPECT_GT(lookups, 0u);
  EXPECT_LT(lookups, offered);
}

TEST(NearSampleLists, CoreLocOnCoreLocFindsTheFullSearchsPointsBitForBit) { walk("coreloc", "coreloc", 1.0); }

TEST(NearSampleLists, CubeOnCoreLocOfAnotherScaleFindsTheFullSearchsPointsBitForBit) { walk("coreloc", "cube", 0.7); }

TEST(NearSampleLists, AListMadeForOtherShapesIsNotUsed) {
  const Shape A = makeShape("coreloc");
  const Shape B = makeShape("cube");
  const Shape C = makeShape("tetrapod");
  const ContactPose pa = pose(Vec3::Zero(), Quat::Identity(), 1.0);
  const ContactPose pb = pose(Vec3(0.8, 0.0, 0.0), Quat::Identity(), 1.0);
  PairSampleCache cache;
  std::vector<ContactPoint> first, second, full;
  armour::contact::samplesInLevelSets(A.view, pa, B.view, pb, 0.0, first, &cache, 0.05);
  ASSERT_EQ(searches(cache), 2u);
  // Same poses, the second body now another shape: the lists must be made anew, not reused.
  armour::contact::samplesInLevelSets(A.view, pa, C.view, pb, 0.0, second, &cache, 0.05);
  armour::contact::samplesInLevelSets(A.view, pa, C.view, pb, 0.0, full);
  EXPECT_EQ(searches(cache), 4u);
  EXPECT_EQ(reuses(cache), 0u);
  expectSamePoints(full, second, 0);
}

} // namespace

// samplesInHalfSpaces skips a pair whose body ball (radius R about the centroid) lies outside one
// face by more than the margin. Against a brute-force search over every sample of a Core-Loc at
// 3000 poses around a 1 m box (near misses, touches, deep overlaps; margins 0 and 0.05 m): every
// point it returns is the brute force's, bit for bit, and it misses no sample inside the box (for
// margin 0 the two sets are equal). A wrong cull (the ball too small, the scale or the margin
// left out) drops points that are inside.
TEST(HalfSpaces, TheBallCullLosesNoSampleInsideTheSolid) {
  const Shape A = makeShape("coreloc");
  const std::vector<Vec3> normals{Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitZ()};
  const std::vector<double> offsets(6, 0.5);
  armour::contact::HalfSpaces solid{normals, offsets, {}};
  solid.region.extend(Vec3::Constant(-0.5));
  solid.region.extend(Vec3::Constant(0.5));
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::size_t inside = 0, culledPoses = 0;
  for (int step = 0; step < 3000; ++step) {
    const double scale = 0.8 + 0.4 * (u(rng) + 1.0) / 2.0;
    const double margin = step % 2 == 0 ? 0.0 : 0.05;
    const Vec3 x = (0.6 + 1.6 * (u(rng) + 1.0) / 2.0) * Vec3(u(rng), u(rng), u(rng)).normalized();
    const ContactPose pa = pose(x, Quat(Eigen::AngleAxisd(3.2 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized())), scale);
    std::vector<ContactPoint> found;
    const double deepest = armour::contact::samplesInHalfSpaces(A.view, pa, solid, margin, found);
    // Brute force: every sample, its largest face distance phi, in the function's arithmetic.
    std::vector<ContactPoint> expected;
    double expectedDeepest = 0.0;
    for (std::uint32_t i = 0; i < A.samples->positions().size(); ++i) {
      const Vec3 X = pa.position + pa.rotation * (scale * A.samples->positions()[i]);
      double phi = -std::numeric_limits<double>::infinity();
      std::size_t nearest = 0;
      for (std::size_t k = 0; k < normals.size(); ++k) {
        const double d = normals[k].dot(X) - offsets[k];
        if (d > phi) {
          phi = d;
          nearest = k;
        }
      }
      if (phi < 0.0) expectedDeepest = std::max(expectedDeepest, -phi);
      const double area = -scale * scale * (pa.rotation * A.samples->areaVectors()[i]).dot(normals[nearest]);
      if (phi < margin && area > 0.0) expected.push_back({i, X, normals[nearest], -phi, area});
    }
    ASSERT_EQ(deepest, expectedDeepest) << "step " << step;
    for (const ContactPoint& p : found) {
      const auto it = std::find_if(expected.begin(), expected.end(), [&](const ContactPoint& e) { return e.key == p.key; });
      ASSERT_NE(it, expected.end()) << "step " << step << ": sample " << p.key << " is not within the margin";
      ASSERT_EQ(it->point, p.point);
      ASSERT_EQ(it->depth, p.depth);
      ASSERT_EQ(it->area, p.area);
    }
    for (const ContactPoint& e : expected) {
      if (e.depth <= 0.0 && margin > 0.0) continue; // within the margin outside: the buckets may skip it
      const auto it = std::find_if(found.begin(), found.end(), [&](const ContactPoint& p) { return p.key == e.key; });
      ASSERT_NE(it, found.end()) << "step " << step << ": sample " << e.key << " at depth " << e.depth << " missed";
      inside += e.depth > 0.0 ? 1 : 0;
    }
    culledPoses += expected.empty() && found.empty() ? 1 : 0;
  }
  // The poses both touched (else it proves nothing) and missed.
  EXPECT_GT(inside, 10000u);
  EXPECT_GT(culledPoses, 300u);
}
