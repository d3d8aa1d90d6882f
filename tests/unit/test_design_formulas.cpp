// SPDX-License-Identifier: GPL-3.0-or-later
// The design formulas of analysis/DesignFormulas (docs/theory.md, "Design formulas"): Hudson, van
// der Meer (rock, cubes, tetrapods, Accropode), Melby and Kobayashi, and the counted damage of a
// simulated pack. Expected values are the published formulas evaluated by hand (the arithmetic is
// in the comments); tolerances are round-off unless said otherwise.
#include "analysis/DesignFormulas.hpp"
#include "core/Error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

using namespace armour::analysis;
using armour::core::InputError;

// Round-off of a handful of pow/cbrt calls: a few ulps, relative.
constexpr double kRoundOff = 1e-12;

TEST(DesignFormulas, HudsonRockTextbookCase) {
  // K_D = 4 (rock, non-breaking), 1:2 slope: Ns = (4 x 2)^(1/3) = 2 exactly.
  EXPECT_NEAR(hudsonStabilityNumber(4.0, 2.0), 2.0, kRoundOff);
  // Hs = 4 m on rock of 2650 kg/m^3 in sea water of 1025 kg/m^3: Delta = 1.585366, and Hudson's
  // weight form W = rho_r Hs^3 / (K_D Delta^3 cot alpha) (SPM 1984 eq. 7-116 with Hs) must equal
  // rho_r Dn^3 with the Dn of the stability-number form: the two published forms agree.
  const double delta = relativeDensity(2650.0, 1025.0);
  EXPECT_NEAR(delta, 1625.0 / 1025.0, kRoundOff);
  const double dn = hudsonNominalDiameter(4.0, delta, 4.0, 2.0);
  EXPECT_NEAR(dn, 4.0 / (delta * 2.0), kRoundOff); // 1.26154 m
  const double massSpm = 2650.0 * 64.0 / (4.0 * delta * delta * delta * 2.0);
  EXPECT_NEAR(2650.0 * dn * dn * dn / massSpm, 1.0, kRoundOff);
  EXPECT_NEAR(massSpm, 5320.4, 0.1); // kg: 2650 x 1.26154^3, to the 0.1 kg printed
}

TEST(DesignFormulas, HudsonInverseRoundTrips) {
  for (double kd : {2.0, 4.0, 7.0, 12.0, 16.0, 31.8})
    for (double cot : {1.33, 1.5, 2.0, 3.0, 4.0}) {
      const double ns = hudsonStabilityNumber(kd, cot);
      EXPECT_NEAR(hudsonKd(ns, cot) / kd, 1.0, kRoundOff) << kd << " " << cot;
      // Hs = Ns Delta Dn: the diameter Hudson asks for makes the storm's Ns exactly Hudson's.
      const double dn = hudsonNominalDiameter(3.0, 1.34, kd, cot);
      EXPECT_NEAR(stabilityNumber(3.0, 1.34, dn) / ns, 1.0, kRoundOff);
    }
}

TEST(DesignFormulas, HudsonTableCoversTheShapeLibrary) {
  for (const char* unit :
       {"rock", "voronoi-rock", "cube", "antifer", "tetrapod", "dolos", "accropode", "coreloc", "xbloc", "cubipod"}) {
    const HudsonCoefficient& c = hudsonCoefficient(unit);
    EXPECT_GT(c.kdBreaking, 0.0) << unit;
    // Breaking waves are the harder load: their K_D is never the larger one.
    EXPECT_LE(c.kdBreaking, c.kdNonBreaking) << unit;
    EXPECT_LE(c.cotMin, c.cotMax) << unit;
    EXPECT_FALSE(c.source.empty()) << unit;
  }
  EXPECT_DOUBLE_EQ(hudsonCoefficient("coreloc").kdBreaking, 16.0);   // CEM Table VI-5-29
  EXPECT_DOUBLE_EQ(hudsonCoefficient("accropode").kdBreaking, 12.0); // CEM Table VI-5-29
  EXPECT_DOUBLE_EQ(hudsonCoefficient("tetrapod").kdNonBreaking, 8.0);
  EXPECT_THROW((void)hudsonCoefficient("vcross"), InputError);
}

