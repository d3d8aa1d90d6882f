// SPDX-License-Identifier: GPL-3.0-or-later
// The analytic wave-force models as World load stages (docs/theory.md, "Analytic wave forces"):
// the oscillating force of seed 001 eq. 1-2 and the shallow-wave force of seed 003 eq. 2 with
// ray-cast exposure. Checked against the closed forms, the impulse of a whole period, the energy
// bookkeeping of the World, lattice-count bounds of the exposed area, shadowing, the
// shallow-water travel time, and the errors of bad settings.

#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "hydro/Exposure.hpp"
#include "hydro/OscillatingForce.hpp"
#include "hydro/ShallowWaveForce.hpp"
#include "simulation/World.hpp"
#include "support/TestMeshes.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <omp.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace armour;
using namespace armour::hydro;
using simulation::BodySpec;
using simulation::World;
using simulation::WorldSettings;
using dynamics::BodyId;
using dynamics::Quat;
using dynamics::Vec3;

namespace {

constexpr double kPi = std::numbers::pi;

/// A world with one material and a unit cube shape (side 1 m, Dn = 1 m).
struct Scene {
  World world;
  simulation::MaterialId material = 0;
  simulation::ShapeId cube = 0;

  explicit Scene(WorldSettings settings = {}, simulation::Material m = {}) : world(settings) {
    material = world.addMaterial(m);
    geometry::ShapeRequest r;
    r.volume = 1.0;
    cube = world.addShape("cube", geometry::makeShape("cube", r));
  }
  BodyId add(const std::string& name, const Vec3& position, const Quat& orientation = Quat::Identity(),
             bool fixed = false) {
    BodySpec b;
    b.name = name;
    b.shape = cube;
    b.material = material;
    b.position = position;
    b.orientation = orientation;
    b.fixed = fixed;
    return world.addBody(b);
  }
};

/// Run `f` and expect a core::InputError whose message names `key`.
void expectInputError(const std::function<void()>& f, const std::string& key) {
  try {
    f();
    ADD_FAILURE() << "no error for " << key;
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

// --- Oscillating force (seed 001 eq. 1-2) --------------------------------------------------------

OscillatingForceSettings oscillating() {
  OscillatingForceSettings s;
  s.amplitude = 1000.0;
  s.period = 8.0;
  s.waveNumber = 0.05;
  s.zMin = -2.0;
  s.zSwl = 1.0;
  s.zMax = 4.0;
  s.waves = 3.0;
  return s;
}

TEST(OscillatingForce, MatchesTheFormulaAtTheCentreOfMass) {
  Scene scene;
  const BodyId b = scene.add("unit_1", Vec3(3.2, 0.7, 0.3));
  const OscillatingForceSettings s = oscillating();
  OscillatingForce stage(scene.world, s, "unit_");
  std::vector<Vec3> force(1, Vec3::Zero()), torque(1, Vec3::Zero());
  const double t = 1.7;
  stage.apply(scene.world, t, force, torque);
  // Seed 001 eq. 1-2 written out in our axes (their z, y = our x, z).
  const double w = 2.0 * kPi / s.period;
  const double phi = (0.3 - s.zMin) / (s.zSwl - s.zMin);
  const Vec3 expected = s.amplitude * phi * Vec3(std::cos(w * t - s.waveNumber * 3.2), 0.0,
                                                 std::sin(w * t - s.waveNumber * 3.2));
  // A handful of floating-point operations: round-off of order 1e-15 relative.
  EXPECT_LE((force[b] - expected).norm(), 1e-12 * expected.norm());
  EXPECT_EQ(torque[b], Vec3::Zero()); // applied at the centre of mass
}

TEST(OscillatingForce, PhiIsZeroOutsideAndOneAtTheStillWaterLine) {
  Scene scene;
  scene.add("unit_1", Vec3::Zero());
  const OscillatingForceSettings s = oscillating();
  OscillatingForce stage(scene.world, s);
  EXPECT_EQ(stage.phi(s.zMin - 1.0), 0.0);
  EXPECT_EQ(stage.phi(s.zMin), 0.0);
  EXPECT_EQ(stage.phi(s.zSwl), 1.0);
  EXPECT_EQ(stage.phi(s.zMax), 0.0);
  EXPECT_EQ(stage.phi(s.zMax + 1.0), 0.0);
  // Linear on each side: half way is one half (exact in binary for these values up to round-off).
  EXPECT_NEAR(stage.phi(0.5 * (s.zMin + s.zSwl)), 0.5, 1e-15);
  EXPECT_NEAR(stage.phi(0.5 * (s.zSwl + s.zMax)), 0.5, 1e-15);
  // A body above z_max feels nothing.
  EXPECT_EQ(stage.force(0.0, s.zMax + 0.1, 1.0), Vec3::Zero());
}

TEST(OscillatingForce, StopsAfterNWaves) {
  Scene scene;
  scene.add("unit_1", Vec3::Zero());
  OscillatingForceSettings s = oscillating();
  OscillatingForce stage(scene.world, s);
  const double end = s.waves * s.period;
  EXPECT_GT(stage.force(0.0, 0.0, end - 1.0).norm(), 0.0);
  EXPECT_EQ(stage.force(0.0, 0.0, end + 1e-9), Vec3::Zero());
  EXPECT_EQ(stage.force(0.0, 0.0, 1e3), Vec3::Zero());
  std::vector<Vec3> force(1, Vec3::Zero()), torque(1, Vec3::Zero());
  stage.apply(scene.world, end + 0.5, force, torque);
  EXPECT_EQ(force[0], Vec3::Zero());
  // n = 0: for the whole run.
  s.waves = 0.0;
  OscillatingForce always(scene.world, s);
  EXPECT_GT(always.force(0.0, 0.0, 1e3 + 1.0).norm(), 0.0);
}

TEST(OscillatingForce, FreeBodyReturnsToItsVelocityAfterWholePeriods) {
  // No gravity, no contacts: v(t) = v0 + (1/m) int F dt. At fixed x and z the force integrates to
  // zero over a period. The body is made very heavy (F0 / m = 1e-6 m/s^2) so that it moves by
  // ~1e-6 m, changing phi and k x by a relative 1e-7 at most: below the 1e-6 asserted.
  WorldSettings ws;
  ws.gravity = Vec3::Zero();
  ws.sleep.enabled = false;
  const OscillatingForceSettings s = [] {
    OscillatingForceSettings o = oscillating();
    o.period = 2.0;
    o.waves = 0.0;
    return o;
  }();
  ws.timeStep = s.period / 4000.0;
  simulation::Material heavy;
  heavy.density = 1e9; // m = 1e9 kg for the 1 m^3 cube
  Scene scene(ws, heavy);
  const BodyId b = scene.add("unit", Vec3(0.0, 0.0, 0.0));
  auto stage = std::make_shared<OscillatingForce>(scene.world, s);
  scene.world.addLoadStage(stage);
  const double m = scene.world.bodies().info(b).mass;
  const double w = 2.0 * kPi / s.period;
  const double phi = stage->phi(0.0);
  // Velocity scale: the peak of v_z = F0 phi / (m w) (cos(k x) - cos(w t - k x)) is 2 F0 phi / (m w).
  const double scale = s.amplitude * phi / (m * w);
  // Half a period: v_z = 2 F0 phi / (m w) at x = 0 (the force acts, the test can fail). Trapezoidal
  // impulse of a sinusoid over half a period with 2000 steps: relative error ~ (pi/2000)^2 / 12 = 2e-7.
  scene.world.advanceTo(0.5 * s.period - 0.25 * ws.timeStep);
  EXPECT_NEAR(scene.world.bodies().velocity(b).z(), 2.0 * scale, 1e-5 * scale);
  for (int period = 1; period <= 2; ++period) {
    scene.world.advanceTo(period * s.period - 0.25 * ws.timeStep);
    EXPECT_NEAR(std::abs(scene.world.time() - period * s.period), 0.0, 1e-9);
    // Whole periods: the trapezoidal sum of a sinusoid over a period is exact to round-off.
    EXPECT_LE(scene.world.bodies().velocity(b).norm(), 1e-6 * scale) << "after " << period << " periods";
  }
}

TEST(OscillatingForce, WorkIsAccountedSoTheEnergyGuardLetsADrivenCubeSlide) {
  // A cube on a floor, mu = 0.5: the horizontal push (20 kN) beats friction (0.5 x 23.5 kN) while
  // the vertical part (below the 23.5 kN weight) never lifts it. The World counts the stage's work,
  // so its energy guard must not stop the run, and the energy balance E(t) - E(0) <= W(t) holds
  // (friction only dissipates).
  // A soft contact (1e7 Pa, 2.4 mm static overlap) allows a 10x longer stable step than concrete's
  // 1e9 Pa: the bookkeeping under test does not depend on the stiffness.
  simulation::Material m;
  m.frictionStatic = m.frictionDynamic = 0.5;
  m.penaltyModulus = 1e7;
  Scene scene({}, m);
  scene.world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), scene.material});
  const BodyId b = scene.add("unit", Vec3(0.0, 0.0, 0.5));
  OscillatingForceSettings s;
  s.amplitude = 20e3;
  s.period = 4.0;
  s.waveNumber = 0.1;
  s.zMin = -1.0;
  s.zSwl = 0.5;
  s.zMax = 2.0;
  scene.world.addLoadStage(std::make_shared<OscillatingForce>(scene.world, s));
  scene.world.step();
  const double e0 = scene.world.mechanicalEnergy() + scene.world.contactEnergy() - scene.world.externalWork();
  double travel = 0.0;
  double worstGain = -1e300;
  const double x0 = scene.world.bodies().position(b).x();
  for (int k = 1; k <= 200; ++k) {
    ASSERT_NO_THROW(scene.world.advanceTo(0.1 * k)) << "t = " << scene.world.time();
    travel = std::max(travel, std::abs(scene.world.bodies().position(b).x() - x0));
    const double net = scene.world.mechanicalEnergy() + scene.world.contactEnergy() - scene.world.externalWork();
    worstGain = std::max(worstGain, net - e0);
  }
  EXPECT_GT(travel, 0.5) << "the cube should slide back and forth";
  EXPECT_GT(scene.world.externalWork(), 0.0);
  // E - W may not grow beyond integration noise: 1 % of the weight x Dn (235 J), far below the work
  // of ~10 kJ per stroke that would show if the stage's work were not counted.
  const double weightDn = scene.world.bodies().info(b).mass * 9.81 * 1.0;
  EXPECT_LE(worstGain, 0.01 * weightDn);
}

