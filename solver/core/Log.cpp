// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/Log.hpp"

#include "core/Error.hpp"

#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>

#include <algorithm>
#include <mutex>
#include <vector>

namespace armour::core {
namespace {

/// The console shows what --log-level asks for; a run-log file always keeps at least the info
/// lines (build line, settings, progress), so loggers pass the lower of the two levels and each
/// sink filters for itself.
struct LogRegistry {
  std::mutex mutex;
  spdlog::sink_ptr console = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  std::vector<spdlog::sink_ptr> sinks{console};
  spdlog::level::level_enum level = spdlog::level::info; ///< console level
  bool hasFile = false;
  [[nodiscard]] spdlog::level::level_enum loggerLevel() const {
    return hasFile ? std::min(level, spdlog::level::info) : level;
  }
};

LogRegistry& registry() {
  static LogRegistry r;
  return r;
}

} // namespace

std::shared_ptr<spdlog::logger> logger(const std::string& module) {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  if (auto existing = spdlog::get(module)) {
    return existing;
  }
  auto created = std::make_shared<spdlog::logger>(module, r.sinks.begin(), r.sinks.end());
  created->set_level(r.loggerLevel());
  created->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%n] [%l] %v");
  // Every line reaches the file at once: a run killed by SIGKILL (or the OOM killer) keeps its log
  // to the last progress line, which the file's 8 KiB buffer would lose. Lines are few (progress
  // every few seconds), so the flushes cost nothing measurable.
  created->flush_on(spdlog::level::trace);
  spdlog::register_logger(created);
  return created;
}

namespace {

/// Open `path` and attach it to every logger; the registry's mutex must be held.
spdlog::sink_ptr attachFile(LogRegistry& r, const std::string& path) {
  spdlog::sink_ptr sink;
  try {
    sink = std::make_shared<spdlog::sinks::basic_file_sink_mt>(path, true);
  } catch (const spdlog::spdlog_ex& e) {
    failInput(path, "cannot open the run log for writing ({}); choose a writable output folder", e.what());
  }
  sink->set_level(std::min(r.level, spdlog::level::info));
  r.sinks.push_back(sink);
  r.hasFile = true;
  const auto level = r.loggerLevel();
  spdlog::apply_all([&](const std::shared_ptr<spdlog::logger>& l) {
    l->sinks().push_back(sink);
    l->set_level(level);
  });
  return sink;
}

} // namespace

void addLogFile(const std::string& path) {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  attachFile(r, path);
}

ScopedLogFile::ScopedLogFile(const std::string& path) {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  sink_ = attachFile(r, path);
}

ScopedLogFile::~ScopedLogFile() {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  sink_->flush();
  std::erase(r.sinks, sink_);
  r.hasFile = r.sinks.size() > 1; // the console is always there
  const auto level = r.loggerLevel();
  spdlog::apply_all([&](const std::shared_ptr<spdlog::logger>& l) {
    std::erase(l->sinks(), sink_);
    l->set_level(level);
  });
}

void setLogLevel(const std::string& level) {
  auto& r = registry();
  const auto parsed = spdlog::level::from_str(level);
  if (parsed == spdlog::level::off && level != "off") {
    failInput("--log-level", "'{}' is not a log level; use trace, debug, info, warn, error or off", level);
  }
  std::lock_guard lock(r.mutex);
  r.level = parsed;
  r.console->set_level(parsed);
  const auto loggerLevel = r.loggerLevel();
  spdlog::apply_all([&](const std::shared_ptr<spdlog::logger>& l) { l->set_level(loggerLevel); });
}

} // namespace armour::core
