// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StopSignals.hpp
/// SIGINT and SIGTERM ask a long command (`armour run`, `armour storm`, `armour place`) to stop:
/// it finishes the step, writes a checkpoint and exits with kExitStopped. The handler is one-shot
/// (SA_RESETHAND): a second signal stops the program at once, leaving the last checkpoint (written
/// atomically) in place. The previous handlers are restored when the command ends.

#include <csignal>
#include <string>

namespace armour::app {

/// Exit code of a command stopped by SIGINT or SIGTERM (the shell's 128 + SIGINT).
constexpr int kExitStopped = 130;

/// Installs the handlers for its lifetime; one at a time.
class StopSignals {
public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  /// The signal received so far, 0 if none.
  [[nodiscard]] int received() const;

private:
  struct sigaction previousInt_ {};
  struct sigaction previousTerm_ {};
};

/// A word of the printed command that continues a stopped run, as a shell reads it back: quoted
/// when it holds a space, a bracket, a quote or another character the shell would act on (a --set
/// value such as 'hydro.storm.offset=[104, 3]').
std::string shellWord(const std::string& word);

/// "SIGINT", "SIGTERM" or "a signal".
const char* signalName(int signal);

} // namespace armour::app
