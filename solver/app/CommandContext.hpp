// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file CommandContext.hpp
/// What every subcommand shares: the global options (log level, log file) and the start-of-run
/// banner with the build information, written to the run log before any work.

#include <string>

namespace armour::app {

struct GlobalOptions {
  std::string logLevel = "info"; ///< trace, debug, info, warn, error, off
  std::string logFile;           ///< extra run-log file ("" = standard error only)
};

/// Apply the global options and log the build line and the command line.
void startRun(const GlobalOptions& options, const std::string& commandLine);

} // namespace armour::app