// --- Exposure -------------------------------------------------------------------------------------

/// A 1:2 slope: theta = atan(1/2).
const double kTheta = std::atan(0.5);
const Vec3 kNormal(-std::sin(kTheta), 0.0, std::cos(kTheta));
const Vec3 kUp(std::cos(kTheta), 0.0, std::sin(kTheta)); // u = v x n with v = e_y
/// A cube lying flat on the slope: its +z face looks along n, its edges along u and e_y.
const Quat kOnSlope(Eigen::AngleAxisd(-kTheta, Vec3::UnitY()));

/// Lattice points (i + 1/2) h in [lo, hi], or -1 if one is within 1e-6 h of an end (ambiguous).
int pointsIn(double lo, double hi, double h) {
  int count = 0;
  for (int i = static_cast<int>(std::floor(lo / h)) - 2; i <= static_cast<int>(std::ceil(hi / h)) + 2; ++i) {
    const double p = (i + 0.5) * h;
    if (std::abs(p - lo) < 1e-6 * h || std::abs(p - hi) < 1e-6 * h) {
      return -1;
    }
    count += (p > lo && p < hi) ? 1 : 0;
  }
  return count;
}

TEST(MeshRayCaster, FindsTheEntryPointOfTheWholeLine) {
  const MeshRayCaster caster(test::makeBox(1.0, 1.0, 1.0));
  EXPECT_NEAR(caster.firstHit(Vec3(0.3, 0.4, 5.0), Vec3(0, 0, -1)), 4.0, 1e-12);
  // Through the diagonal edge shared by the top face's two triangles, and through a corner.
  EXPECT_NEAR(caster.firstHit(Vec3(0.5, 0.5, 5.0), Vec3(0, 0, -1)), 4.0, 1e-12);
  EXPECT_NEAR(caster.firstHit(Vec3(1.0, 1.0, 5.0), Vec3(0, 0, -1)), 4.0, 1e-12);
  // From inside: the line entered behind the origin (negative t).
  EXPECT_NEAR(caster.firstHit(Vec3(0.3, 0.4, 0.5), Vec3(0, 0, -1)), -0.5, 1e-12);
  // An oblique line and a miss.
  const Vec3 d = Vec3(1.0, 0.0, -1.0).normalized();
  EXPECT_NEAR(caster.firstHit(Vec3(-0.5, 0.5, 2.0), d), std::sqrt(2.0), 1e-12); // enters the top at (0.5, 0.5, 1)
  EXPECT_TRUE(std::isinf(caster.firstHit(Vec3(2.0, 2.0, 5.0), Vec3(0, 0, -1))));
}

