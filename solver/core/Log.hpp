// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Log.hpp
/// One logger per module (spdlog), all writing to the same sinks: standard error and, when a run
/// opens one, a run log file. Library code never writes to std::cout.

#include <spdlog/spdlog.h>

#include <memory>
#include <string>

namespace armour::core {

/// Logger for a module ("geometry", "contact", ...). Created on first use, shares the sinks.
std::shared_ptr<spdlog::logger> logger(const std::string& module);

/// Add a file sink (the run log) to every existing and future logger.
void addLogFile(const std::string& path);

/// A run log open for one scope: every logger also writes to it while it lives; it is closed
/// and detached when it goes. For several runs in one process (the members of an ensemble), each
/// with its own run.log.
class ScopedLogFile {
public:
  explicit ScopedLogFile(const std::string& path);
  ~ScopedLogFile();
  ScopedLogFile(const ScopedLogFile&) = delete;
  ScopedLogFile& operator=(const ScopedLogFile&) = delete;

private:
  spdlog::sink_ptr sink_;
};

/// Set the level of every logger ("trace", "debug", "info", "warn", "error", "off").
void setLogLevel(const std::string& level);

} // namespace armour::core
