// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DesignFormulas.hpp
/// The empirical armour-stability formulas of coastal engineering, to set a simulated storm's
/// damage beside what the design methods predict for it (issue 9; docs/report.md, and
/// docs/theory.md, "Design formulas", where every formula is written out with its source):
///
///  - Hudson (1959), in the form of the Shore Protection Manual and the Coastal Engineering
///    Manual: Ns = Hs / (Delta Dn) = (K_D cot alpha)^(1/3), with a table of published K_D;
///  - van der Meer (1988) for rock: the plunging and surging formulas in P, S, N and xi_m, solved
///    for the damage S;
///  - van der Meer (1988) for concrete units: cubes and tetrapods (Nod from Ns, N and s_om) and
///    the Accropode's start-of-damage and failure stability numbers;
///  - Melby and Kobayashi (1998): the progression S(t) of the damage of rock armour through a
///    storm, with its standard deviation;
///  - the damage measures of a simulated pack, Nod and S, counted from displaced units.
///
/// Every function checks its inputs against the range the formula was fitted to and throws
/// core::InputError naming the input, its value and the range: an empirical formula outside its
/// data says nothing, and a report should say "not applicable" rather than print a number.
///
/// Notation: Delta = rho_unit / rho_water - 1 (relative buoyant density), Dn the nominal
/// diameter (cube root of the unit's volume), Hs the significant wave height at the toe, Tm the
/// mean (zero-crossing) period, Tp the spectral peak period, s_om = 2 pi Hs / (g Tm^2) the
/// fictitious wave steepness, xi_m = tan alpha / sqrt(s_om) the surf-similarity (Iribarren)
/// number, N the number of waves. SI units.

#include <string>
#include <string_view>
#include <vector>