TEST(DesignFormulas, VanDerMeerRockHandValues) {
  // Plunging: P = 0.4, 1:3, s_om = 0.03, N = 3000, S = 2 (start of damage).
  //   xi_m = (1/3) / sqrt(0.03) = 1.92450; xi_mc = (6.2 x 0.4^0.31 x sqrt(1/3))^(1/0.9) = 3.00815
  //   Ns = 6.2 x 0.4^0.18 x (2 / sqrt(3000))^0.2 x 1.92450^-0.5 = 1.954777
  RockStorm plunging{0.0, 0.03, 3.0, 0.4, 3000.0};
  EXPECT_NEAR(vanDerMeerTransition(0.4, 3.0), 3.0081509, 1e-6);
  EXPECT_NEAR(vanDerMeerRockStabilityNumber(2.0, plunging), 1.9547774, 1e-6);
  // Surging: P = 0.4, 1:1.5, s_om = 0.02: xi_m = 4.71405 > xi_mc = 4.42118;
  //   Ns = 1.0 x 0.4^-0.13 x (2 / sqrt(3000))^0.2 x sqrt(1.5) x 4.71405^0.4 = 1.323211
  RockStorm surging{0.0, 0.02, 1.5, 0.4, 3000.0};
  EXPECT_NEAR(vanDerMeerRockStabilityNumber(2.0, surging), 1.3232113, 1e-6);
  plunging.stabilityNumber = 1.9547774;
  const RockDamage d = vanDerMeerRockDamage(plunging);
  EXPECT_TRUE(d.plunging);
  EXPECT_NEAR(d.damage, 2.0, 2e-6); // 5 x the 1e-7 relative rounding of the Ns typed in, plus margin
  surging.stabilityNumber = 1.3232113;
  EXPECT_FALSE(vanDerMeerRockDamage(surging).plunging);
}

TEST(DesignFormulas, VanDerMeerRockRoundTripsAndIsContinuousAtTheTransition) {
  for (double cot : {1.5, 2.0, 3.0, 4.0, 6.0})
    for (double s : {0.005, 0.01, 0.03, 0.06})
      for (double S : {1.0, 2.0, 8.0, 17.0}) {
        RockStorm storm{0.0, s, cot, 0.5, 2000.0};
        storm.stabilityNumber = vanDerMeerRockStabilityNumber(S, storm);
        EXPECT_NEAR(vanDerMeerRockDamage(storm).damage / S, 1.0, 1e-11);
      }
  // xi_mc is where the two formulas give the same Ns: just below and above it they agree to the
  // change of xi over the step (Ns ~ xi^-0.5 or xi^P: relative change ~ 1e-7 for a 1e-7 step).
  const double P = 0.4, cot = 2.0;
  const double xic = vanDerMeerTransition(P, cot);
  const auto steepnessAt = [&](double xi) { return std::pow(1.0 / cot / xi, 2.0); };
  RockStorm below{0.0, steepnessAt(xic * (1.0 - 1e-7)), cot, P, 1000.0};
  RockStorm above{0.0, steepnessAt(xic * (1.0 + 1e-7)), cot, P, 1000.0};
  const double nsBelow = vanDerMeerRockStabilityNumber(3.0, below);
  const double nsAbove = vanDerMeerRockStabilityNumber(3.0, above);
  EXPECT_NEAR(nsAbove / nsBelow, 1.0, 1e-6);
  // Damage grows as Ns^5 and as sqrt(N).
  RockStorm a{2.0, 0.03, 2.0, 0.4, 1000.0}, b = a;
  b.stabilityNumber = 4.0;
  EXPECT_NEAR(vanDerMeerRockDamage(b).damage / vanDerMeerRockDamage(a).damage, 32.0, 32.0 * kRoundOff);
  b = a;
  b.waves = 4000.0;
  EXPECT_NEAR(vanDerMeerRockDamage(b).damage / vanDerMeerRockDamage(a).damage, 2.0, 2.0 * kRoundOff);
}

TEST(DesignFormulas, VanDerMeerRockRefusesOutsideItsData) {
  RockStorm storm{2.0, 0.03, 2.0, 0.4, 1000.0};
  EXPECT_NO_THROW((void)vanDerMeerRockDamage(storm));
  auto bad = storm;
  bad.steepness = 0.08; // steeper than any wave tested
  EXPECT_THROW((void)vanDerMeerRockDamage(bad), InputError);
  bad = storm;
  bad.permeability = 0.8;
  EXPECT_THROW((void)vanDerMeerRockDamage(bad), InputError);
  bad = storm;
  bad.waves = 10000.0;
  EXPECT_THROW((void)vanDerMeerRockDamage(bad), InputError);
  bad = storm;
  bad.cotAlpha = 1.2;
  EXPECT_THROW((void)vanDerMeerRockDamage(bad), InputError);
  try {
    bad = storm;
    bad.steepness = 0.08;
    (void)vanDerMeerRockDamage(bad);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s_om = 0.08"), std::string::npos) << e.what();
  }
}

