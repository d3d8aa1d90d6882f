// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file CommandContext.hpp
/// What every subcommand shares: the global options (log level, log file) and the start-of-run
/// banner with the build information, written to the run log before any work.

#include <filesystem>
#include <string>
#include <vector>

namespace armour::app {

struct GlobalOptions {
  std::string logLevel = "info"; ///< trace, debug, info, warn, error, off
  std::string logFile;           ///< extra run-log file ("" = standard error only)
};

/// Apply the global options and log the build line and the command line.
void startRun(const GlobalOptions& options, const std::string& commandLine);

/// Keep the log of the run being continued: run.log -> run.<k>.log, the first free k from 1 (a log
/// that cannot be moved is overwritten, which loses no result).
void keepPreviousLog(const std::filesystem::path& runLog);

/// Run utilities/<script> (Python 3 with numpy and matplotlib, from the source tree) with `args`.
/// Plots are extras: a missing script or a failed run prints a notice naming `what` was skipped and
/// the command, not an error. Returns true when the script ran and succeeded.
bool runUtility(const std::string& script, const std::vector<std::string>& args, const std::string& what);

} // namespace armour::app
