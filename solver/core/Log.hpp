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

/// Set the level of every logger ("trace", "debug", "info", "warn", "error", "off").
void setLogLevel(const std::string& level);

} // namespace armour::core