TEST(Exposure, ACubeFlatOnTheSlopeShowsOneFaceFromTheSea) {
  Scene scene;
  const Vec3 c(6.0, 0.013, 3.0);
  const BodyId a = scene.add("unit_a", c, kOnSlope);
  Exposure exposure;
  ExposureQuery q;
  q.slopeNormal = kNormal;
  q.spacing = 0.05;
  const std::vector<BodyId> loaded{a};
  const auto e = exposure.compute(scene.world, loaded, q);
  // The face is the square [cu -/+ 1/2] x [cv -/+ 1/2] on the ray grid: the count is exact.
  const int nu = pointsIn(c.dot(kUp) - 0.5, c.dot(kUp) + 0.5, q.spacing);
  const int nv = pointsIn(c.y() - 0.5, c.y() + 0.5, q.spacing);
  ASSERT_GT(nu, 0);
  ASSERT_GT(nv, 0);
  EXPECT_EQ(e[0].hits, nu * nv);
  // And within the lattice bound of an aligned square: (a/h - 1)^2 <= hits <= (a/h + 1)^2.
  EXPECT_GE(e[0].hits, 19 * 19);
  EXPECT_LE(e[0].hits, 21 * 21);
  // Mean hit point: on the face (exactly, along n) and within h/2 of its centre along u and v (the
  // mean of a symmetric-but-for-one-row lattice).
  const Vec3 centre = c + 0.5 * kNormal;
  EXPECT_NEAR((e[0].meanPoint - centre).dot(kNormal), 0.0, 1e-9);
  EXPECT_LE(std::abs((e[0].meanPoint - centre).dot(kUp)), 0.5 * q.spacing);
  EXPECT_LE(std::abs((e[0].meanPoint - centre).y()), 0.5 * q.spacing);
  EXPECT_EQ(static_cast<int>(exposure.lastStatistics().hits), e[0].hits);
  // From behind the opposite face shows, the same count.
  q.side = ExposureSide::FromBehind;
  const auto back = exposure.compute(scene.world, loaded, q);
  EXPECT_EQ(back[0].hits, nu * nv);
  EXPECT_NEAR((back[0].meanPoint - (c - 0.5 * kNormal)).dot(kNormal), 0.0, 1e-9);
}

