// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file EnsembleCommands.hpp
/// `armour ensemble`: packings x storm realisations. Member k of the packings is the placement
/// file with seed S + k (seed 001 Table 1: mean +- std over 16 packings); with --storm, each
/// packing is also stormed by each storm file and each variability seed (seed 000's Weibull draws),
/// and the damage measures are gathered like the pack measures.
///
/// Under `mpirun -np N` (Open MPI) the members are dealt to the ranks round-robin, one run per
/// rank at a time with OpenMP inside; rank 0 gathers the measures and writes the tables. Members
/// write their own folders, so across nodes the output folder must be on a shared file system.
/// docs/user-guide.md, "Ensembles".

#include "app/CommandContext.hpp"

#include <CLI/CLI.hpp>

namespace armour::app {

void addEnsembleCommands(CLI::App& app, const GlobalOptions& global);

} // namespace armour::app
