// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StressCommands.hpp
/// `armour stress RUN_DIR`: the stress in chosen units of a rigid run (issue 26; docs/user-guide.md,
/// "Stress in the units"). The run recorded the contact loads on its `output.unit_loads` units
/// (simulation/UnitLoads.hpp); each unit is meshed (gmsh, tet10 with F-bar by default) and every
/// record is solved quasi-statically with inertia relief (deformable/UnitStress.hpp). Writes, in
/// RUN_DIR/stress/: units.csv (per unit: largest stresses, times, places, verdict against the
/// tensile strength), series.csv (per record), events.csv (the peaks and their causes),
/// summary.json, stress_map.vtp (the units at their last pose, coloured by their largest body
/// stress: the map of units above the strength, for ParaView) and <unit>-peak.vtu (the stress
/// field inside each unit at its worst record).

#include "app/CommandContext.hpp"

#include <CLI/CLI.hpp>

namespace armour::app {

void addStressCommands(CLI::App& app, const GlobalOptions& global);

} // namespace armour::app