TEST(Exposure, AnyOrientationShowsTheCubesProjectedAreaWithinTheLatticeBound) {
  // Projected area of a unit cube along a unit direction d (body frame): |d_x| + |d_y| + |d_z|.
  // Lattice count of a convex region K with perimeter P at spacing h: the union of the counted
  // cells differs from K only within h / sqrt(2) of the boundary, so
  // |hits h^2 - A| <= sqrt(2) P h + pi h^2 / 2; the silhouette of a cube has at most 6 edges, each
  // at most sqrt(2) long (a face diagonal): P <= 6 sqrt(2).
  Scene scene;
  const Quat q0(test::someRotation());
  const BodyId a = scene.add("unit_a", Vec3(4.3, -1.2, 2.0), q0);
  Exposure exposure;
  ExposureQuery q;
  q.slopeNormal = kNormal;
  q.spacing = 0.02;
  const auto e = exposure.compute(scene.world, std::vector<BodyId>{a}, q);
  const Vec3 d = q0.conjugate() * kNormal;
  const double area = d.cwiseAbs().sum();
  const double h = q.spacing;
  const double bound = std::sqrt(2.0) * 6.0 * std::sqrt(2.0) * h + kPi * h * h / 2.0;
  EXPECT_NEAR(e[0].area(h), area, bound);
}

