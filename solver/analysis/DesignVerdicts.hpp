// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DesignVerdicts.hpp
/// The design formulas (analysis/DesignFormulas.hpp) that apply to a unit type, evaluated for a
/// simulated storm, each with its verdict: its values, or "not applicable" and why (no Hs, no
/// slope, no mean period, a stability number outside the formula's data). `armour report` puts
/// them beside the simulated damage (docs/report.md).

#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace armour::analysis {

/// One design formula's verdict for the report.
struct FormulaResult {
  std::string name;
  std::string source;
  bool applicable = false;
  std::string note; ///< why not applicable, or what the numbers mean
  std::vector<std::pair<std::string, double>> values;
};

/// What the design formulas need of the run and its storm.
struct DesignInputs {
  std::string unitType;                                        ///< shape-library name of the units
  double ns = std::numeric_limits<double>::quiet_NaN();        ///< Hs / (Delta Dn) (unit: -)
  double cotAlpha = std::numeric_limits<double>::quiet_NaN();  ///< slope (unit: -)
  double steepness = std::numeric_limits<double>::quiet_NaN(); ///< s_om (unit: -)
  double xi = std::numeric_limits<double>::quiet_NaN();        ///< xi_m (unit: -)
  double waves = std::numeric_limits<double>::quiet_NaN();     ///< N in the run (unit: -)
  double tm = std::numeric_limits<double>::quiet_NaN();        ///< mean period (unit: s)
  double duration = 0.0;                                       ///< the run's duration (unit: s)
  double permeability = 0.4;                                   ///< van der Meer's P (unit: -)
  bool breaking = false;                                       ///< Hudson's K_D for breaking waves
  std::string noHs = "no storm: Hs unknown (give --storm or --hs)"; ///< why ns is unknown
};

/// Each formula that applies to the unit type (Hudson for all; van der Meer and Melby and
/// Kobayashi for rock; van der Meer for cubes, tetrapods and Accropodes), evaluated or marked not
/// applicable with the reason.
[[nodiscard]] std::vector<FormulaResult> designVerdicts(const DesignInputs& in);

} // namespace armour::analysis
