// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/CommandContext.hpp"

#include "core/BuildInfo.hpp"
#include "core/Log.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#ifndef ARMOUR_UTILITIES_DIR
#define ARMOUR_UTILITIES_DIR ""
#endif

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

bool runUtility(const std::string& script, const std::vector<std::string>& args, const std::string& what) {
  const std::filesystem::path path = std::filesystem::path(ARMOUR_UTILITIES_DIR) / script;
  if (!std::filesystem::exists(path)) {
    std::cout << fmt::format("{} skipped: {} not found\n", what, path.string());
    return false;
  }
  std::string command = fmt::format("/usr/bin/python3 '{}'", path.string());
  for (const std::string& a : args) command += fmt::format(" '{}'", a);
  if (std::system(command.c_str()) != 0) {
    std::cout << fmt::format("{} failed (python3 with numpy and matplotlib needed): {}\n", what, command);
    return false;
  }
  return true;
}

void keepPreviousLog(const std::filesystem::path& runLog) {
  std::error_code ec;
  if (!std::filesystem::exists(runLog, ec)) {
    return;
  }
  for (int k = 1;; ++k) {
    const std::filesystem::path kept = runLog.parent_path() / fmt::format("run.{}.log", k);
    if (!std::filesystem::exists(kept, ec)) {
      std::filesystem::rename(runLog, kept, ec);
      return; // a log that cannot be moved is overwritten, which loses no result
    }
  }
}

} // namespace armour::app