TEST(Exposure, ACubeBehindAnotherIsShadowedAndTheOrderReversesFromBehind) {
  Scene scene;
  const Vec3 c(6.0, 0.013, 3.0);
  const BodyId front = scene.add("unit_front", c, kOnSlope);
  const BodyId back = scene.add("unit_back", c - 2.0 * kNormal, kOnSlope);
  Exposure exposure;
  ExposureQuery q;
  q.slopeNormal = kNormal;
  q.spacing = 0.05;
  const std::vector<BodyId> loaded{front, back};
  const auto sea = exposure.compute(scene.world, loaded, q);
  EXPECT_GT(sea[0].hits, 19 * 19);
  EXPECT_EQ(sea[1].hits, 0);
  q.side = ExposureSide::FromBehind;
  const auto behind = exposure.compute(scene.world, loaded, q);
  EXPECT_EQ(behind[0].hits, 0);
  EXPECT_EQ(behind[1].hits, sea[0].hits);
}

TEST(Exposure, FixedBodiesBlockButReceiveNothing) {
  Scene scene;
  const Vec3 c(6.0, 0.013, 3.0);
  const BodyId unit = scene.add("unit", c, kOnSlope);
  const BodyId rock = scene.add("rock", c + 2.0 * kNormal, kOnSlope, /*fixed=*/true);
  Exposure exposure;
  ExposureQuery q;
  q.slopeNormal = kNormal;
  q.spacing = 0.05;
  const std::vector<BodyId> loaded{unit, rock};
  const auto sea = exposure.compute(scene.world, loaded, q);
  EXPECT_EQ(sea[0].hits, 0); // behind the fixed rock
  EXPECT_EQ(sea[1].hits, 0); // fixed: only blocks
  q.side = ExposureSide::FromBehind;
  const auto behind = exposure.compute(scene.world, loaded, q);
  EXPECT_GT(behind[0].hits, 19 * 19);
  EXPECT_EQ(behind[1].hits, 0);
  // A movable body that is not loaded blocks too.
  Scene other;
  const BodyId u2 = other.add("unit", c, kOnSlope);
  other.add("other", c + 2.0 * kNormal, kOnSlope);
  q.side = ExposureSide::FromSea;
  EXPECT_EQ(exposure.compute(other.world, std::vector<BodyId>{u2}, q)[0].hits, 0);
}

TEST(Exposure, SameResultForOneAndTwoThreads) {
  // A random pile of 60 cubes over the slope, overlapping in projection.
  Scene scene;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<BodyId> loaded;
  for (int k = 0; k < 60; ++k) {
    const Vec3 p = (k % 10) * 1.1 * kUp + (k / 10) * 1.1 * Vec3::UnitY() + (0.5 + 2.0 * U(rng)) * kNormal +
                   0.4 * (U(rng) - 0.5) * kUp;
    const Quat q(Eigen::AngleAxisd(2.0 * kPi * U(rng), Vec3(U(rng), U(rng), U(rng) + 0.1).normalized()));
    loaded.push_back(scene.add("unit_" + std::to_string(k), p, q, k % 7 == 0));
  }
  Exposure exposure;
  ExposureQuery q;
  q.slopeNormal = kNormal;
  q.spacing = 0.1;
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto one = exposure.compute(scene.world, loaded, q);
  omp_set_num_threads(2);
  const auto two = exposure.compute(scene.world, loaded, q);
  omp_set_num_threads(saved);
  int total = 0;
  for (std::size_t k = 0; k < loaded.size(); ++k) {
    EXPECT_EQ(one[k].hits, two[k].hits);
    EXPECT_EQ(one[k].meanPoint, two[k].meanPoint); // bit for bit
    total += one[k].hits;
  }
  EXPECT_GT(total, 0);
}

// --- Shallow-wave force (seed 003 eq. 2) ---------------------------------------------------------

ShallowWaveForceSettings shallow() {
  ShallowWaveForceSettings s;
  s.amplitude = 1e4;
  s.angularFrequency = kPi;
  s.slopeAngle = kTheta;
  s.toeX = 0.0;
  s.depthAtToe = 10.0;
  s.raySpacing = 0.05;
  s.exposureInterval = 0.5;
  return s;
}