namespace armour::analysis {

/// Standard gravity used by the wave steepness (unit: m/s^2).
inline constexpr double kDesignGravity = 9.81;

// ---------------------------------------------------------------------------------------------
// Common quantities
// ---------------------------------------------------------------------------------------------

/// Delta = rho_unit / rho_water - 1 (unit: -). Throws for non-positive densities or a unit that
/// does not sink (Delta <= 0).
[[nodiscard]] double relativeDensity(double unitDensity, double waterDensity);

/// The stability number Ns = Hs / (Delta Dn) (unit: -). Throws for non-positive inputs.
[[nodiscard]] double stabilityNumber(double hs, double delta, double dn);

/// Fictitious deep-water wave steepness s = 2 pi H / (g T^2) (unit: -).
[[nodiscard]] double waveSteepness(double height, double period, double gravity = kDesignGravity);

/// Surf-similarity (Iribarren) number xi = tan alpha / sqrt(s) (unit: -).
[[nodiscard]] double iribarren(double tanAlpha, double steepness);

// ---------------------------------------------------------------------------------------------
// Hudson
// ---------------------------------------------------------------------------------------------

/// Published Hudson stability coefficients of one unit type, for the trunk of a breakwater with
/// the no-damage criterion (0-5 % of the units displaced), with the wave height Hs.
struct HudsonCoefficient {
  std::string unit;           ///< shape-library name: rock, cube, antifer, tetrapod, dolos, ...
  std::string description;    ///< e.g. "rough angular quarry stone, two layers, random"
  double kdBreaking = 0.0;    ///< K_D for breaking waves on the trunk (unit: -)
  double kdNonBreaking = 0.0; ///< K_D for non-breaking waves on the trunk (unit: -)
  double cotMin = 1.5;        ///< slopes the value is given for: cot alpha from (unit: -)
  double cotMax = 3.0;        ///< ... to (unit: -)
  int layers = 2;             ///< armour layer thickness in units (unit: -)
  std::string source;         ///< where the values come from
};

/// The table of K_D for the unit types of geometry::ShapeLibrary (rock, cube, antifer, tetrapod,
/// dolos, accropode, coreloc, xbloc, cubipod).
[[nodiscard]] const std::vector<HudsonCoefficient>& hudsonTable();

/// The row for a shape-library name ("voronoi-rock" counts as rock). Throws core::InputError for
/// a unit without published K_D, listing the ones that have.
[[nodiscard]] const HudsonCoefficient& hudsonCoefficient(std::string_view unit);

/// Hudson's stability number (K_D cot alpha)^(1/3) (unit: -): the largest Ns = Hs / (Delta Dn)
/// with no damage. Throws for K_D <= 0 or cot alpha outside [1, 6] (Hudson's tests: 1.25-5; the
/// formula is used on 1:1.33 to 1:4 slopes).
[[nodiscard]] double hudsonStabilityNumber(double kd, double cotAlpha);

/// The inverse: K_D = Ns^3 / cot alpha (unit: -), the coefficient a stability number needs.
[[nodiscard]] double hudsonKd(double stabilityNumber, double cotAlpha);

/// The nominal diameter Hudson asks for: Dn = Hs / (Delta (K_D cot alpha)^(1/3)) (unit: m).
[[nodiscard]] double hudsonNominalDiameter(double hs, double delta, double kd, double cotAlpha);

// ---------------------------------------------------------------------------------------------
// van der Meer (1988), rock
// ---------------------------------------------------------------------------------------------

/// Coefficients of van der Meer's rock formulas: the mean fit (6.2, 1.0) describes the expected
/// damage; the Rock Manual's deterministic design values (5.5, 0.87) are about one standard
/// deviation safer.
struct VanDerMeerCoefficients {
  double plunging = 6.2; ///< c_pl (unit: -)
  double surging = 1.0;  ///< c_s (unit: -)
};

/// A storm on a rock slope.
struct RockStorm {
  double stabilityNumber = 0.0; ///< Hs / (Delta Dn50) (unit: -)
  double steepness = 0.0;       ///< s_om = 2 pi Hs / (g Tm^2) (unit: -)
  double cotAlpha = 2.0;        ///< slope (unit: -)
  /// Notional permeability P (unit: -): 0.1 impermeable core, 0.4 breakwater, 0.6 homogeneous.
  double permeability = 0.4;
  double waves = 1000.0; ///< N, number of waves (unit: -)
};

/// The damage van der Meer's formulas give.
struct RockDamage {
  double damage = 0.0;            ///< S = A / Dn50^2 (unit: -)
  bool plunging = true;           ///< which formula applied
  double iribarren = 0.0;         ///< xi_m (unit: -)
  double iribarrenCritical = 0.0; ///< xi_mc, the transition (unit: -)
};

/// xi_mc = (c_pl / c_s P^0.31 sqrt(tan alpha))^(1 / (P + 0.5)) (unit: -).
[[nodiscard]] double vanDerMeerTransition(double permeability, double cotAlpha, const VanDerMeerCoefficients& c = {});

/// Ns for a damage S (the formulas as published): plunging (xi_m < xi_mc, or cot alpha >= 4)
/// Ns = c_pl P^0.18 (S / sqrt N)^0.2 xi_m^-0.5, surging Ns = c_s P^-0.13 (S / sqrt N)^0.2
/// sqrt(cot alpha) xi_m^P. `storm.stabilityNumber` is ignored.
[[nodiscard]] double vanDerMeerRockStabilityNumber(double damage, const RockStorm& storm,
                                                   const VanDerMeerCoefficients& c = {});

/// The damage S for the storm: the formulas solved for S. Validity (van der Meer 1988; Rock
/// Manual 2007 section 5.2.2.2): 0.1 <= P <= 0.6, 0.005 <= s_om <= 0.06, 1.5 <= cot alpha <= 6,
/// 1 <= N <= 7500 (the tests' range); outside, core::InputError. The result is not clipped: S below 1 means "no
/// damage", and S above the failure level of the slope (8 at 1:1.5-1:2, 12 at 1:3, 17 at 1:4-1:6)
/// means the filter shows.
[[nodiscard]] RockDamage vanDerMeerRockDamage(const RockStorm& storm, const VanDerMeerCoefficients& c = {});

// ---------------------------------------------------------------------------------------------
// van der Meer (1988), concrete units
// ---------------------------------------------------------------------------------------------

/// Cubes in two layers on a 1:1.5 slope: Ns = (6.7 Nod^0.4 / N^0.3 + 1.0) s_om^-0.1, solved for
/// Nod (0 when Ns is below the no-damage value 1.0 s_om^-0.1) (unit: -). Validity: cot alpha
/// within 1.5 +- 0.1, 0.005 <= s_om <= 0.06, 1 <= N <= 7500.
[[nodiscard]] double vanDerMeerCubesNod(double stabilityNumber, double waves, double steepness, double cotAlpha = 1.5);
/// The forward formula Ns(Nod) (unit: -), same validity, Nod >= 0.
[[nodiscard]] double vanDerMeerCubesStabilityNumber(double nod, double waves, double steepness, double cotAlpha = 1.5);

/// Tetrapods in two layers on a 1:1.5 slope: Ns = (3.75 Nod^0.5 / N^0.25 + 0.85) s_om^-0.2, solved
/// for Nod (unit: -). Same validity as the cubes.
[[nodiscard]] double vanDerMeerTetrapodsNod(double stabilityNumber, double waves, double steepness,
                                            double cotAlpha = 1.5);
[[nodiscard]] double vanDerMeerTetrapodsStabilityNumber(double nod, double waves, double steepness,
                                                        double cotAlpha = 1.5);

/// Accropode (one layer, 1:1.33): no influence of the wave period or the storm duration was
/// found; the damage is "none" up to Ns = 3.7 (start of damage, Nod = 0) and "failure" from
/// Ns = 4.1 (Nod > 0.5): the unit is brittle, with little between.
struct AccropodeStability {
  double startOfDamage = 3.7; ///< Ns at Nod = 0 (unit: -)
  double failure = 4.1;       ///< Ns at Nod > 0.5 (unit: -)
  std::string verdict;        ///< "no damage", "start of damage", "failure"
};
/// The verdict for a stability number. Validity: cot alpha in [1.25, 1.5] (tested at 1.33),
/// 0.005 <= s_om <= 0.06.
[[nodiscard]] AccropodeStability vanDerMeerAccropode(double stabilityNumber, double steepness,
                                                     double cotAlpha = 4.0 / 3.0);

// ---------------------------------------------------------------------------------------------
// Melby and Kobayashi (1998), damage progression of rock armour
// ---------------------------------------------------------------------------------------------

/// One stage of a storm with constant wave conditions.
struct StormStage {
  double duration = 0.0;        ///< (unit: s)
  double stabilityNumber = 0.0; ///< Hs / (Delta Dn50) (Tm form) or Hmo / (Delta Dn50) (Tp form) (unit: -)
  double period = 0.0;          ///< Tm (Tm form) or Tp (Tp form) (unit: s)
};

/// Which published fit: with the mean period (a = 0.025, Melby and Kobayashi 1998) or with the
/// spectral peak period and Hmo (a = 0.022, Melby 1999/2005, CHETN-III-64).
enum class MelbyKobayashiPeriod { mean, peak };

struct ProgressedDamage {
  double damage = 0.0;            ///< mean S at the end (unit: -)
  double standardDeviation = 0.0; ///< sigma_S = 0.5 S^0.65 (Melby and Kobayashi 1998) (unit: -)
  std::vector<double> afterStage; ///< mean S at the end of each stage (unit: -)
};

/// S(t) = S(t_n) + a Ns_n^5 (t^b - t_n^b) / T_n^b, b = 0.25, stage by stage from `initialDamage`
/// at t = 0 (stage n runs from t_n to t_n + duration_n). Validity (the tests behind it): slope
/// cot alpha in [1.5, 3] (tested at 2: the coefficient belongs to that slope), xi_m in
/// [2.0, 4.2] (tested 2.08-4.17) for every stage, Ns in (0, 5]; outside, core::InputError.
/// `iribarrenPerStage` gives xi_m (with Tm) of each stage.
[[nodiscard]] ProgressedDamage melbyKobayashiDamage(const std::vector<StormStage>& stages, double cotAlpha,
                                                    const std::vector<double>& iribarrenPerStage,
                                                    MelbyKobayashiPeriod form = MelbyKobayashiPeriod::mean,
                                                    double initialDamage = 0.0);

// ---------------------------------------------------------------------------------------------
// Damage measured on a simulated pack
// ---------------------------------------------------------------------------------------------

/// Nod, S from the count of displaced units.
struct CountedDamage {
  std::size_t displaced = 0; ///< units counted as displaced (unit: -)
  double nod = 0.0;          ///< displaced units per strip of width Dn: n Dn / B (unit: -)
  double damage = 0.0;       ///< S = Nod / (1 - porosity): eroded area / Dn^2 (unit: -)
};

/// Nod = n Dn / B (van der Meer 1988: displaced units in a strip one Dn wide across the slope)
/// and S = A / Dn^2 with A the eroded cross-section: n displaced units of volume Dn^3 leave a hole
/// of bulk volume n Dn^3 / (1 - p) over the width B, so A = n Dn^3 / (B (1 - p)) and
/// S = Nod / (1 - p). Throws for B <= 0, Dn <= 0 or p outside [0, 1).
[[nodiscard]] CountedDamage countedDamage(std::size_t displaced, double dn, double width, double porosity);

} // namespace armour::analysis