TEST(DesignFormulas, VanDerMeerConcreteUnits) {
  // Cubes, Nod = 1, N = 1000, s_om = 0.03: (6.7 / 1000^0.3 + 1) x 0.03^-0.1 = 2.617739.
  EXPECT_NEAR(vanDerMeerCubesStabilityNumber(1.0, 1000.0, 0.03), 2.6177388, 1e-6);
  // Tetrapods, Nod = 0.5: (3.75 sqrt(0.5) / 1000^0.25 + 0.85) x 0.03^-0.2 = 2.664743.
  EXPECT_NEAR(vanDerMeerTetrapodsStabilityNumber(0.5, 1000.0, 0.03), 2.6647425, 1e-6);
  for (double nod : {0.1, 0.5, 1.0, 4.0})
    for (double n : {100.0, 1000.0, 5000.0})
      for (double s : {0.01, 0.04}) {
        EXPECT_NEAR(vanDerMeerCubesNod(vanDerMeerCubesStabilityNumber(nod, n, s), n, s) / nod, 1.0, 1e-11);
        EXPECT_NEAR(vanDerMeerTetrapodsNod(vanDerMeerTetrapodsStabilityNumber(nod, n, s), n, s) / nod, 1.0, 1e-11);
      }
  // Below the no-damage stability number (Nod = 0: 1.0 s^-0.1 for cubes) nothing moves.
  EXPECT_EQ(vanDerMeerCubesNod(0.9 * std::pow(0.03, -0.1), 1000.0, 0.03), 0.0);
  EXPECT_EQ(vanDerMeerTetrapodsNod(0.8 * std::pow(0.03, -0.2), 1000.0, 0.03), 0.0);
  // Only the 1:1.5 slope was tested.
  EXPECT_THROW((void)vanDerMeerCubesNod(2.0, 1000.0, 0.03, 2.0), InputError);
  EXPECT_THROW((void)vanDerMeerTetrapodsNod(2.0, 1000.0, 0.1), InputError);
  EXPECT_EQ(vanDerMeerAccropode(3.5, 0.03).verdict, "no damage");
  EXPECT_EQ(vanDerMeerAccropode(3.9, 0.03).verdict, "start of damage");
  EXPECT_EQ(vanDerMeerAccropode(4.2, 0.03).verdict, "failure");
  EXPECT_THROW((void)vanDerMeerAccropode(3.5, 0.03, 2.0), InputError);
}

TEST(DesignFormulas, MelbyKobayashiProgression) {
  // Constant conditions: S = 0.025 Ns^5 (t / Tm)^0.25. Ns = 2, Tm = 8 s, one hour:
  // 0.025 x 32 x 450^0.25 = 3.6846.
  const std::vector<double> xi{3.0};
  const ProgressedDamage one = melbyKobayashiDamage({{3600.0, 2.0, 8.0}}, 2.0, xi);
  EXPECT_NEAR(one.damage, 0.025 * 32.0 * std::pow(450.0, 0.25), kRoundOff);
  EXPECT_NEAR(one.damage, 3.6846, 1e-4);
  EXPECT_NEAR(one.standardDeviation, 0.5 * std::pow(one.damage, 0.65), kRoundOff);
  // The same storm in two stages gives the same damage: the law is cumulative in t^0.25.
  const ProgressedDamage two = melbyKobayashiDamage({{1000.0, 2.0, 8.0}, {2600.0, 2.0, 8.0}}, 2.0, {3.0, 3.0});
  EXPECT_NEAR(two.damage / one.damage, 1.0, kRoundOff);
  ASSERT_EQ(two.afterStage.size(), 2u);
  EXPECT_LT(two.afterStage[0], two.afterStage[1]);
  // The spectral form uses a = 0.022.
  const ProgressedDamage peak = melbyKobayashiDamage({{3600.0, 2.0, 8.0}}, 2.0, xi, MelbyKobayashiPeriod::peak);
  EXPECT_NEAR(peak.damage / one.damage, 0.022 / 0.025, kRoundOff);
  // Outside the tests: an Iribarren number of 6 (surging on a steep slope) is refused.
  EXPECT_THROW((void)melbyKobayashiDamage({{3600.0, 2.0, 8.0}}, 2.0, {6.0}), InputError);
  EXPECT_THROW((void)melbyKobayashiDamage({{3600.0, 2.0, 8.0}}, 5.0, xi), InputError);
}

TEST(DesignFormulas, CountedDamageFromDisplacedUnits) {
  // 3 units of Dn = 2 m displaced over a 20 m wide trunk: Nod = 3 x 2 / 20 = 0.3; with a layer
  // porosity of 0.4 the hole's bulk volume is 3 x 8 / 0.6 m^3 = 40 m^3, A = 2 m^2, S = A / Dn^2 = 0.5.
  const CountedDamage c = countedDamage(3, 2.0, 20.0, 0.4);
  EXPECT_NEAR(c.nod, 0.3, kRoundOff);
  EXPECT_NEAR(c.damage, 0.5, kRoundOff);
  EXPECT_THROW((void)countedDamage(3, 2.0, 0.0, 0.4), InputError);
  EXPECT_THROW((void)countedDamage(3, 2.0, 20.0, 1.0), InputError);
}

TEST(DesignFormulas, CommonQuantities) {
  // 2 pi x 2 / (9.81 x 8^2) = 0.0200152; xi = 0.5 / sqrt(0.0200152) = 3.534187.
  const double s = waveSteepness(2.0, 8.0);
  EXPECT_NEAR(s, 0.0200152, 1e-7);
  EXPECT_NEAR(iribarren(0.5, s), 3.534187, 1e-6);
  EXPECT_THROW((void)relativeDensity(1000.0, 1025.0), InputError); // floats
  EXPECT_THROW((void)stabilityNumber(2.0, 1.3, 0.0), InputError);
}

} // namespace