TEST(ShallowWaveForce, PhaseIsOmegaTimesTheShallowWaterTravelTime) {
  Scene scene;
  scene.add("unit", Vec3::Zero());
  const ShallowWaveForceSettings s = shallow();
  const ShallowWaveForce stage(scene.world, s);
  const double g = 9.81, w = s.angularFrequency, d0 = s.depthAtToe, tn = std::tan(s.slopeAngle);
  // At the toe the spatial phase is zero: exactly w t.
  EXPECT_EQ(stage.phase(0.0, 1.3), w * 1.3);
  for (const double x : {-6.0, 3.0, 11.0, 0.9 * d0 / tn}) {
    // Seed 003 eq. 2 as printed (their z = our s = x - toeX).
    const double eq2 = w * 1.3 + 2.0 * w / (std::sqrt(g) * tn) * (std::sqrt(d0 - x * tn) - std::sqrt(d0));
    EXPECT_NEAR(stage.phase(x, 1.3), eq2, 1e-12 * std::abs(eq2));
    // Its meaning: w (t - tau), tau the travel time from the toe at celerity c = sqrt(g d),
    // d = d0 - s tan th. Simpson's rule with 2000 intervals on a smooth integrand (d >= d0/10):
    // relative error ~1e-12; asserted to 1e-9.
    const int n = 2000;
    const double hs = x / n;
    double tau = 0.0;
    for (int k = 0; k <= n; ++k) {
      const double f = 1.0 / std::sqrt(g * (d0 - k * hs * tn));
      tau += f * ((k == 0 || k == n) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0));
    }
    tau *= hs / 3.0;
    EXPECT_NEAR(stage.phase(x, 1.3), w * (1.3 - tau), 1e-9 * std::max(1.0, w * std::abs(tau)));
  }
  // Above the shore line (d < 0) there is no wave: F = 0 at every time.
  const double dry = 1.01 * d0 / tn;
  EXPECT_FALSE(stage.wet(dry));
  for (const double t : {0.0, 0.3, 0.7, 1.1}) {
    EXPECT_EQ(stage.forceMagnitude(dry, t), 0.0);
  }
  EXPECT_NEAR(stage.forceMagnitude(0.0, 0.5), s.amplitude, 1e-12 * s.amplitude); // sin(pi/2)
}

/// Two cubes flat on the slope, `back` right behind `front` along -n.
struct Pair {
  Scene scene;
  BodyId front, back;
  Vec3 c{6.0, 0.013, 3.0};
  explicit Pair(const Vec3& backOffset = Vec3::Zero()) {
    front = scene.add("unit_front", c, kOnSlope);
    back = scene.add("unit_back", c - 2.0 * kNormal + backOffset, kOnSlope);
  }
};

/// A time >= 0 at which the phase at s is `target` (mod 2 pi).
double timeForPhase(const ShallowWaveForce& stage, double s, double target, double w) {
  double t = (target - stage.phase(s, 0.0)) / w;
  while (t < 0.0) {
    t += 2.0 * kPi / w;
  }
  return t;
}

TEST(ShallowWaveForce, OnshoreForcePushesTheExposedUnitOnly) {
  Pair p;
  const ShallowWaveForceSettings s = shallow();
  ShallowWaveForce stage(p.scene.world, s, "unit_");
  const auto& bodies = p.scene.world.bodies();
  const double sFront = bodies.position(p.front).x() - s.toeX;
  const double sBack = bodies.position(p.back).x() - s.toeX;
  const double t = timeForPhase(stage, sFront, 0.5 * kPi, s.angularFrequency);
  ASSERT_GT(stage.forceMagnitude(sBack, t), 0.0); // the back unit is pushed too, if it were exposed
  std::vector<Vec3> force(2, Vec3::Zero()), torque(2, Vec3::Zero());
  stage.apply(p.scene.world, t, force, torque);
  const double f = stage.forceMagnitude(sFront, t);
  ASSERT_NEAR(f, s.amplitude, 1e-9 * s.amplitude);
  const double h = stage.raySpacing();
  const double area = stage.held()[0].seaHits * h * h;
  // The face (1 m^2) within the aligned-square lattice bound.
  EXPECT_NEAR(area, 1.0, 2.0 * h + h * h);
  const double share = std::min(1.0, area);
  EXPECT_NEAR(force[p.front].x(), f * share, 1e-12 * s.amplitude);
  EXPECT_GT(force[p.front].x(), 0.0); // onshore
  EXPECT_EQ(force[p.front].y(), 0.0);
  EXPECT_EQ(force[p.front].z(), 0.0);
  // At the mean hit point, (1/2) n from the centre within h/2 along u and v: torque
  // (1/2) n x (F e_x) = (0, F cos th / 2, 0), up to F h / sqrt(2) from the arm's in-plane error.
  const Vec3 expectedTorque(0.0, 0.5 * force[p.front].x() * std::cos(kTheta), 0.0);
  EXPECT_LE((torque[p.front] - expectedTorque).norm(), force[p.front].x() * h);
  // Shadowed: nothing.
  EXPECT_EQ(force[p.back], Vec3::Zero());
  EXPECT_EQ(torque[p.back], Vec3::Zero());
}

