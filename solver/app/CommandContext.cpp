// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/CommandContext.hpp"

#include "core/BuildInfo.hpp"
#include "core/Log.hpp"

namespace armour::app {

void startRun(const GlobalOptions& options, const std::string& commandLine) {
  core::setLogLevel(options.logLevel);
  if (!options.logFile.empty()) {
    core::addLogFile(options.logFile);
  }
  auto log = core::logger("armour");
  log->info("{}", core::buildInfo());
  log->info("command: {}", commandLine);
}

} // namespace armour::app
