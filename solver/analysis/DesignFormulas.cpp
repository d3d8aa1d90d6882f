// SPDX-License-Identifier: GPL-3.0-or-later
#include "analysis/DesignFormulas.hpp"

#include "core/Error.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

namespace armour::analysis {
namespace {

/// Refuse a value outside [lo, hi] (NaN included), naming the formula, the input and its range.
void requireRange(const char* formula, const char* name, double value, double lo, double hi, const char* why) {
  if (!(value >= lo && value <= hi))
    core::failInput(formula, "{} = {:.6g} is outside [{:g}, {:g}], the range {}; the formula says nothing there", name,
                    value, lo, hi, why);
}

void requirePositive(const char* formula, const char* name, double value) {
  if (!(value > 0.0) || !std::isfinite(value))
    core::failInput(formula, "{} = {:.6g}: must be a positive finite number", name, value);
}

// The steepness range of van der Meer's tests (1988), shared by the rock and concrete formulas.
constexpr double kSteepMin = 0.005;
constexpr double kSteepMax = 0.06;
constexpr double kMaxWaves = 7500.0;

void requireConcreteRange(const char* formula, double waves, double steepness, double cotAlpha, double cotLo,
                          double cotHi) {
  requireRange(formula, "N", waves, 1.0, kMaxWaves, "of the tests (van der Meer 1988)");
  requireRange(formula, "s_om", steepness, kSteepMin, kSteepMax, "of the tests (van der Meer 1988)");
  requireRange(formula, "cot alpha", cotAlpha, cotLo, cotHi, "of the slope the units were tested on");
}

} // namespace

double relativeDensity(double unitDensity, double waterDensity) {
  requirePositive("relative density", "rho_unit (kg/m^3)", unitDensity);
  requirePositive("relative density", "rho_water (kg/m^3)", waterDensity);
  const double delta = unitDensity / waterDensity - 1.0;
  if (!(delta > 0.0))
    core::failInput("relative density",
                    "rho_unit = {:g} kg/m^3 is not denser than the water ({:g} kg/m^3): the unit "
                    "floats and no stability formula applies",
                    unitDensity, waterDensity);
  return delta;
}

double stabilityNumber(double hs, double delta, double dn) {
  requirePositive("stability number", "Hs (m)", hs);
  requirePositive("stability number", "Delta", delta);
  requirePositive("stability number", "Dn (m)", dn);
  return hs / (delta * dn);
}

double waveSteepness(double height, double period, double gravity) {
  requirePositive("wave steepness", "H (m)", height);
  requirePositive("wave steepness", "T (s)", period);
  requirePositive("wave steepness", "g (m/s^2)", gravity);
  return 2.0 * std::numbers::pi * height / (gravity * period * period);
}

double iribarren(double tanAlpha, double steepness) {
  requirePositive("Iribarren number", "tan alpha", tanAlpha);
  requirePositive("Iribarren number", "wave steepness", steepness);
  return tanAlpha / std::sqrt(steepness);
}

// --- Hudson ------------------------------------------------------------------------------------

const std::vector<HudsonCoefficient>& hudsonTable() {
  // Trunk, no-damage criterion (0-5 % displaced), used with H = Hs. SPM 1984 moved to H = H1/10
  // and lowered the breaking-wave K_D of rock to 2.0; with Hs its 1977 value 3.5 is the consistent
  // one (docs/theory.md, "Design formulas").
  static const std::vector<HudsonCoefficient> table = {
      {"rock", "rough angular quarry stone, two layers, random", 3.5, 4.0, 1.5, 3.0, 2,
       "SPM (1977) Table 7-8, with H = Hs (SPM 1984 gives 2.0 for breaking waves with H = H1/10)"},
      {"cube", "modified / plain cube, two layers, random", 6.5, 7.5, 1.5, 3.0, 2, "SPM (1984) Table 7-8"},
      {"antifer", "Antifer cube, two layers, random", 6.5, 7.5, 1.5, 2.0, 2,
       "treated as the cube of SPM (1984) Table 7-8 (CEM 2006 Table VI-5-29 gives cubes and Antifer the same range)"},
      {"tetrapod", "tetrapod, two layers, random", 7.0, 8.0, 1.5, 3.0, 2, "SPM (1984) Table 7-8"},
      {"dolos", "dolos, two layers, random", 15.8, 31.8, 2.0, 3.0, 2,
       "SPM (1984) Table 7-8 (values for cot alpha 2-3; stability beyond cot 2 not confirmed)"},
      {"accropode", "Accropode, one layer, interlocked", 12.0, 15.0, 1.33, 1.5, 1,
       "CEM (2006) Table VI-5-29, after Sogreah's guidance"},
      {"coreloc", "Core-Loc, one layer, interlocked", 16.0, 16.0, 1.33, 2.0, 1,
       "CEM (2006) Table VI-5-29, after Melby and Turk (1994)"},
      {"xbloc", "Xbloc, one layer, interlocked", 16.0, 16.0, 1.33, 2.0, 1,
       "Delta Marine Consultants, Xbloc design guidelines (2003), trunk"},
      {"cubipod", "Cubipod, two layers, random", 28.0, 28.0, 1.5, 1.5, 2,
       "Gomez-Martin and Medina (2014), double-layer trunk, non-overtopped"},
  };
  return table;
}

const HudsonCoefficient& hudsonCoefficient(std::string_view unit) {
  const std::string_view key = unit == "voronoi-rock" ? std::string_view("rock") : unit;
  std::string names;
  for (const HudsonCoefficient& c : hudsonTable()) {
    if (c.unit == key) return c;
    names += (names.empty() ? "" : ", ") + c.unit;
  }
  core::failInput("Hudson K_D", "no published K_D for the unit '{}'; the table has {}", unit, names);
}

double hudsonStabilityNumber(double kd, double cotAlpha) {
  requirePositive("Hudson", "K_D", kd);
  requireRange("Hudson", "cot alpha", cotAlpha, 1.0, 6.0, "of slopes Hudson's formula is used on");
  return std::cbrt(kd * cotAlpha);
}

double hudsonKd(double ns, double cotAlpha) {
  requirePositive("Hudson", "Ns", ns);
  requireRange("Hudson", "cot alpha", cotAlpha, 1.0, 6.0, "of slopes Hudson's formula is used on");
  return ns * ns * ns / cotAlpha;
}

double hudsonNominalDiameter(double hs, double delta, double kd, double cotAlpha) {
  requirePositive("Hudson", "Hs (m)", hs);
  requirePositive("Hudson", "Delta", delta);
  return hs / (delta * hudsonStabilityNumber(kd, cotAlpha));
}

// --- van der Meer, rock --------------------------------------------------------------------------

namespace {

void requireRockRange(const RockStorm& s) {
  const char* f = "van der Meer (rock)";
  requireRange(f, "P", s.permeability, 0.1, 0.6, "of notional permeabilities tested (van der Meer 1988)");
  requireRange(f, "s_om", s.steepness, kSteepMin, kSteepMax, "of the tests (van der Meer 1988)");
  requireRange(f, "cot alpha", s.cotAlpha, 1.5, 6.0, "of the slopes tested (van der Meer 1988)");
  requireRange(f, "N", s.waves, 1.0, kMaxWaves, "of the tests (van der Meer 1988)");
}

/// Whether the plunging formula applies: below the transition, and always on slopes of 1:4 and
/// gentler, where van der Meer found no surging regime.
bool isPlunging(double xi, double xiCritical, double cotAlpha) { return cotAlpha >= 4.0 || xi < xiCritical; }

/// Ns / (S / sqrt N)^0.2: the part of each formula that does not depend on the damage.
double rockFactor(const RockStorm& s, double xi, bool plunging, const VanDerMeerCoefficients& c) {
  const double P = s.permeability;
  return plunging ? c.plunging * std::pow(P, 0.18) / std::sqrt(xi)
                  : c.surging * std::pow(P, -0.13) * std::sqrt(s.cotAlpha) * std::pow(xi, P);
}

} // namespace

double vanDerMeerTransition(double permeability, double cotAlpha, const VanDerMeerCoefficients& c) {
  requireRange("van der Meer (rock)", "P", permeability, 0.1, 0.6, "of notional permeabilities tested");
  requirePositive("van der Meer (rock)", "cot alpha", cotAlpha);
  return std::pow(c.plunging / c.surging * std::pow(permeability, 0.31) * std::sqrt(1.0 / cotAlpha),
                  1.0 / (permeability + 0.5));
}

double vanDerMeerRockStabilityNumber(double damage, const RockStorm& storm, const VanDerMeerCoefficients& c) {
  requireRockRange(storm);
  requirePositive("van der Meer (rock)", "S", damage);
  const double xi = iribarren(1.0 / storm.cotAlpha, storm.steepness);
  const bool plunging = isPlunging(xi, vanDerMeerTransition(storm.permeability, storm.cotAlpha, c), storm.cotAlpha);
  return rockFactor(storm, xi, plunging, c) * std::pow(damage / std::sqrt(storm.waves), 0.2);
}

RockDamage vanDerMeerRockDamage(const RockStorm& storm, const VanDerMeerCoefficients& c) {
  requireRockRange(storm);
  requirePositive("van der Meer (rock)", "Ns", storm.stabilityNumber);
  RockDamage d;
  d.iribarren = iribarren(1.0 / storm.cotAlpha, storm.steepness);
  d.iribarrenCritical = vanDerMeerTransition(storm.permeability, storm.cotAlpha, c);
  d.plunging = isPlunging(d.iribarren, d.iribarrenCritical, storm.cotAlpha);
  // Ns = F (S / sqrt N)^0.2  <=>  S = sqrt(N) (Ns / F)^5.
  const double ratio = storm.stabilityNumber / rockFactor(storm, d.iribarren, d.plunging, c);
  d.damage = std::sqrt(storm.waves) * std::pow(ratio, 5.0);
  return d;
}

// --- van der Meer, concrete units ------------------------------------------------------------------

double vanDerMeerCubesStabilityNumber(double nod, double waves, double steepness, double cotAlpha) {
  requireConcreteRange("van der Meer (cubes)", waves, steepness, cotAlpha, 1.4, 1.6);
  if (!(nod >= 0.0)) core::failInput("van der Meer (cubes)", "Nod = {:g}: must be >= 0", nod);
  return (6.7 * std::pow(nod, 0.4) / std::pow(waves, 0.3) + 1.0) * std::pow(steepness, -0.1);
}

double vanDerMeerCubesNod(double ns, double waves, double steepness, double cotAlpha) {
  requireConcreteRange("van der Meer (cubes)", waves, steepness, cotAlpha, 1.4, 1.6);
  requirePositive("van der Meer (cubes)", "Ns", ns);
  const double excess = ns * std::pow(steepness, 0.1) - 1.0;
  if (excess <= 0.0) return 0.0; // below the no-damage stability number
  return std::pow(excess * std::pow(waves, 0.3) / 6.7, 1.0 / 0.4);
}

double vanDerMeerTetrapodsStabilityNumber(double nod, double waves, double steepness, double cotAlpha) {
  requireConcreteRange("van der Meer (tetrapods)", waves, steepness, cotAlpha, 1.4, 1.6);
  if (!(nod >= 0.0)) core::failInput("van der Meer (tetrapods)", "Nod = {:g}: must be >= 0", nod);
  return (3.75 * std::sqrt(nod) / std::pow(waves, 0.25) + 0.85) * std::pow(steepness, -0.2);
}

double vanDerMeerTetrapodsNod(double ns, double waves, double steepness, double cotAlpha) {
  requireConcreteRange("van der Meer (tetrapods)", waves, steepness, cotAlpha, 1.4, 1.6);
  requirePositive("van der Meer (tetrapods)", "Ns", ns);
  const double excess = ns * std::pow(steepness, 0.2) - 0.85;
  if (excess <= 0.0) return 0.0;
  const double root = excess * std::pow(waves, 0.25) / 3.75;
  return root * root;
}

AccropodeStability vanDerMeerAccropode(double ns, double steepness, double cotAlpha) {
  const char* f = "van der Meer (Accropode)";
  requirePositive(f, "Ns", ns);
  requireRange(f, "s_om", steepness, kSteepMin, kSteepMax, "of the tests (van der Meer 1988)");
  requireRange(f, "cot alpha", cotAlpha, 1.25, 1.5, "of the slope the units were tested on (1:1.33)");
  AccropodeStability a;
  a.verdict = ns < a.startOfDamage ? "no damage" : (ns < a.failure ? "start of damage" : "failure");
  return a;
}

// --- Melby and Kobayashi -----------------------------------------------------------------------------

ProgressedDamage melbyKobayashiDamage(const std::vector<StormStage>& stages, double cotAlpha,
                                      const std::vector<double>& iribarrenPerStage, MelbyKobayashiPeriod form,
                                      double initialDamage) {
  const char* f = "Melby and Kobayashi";
  if (stages.empty()) core::failInput(f, "no storm stages: give at least one");
  if (iribarrenPerStage.size() != stages.size())
    core::failInput(f, "{} Iribarren numbers for {} stages: give one per stage", iribarrenPerStage.size(),
                    stages.size());
  requireRange(f, "cot alpha", cotAlpha, 1.5, 3.0,
               "around the 1:2 slope of the tests (the coefficient belongs to that slope)");
  if (!(initialDamage >= 0.0)) core::failInput(f, "initial S = {:g}: must be >= 0", initialDamage);
  // a: 0.025 with Hs and Tm (Melby and Kobayashi 1998), 0.022 with Hmo and Tp (Melby 2005).
  const double a = form == MelbyKobayashiPeriod::mean ? 0.025 : 0.022;
  constexpr double b = 0.25;
  ProgressedDamage out;
  double s = initialDamage, t = 0.0;
  for (std::size_t n = 0; n < stages.size(); ++n) {
    const StormStage& st = stages[n];
    requirePositive(f, "stage duration (s)", st.duration);
    requirePositive(f, "stage period (s)", st.period);
    requireRange(f, "Ns", st.stabilityNumber, 1e-12, 5.0, "of the tests (Ns up to about 4)");
    requireRange(f, "xi_m", iribarrenPerStage[n], 2.0, 4.2, "of the tests (2.08-4.17, CHETN-III-64)");
    const double t1 = t + st.duration;
    s += a * std::pow(st.stabilityNumber, 5.0) * (std::pow(t1, b) - std::pow(t, b)) / std::pow(st.period, b);
    out.afterStage.push_back(s);
    t = t1;
  }
  out.damage = s;
  out.standardDeviation = 0.5 * std::pow(s, 0.65);
  return out;
}

// --- Counted damage ---------------------------------------------------------------------------------

CountedDamage countedDamage(std::size_t displaced, double dn, double width, double porosity) {
  requirePositive("counted damage", "Dn (m)", dn);
  requirePositive("counted damage", "width B (m)", width);
  if (!(porosity >= 0.0 && porosity < 1.0))
    core::failInput("counted damage", "porosity = {:g}: must be in [0, 1)", porosity);
  CountedDamage c;
  c.displaced = displaced;
  c.nod = static_cast<double>(displaced) * dn / width;
  c.damage = c.nod / (1.0 - porosity);
  return c;
}

} // namespace armour::analysis