TEST(ShallowWaveForce, SeawardForceActsOnlyOnUnitsExposedFromBehind) {
  Pair p;
  const ShallowWaveForceSettings s = shallow();
  ShallowWaveForce stage(p.scene.world, s, "unit_");
  const auto& bodies = p.scene.world.bodies();
  const double sFront = bodies.position(p.front).x() - s.toeX;
  const double sBack = bodies.position(p.back).x() - s.toeX;
  const double t = timeForPhase(stage, sBack, -0.5 * kPi, s.angularFrequency);
  ASSERT_LT(stage.forceMagnitude(sFront, t), 0.0);
  std::vector<Vec3> force(2, Vec3::Zero()), torque(2, Vec3::Zero());
  stage.apply(p.scene.world, t, force, torque);
  EXPECT_EQ(force[p.front], Vec3::Zero()); // its back is covered by the other unit
  const double h = stage.raySpacing();
  const double share = std::min(1.0, stage.held()[1].backHits * h * h);
  EXPECT_GT(share, 0.9);
  EXPECT_NEAR(force[p.back].x(), stage.forceMagnitude(sBack, t) * share, 1e-12 * s.amplitude);
  EXPECT_LT(force[p.back].x(), 0.0); // seaward
  // Arm -(1/2) n: torque -(1/2) n x (F e_x) = (0, -F cos th / 2, 0).
  const Vec3 expectedTorque(0.0, -0.5 * force[p.back].x() * std::cos(kTheta), 0.0);
  EXPECT_LE((torque[p.back] - expectedTorque).norm(), std::abs(force[p.back].x()) * h);
}

TEST(ShallowWaveForce, ForceScalesWithExposedAreaCappedAtDnSquared) {
  // The back unit moved up the slope by half a side: half of its face shows from the sea.
  Pair p(0.5 * kUp);
  // A third unit turned 45 degrees about the trunk axis: projected area sqrt(2) Dn^2 > Dn^2.
  const BodyId turned = p.scene.add("unit_turned", p.c + 5.0 * Vec3::UnitY(),
                                    kOnSlope * Quat(Eigen::AngleAxisd(0.25 * kPi, Vec3::UnitY())));
  const ShallowWaveForceSettings s = shallow();
  ShallowWaveForce stage(p.scene.world, s, "unit_");
  const auto& bodies = p.scene.world.bodies();
  const double t = timeForPhase(stage, bodies.position(p.front).x(), 0.5 * kPi, s.angularFrequency);
  std::vector<Vec3> force(3, Vec3::Zero()), torque(3, Vec3::Zero());
  stage.apply(p.scene.world, t, force, torque);
  const double h = stage.raySpacing();
  // Half face: (a/2h +- 1)(a/h +- 1) lattice points of an aligned 0.5 x 1 rectangle.
  const double half = stage.held()[1].seaHits * h * h;
  EXPECT_GE(half, 9.0 * 19.0 * h * h);
  EXPECT_LE(half, 11.0 * 21.0 * h * h);
  const double fBack = stage.forceMagnitude(bodies.position(p.back).x(), t);
  EXPECT_NEAR(force[p.back].x(), fBack * half, 1e-12 * s.amplitude);
  // Capped: more than Dn^2 exposed takes the full force, not more.
  EXPECT_GT(stage.held()[2].seaHits * h * h, 1.3);
  const double fTurned = stage.forceMagnitude(bodies.position(turned).x(), t);
  ASSERT_GT(fTurned, 0.0);
  EXPECT_NEAR(force[turned].x(), fTurned, 1e-12 * s.amplitude);
}

