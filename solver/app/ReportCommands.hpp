// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ReportCommands.hpp
/// `armour report RUN_DIR`: the damage report of a storm run (issue 9; docs/report.md). Reads the
/// run's bodies.nc, its scene and its storm file, and writes into RUN_DIR/report (or --output):
///  - units.csv: per unit, initial and final centroid, displacement (world and slope frame, m and
///    Dn), rotation and the rocking flag;
///  - timeseries.csv: per bodies.nc record, the total displacement of all units (seed 000 Figs. 9,
///    12), their mean and largest displacement in Dn and the counts above 0.2, 0.5 and 1 Dn;
///  - storm.csv: the storm input at the run's times: pressure at a chosen voxel (seed 000 Fig. 5)
///    and the free surface at the gauge;
///  - summary.json: the damage measures (counts, rocking, Nod, S, delta_rms, P2 before and
///    after), the storm's Hs, Tm, Tp, and the design-formula predictions for the storm
///    (analysis/DesignFormulas.hpp) beside them;
///  - with utilities/report.py (python3, numpy, matplotlib): the PNGs and index.html.
/// The numbers come from analysis/DamageReport.hpp; this file parses the options and writes them
/// (JSON values through core/JsonWriter.hpp, shared with `armour storm-file info --json`).

#include "app/CommandContext.hpp"

#include <CLI/CLI.hpp>

namespace armour::app {

void addReportCommands(CLI::App& app, GlobalOptions& global);

} // namespace armour::app