TEST(ShallowWaveForce, HoldsExposureBetweenUpdatesAndRestoresItBitForBit) {
  Pair p;
  ShallowWaveForceSettings s = shallow();
  ShallowWaveForce stage(p.scene.world, s, "unit_");
  std::vector<Vec3> force(2, Vec3::Zero()), torque(2, Vec3::Zero());
  stage.apply(p.scene.world, 0.1, force, torque);
  EXPECT_EQ(stage.lastExposureTime(), 0.1);
  const auto state = stage.saveState();
  // Move the front unit out of the way: the held exposure (front exposed, back shadowed) stays
  // until the interval has passed.
  auto& bodies = p.scene.world.bodies();
  bodies.setPosition(p.front, p.c + 10.0 * Vec3::UnitY());
  stage.apply(p.scene.world, 0.5, force, torque);
  EXPECT_EQ(stage.lastExposureTime(), 0.1);
  EXPECT_EQ(stage.held()[1].seaHits, 0);
  // A stage restored from the saved state gives the same loads, bit for bit, without casting.
  ShallowWaveForce restored(p.scene.world, s, "unit_");
  restored.restoreState(state);
  for (const double t : {0.3, 0.55}) {
    std::vector<Vec3> f1(2, Vec3::Zero()), t1(2, Vec3::Zero()), f2(2, Vec3::Zero()), t2(2, Vec3::Zero());
    stage.apply(p.scene.world, t, f1, t1);
    restored.apply(p.scene.world, t, f2, t2);
    EXPECT_EQ(f1, f2);
    EXPECT_EQ(t1, t2);
  }
  // After the interval: recomputed, the back unit is now exposed.
  stage.apply(p.scene.world, 0.61, force, torque);
  EXPECT_EQ(stage.lastExposureTime(), 0.61);
  EXPECT_GT(stage.held()[1].seaHits, 19 * 19);
  // A state from another scene is refused.
  expectInputError([&] { restored.restoreState(std::vector<double>(7, 1.0)); }, "shallow_wave");
}

// --- Bad settings ----------------------------------------------------------------------------------

TEST(AnalyticForces, BadSettingsNameTheKey) {
  Scene scene;
  scene.add("unit_1", Vec3::Zero());
  auto osc = [&](const std::function<void(OscillatingForceSettings&)>& change, const std::string& key) {
    OscillatingForceSettings s = oscillating();
    change(s);
    expectInputError([&] { const OscillatingForce stage(scene.world, s); }, key);
  };
  osc([](auto& s) { s.period = 0.0; }, "hydro.oscillating.period");
  osc([](auto& s) { s.amplitude = std::nan(""); }, "hydro.oscillating.amplitude");
  osc([](auto& s) { s.waveNumber = INFINITY; }, "hydro.oscillating.wave_number");
  osc([](auto& s) { s.zMin = s.zSwl; }, "hydro.oscillating.z_min");
  osc([](auto& s) { s.zMax = s.zSwl - 0.1; }, "hydro.oscillating.z_max");
  osc([](auto& s) { s.zSwl = std::nan(""); }, "hydro.oscillating.z_swl");
  osc([](auto& s) { s.waves = -1.0; }, "hydro.oscillating.waves");
  expectInputError([&] { const OscillatingForce stage(scene.world, oscillating(), "armour_"); }, "hydro.bodies");

  auto sw = [&](const std::function<void(ShallowWaveForceSettings&)>& change, const std::string& key) {
    ShallowWaveForceSettings s = shallow();
    change(s);
    expectInputError([&] { const ShallowWaveForce stage(scene.world, s); }, key);
  };
  // The slope is read as angle_deg (or tan, cot): the error names the key the reader accepts.
  sw([](auto& s) { s.slopeAngle = 26.6; }, "hydro.shallow_wave.angle_deg"); // degrees by mistake
  sw([](auto& s) { s.slopeAngle = 0.0; }, "hydro.shallow_wave.angle_deg");
  sw([](auto& s) { s.depthAtToe = 0.0; }, "hydro.shallow_wave.depth_at_toe");
  sw([](auto& s) { s.angularFrequency = -1.0; }, "hydro.shallow_wave.angular_frequency");
  sw([](auto& s) { s.toeX = std::nan(""); }, "hydro.shallow_wave.toe_x");
  sw([](auto& s) { s.amplitude = INFINITY; }, "hydro.shallow_wave.amplitude");
  sw([](auto& s) { s.raySpacing = -0.1; }, "hydro.shallow_wave.ray_spacing");
  sw([](auto& s) { s.exposureInterval = -1.0; }, "hydro.shallow_wave.exposure_interval");

  Exposure exposure;
  ExposureQuery q;
  q.spacing = 0.0;
  expectInputError([&] { (void)exposure.compute(scene.world, std::vector<BodyId>{0}, q, "my.key"); }, "my.key");
}

} // namespace
