// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/ProbeInChild.hpp"

#include "core/Error.hpp"

#include <fmt/format.h>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>

namespace armour::core {
namespace {

bool gInChild = false;

/// How much of the child's stderr is kept: its last words (glibc's "double free or corruption").
constexpr std::size_t kKeptOutput = 4096;

bool disabledByEnvironment() {
  const char* v = std::getenv("ARMOUR_PROBE_IN_CHILD");
  return v != nullptr && std::string_view(v) == "0";
}

/// The child: stdout to /dev/null, stderr to the pipe, a time limit; run the probe and leave
/// without running atexit handlers or flushing the parent's buffered output a second time.
[[noreturn]] void runChild(int writeEnd, const std::function<void()>& probe, unsigned seconds) {
  gInChild = true;
  const int devNull = open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (devNull >= 0) {
    dup2(devNull, STDOUT_FILENO);
  }
  dup2(writeEnd, STDERR_FILENO);
  // glibc writes its fatal messages (heap corruption) to stderr only with this set.
  setenv("LIBC_FATAL_STDERR_", "1", 1);
  std::signal(SIGALRM, SIG_DFL);
  alarm(seconds);
  try {
    probe();
  } catch (...) {
    // Refused with an ordinary error: the parent's own read gives it again, in-process.
  }
  _exit(0); // any other exit code is the library's (or a sanitizer's) doing: see the parent

}

/// The last non-empty line of the child's output, at most 200 characters.
std::string lastLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) {
    text.pop_back();
  }
  const auto nl = text.rfind('\n');
  std::string line = nl == std::string::npos ? text : text.substr(nl + 1);
  if (line.size() > 200) {
    line = line.substr(0, 200) + "...";
  }
  return line;
}

} // namespace

bool inProbeChild() { return gInChild; }

void probeInChild(const std::string& path, const ProbeMessage& message, const std::function<void()>& probe,
                  unsigned seconds) {
  if (gInChild || disabledByEnvironment()) {
    return;
  }
  if (const char* v = std::getenv("ARMOUR_PROBE_SECONDS"); v != nullptr && std::atoi(v) > 0) {
    seconds = static_cast<unsigned>(std::atoi(v)); // tests: a short limit for a file that hangs the library
  }
  int fds[2] = {-1, -1};
  if (pipe2(fds, O_CLOEXEC) != 0) {
    failInput(path, "cannot open a pipe to test-read the {} in a child process ({}); free file descriptors, or set "
                    "ARMOUR_PROBE_IN_CHILD=0 to read it without the test",
              message.kind, std::strerror(errno));
  }
  std::fflush(nullptr); // the child must not inherit unwritten output and write it twice
  const pid_t pid = fork();
  if (pid < 0) {
    const int error = errno;
    close(fds[0]);
    close(fds[1]);
    failInput(path, "cannot start a child process to test-read the {} ({}): free memory or processes, or set "
                    "ARMOUR_PROBE_IN_CHILD=0 to read it without the test",
              message.kind, std::strerror(error));
  }
  if (pid == 0) {
    close(fds[0]);
    runChild(fds[1], probe, seconds);
  }
  close(fds[1]);
  std::string output;
  char buffer[1024];
  for (;;) {
    const ssize_t got = read(fds[0], buffer, sizeof(buffer));
    if (got > 0) {
      output.append(buffer, static_cast<std::size_t>(got));
      if (output.size() > 2 * kKeptOutput) {
        output.erase(0, output.size() - kKeptOutput);
      }
    } else if (got == 0 || errno != EINTR) {
      break;
    }
  }
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      return; // the child is gone (reaped by a SIGCHLD handler): nothing to tell, read in-process
    }
  }
  // netCDF files (the default) are inspected with the netCDF and HDF5 tools; others say how.
  const bool netcdf = message.inspect.empty();
  const auto inspect = [&] {
    return netcdf ? fmt::format("inspect it with `ncdump -h {}` or `h5dump -H {}`", path, path) : message.inspect;
  };
  if (WIFEXITED(status) && WEXITSTATUS(status) != 0) {
    // Not ours (the child exits 0 whatever the probe did): a library called exit(), or a
    // sanitizer reported a memory error (AddressSanitizer exits with 1 by default).
    failInput(path, "reading this {} ended the child process that armour starts to read it safely with exit code {} "
                    "(a library or a sanitizer stopped it): the file is probably damaged; {}; {}",
              message.kind, WEXITSTATUS(status), message.fix, inspect());
  }
  if (!WIFSIGNALED(status)) {
    return;
  }
  const int signal = WTERMSIG(status);
  if (signal == SIGINT || signal == SIGTERM || signal == SIGHUP || signal == SIGQUIT) {
    return; // an interruption, not the file: the caller's stop handling sees it too
  }
  if (signal == SIGALRM) {
    failInput(path, "reading this {} did not finish in {} s (tried in a child process, which was stopped): {}, or the "
                    "file system stalls; {}; {}",
              message.kind, seconds,
              netcdf ? "its HDF5 structure is probably damaged (metadata that loops)"
                     : "the file is probably damaged (a size or a count that makes the reader loop or allocate without end)",
              message.fix, inspect());
  }
  const std::string said = lastLine(output);
  failInput(path, "reading this {} crashed the {} library with signal {} ({}) in a child process that armour starts to "
                  "read it safely{}: {}; {}; {}{}",
            message.kind, message.library, signal, strsignal(signal),
            said.empty() ? std::string() : " (the library said: '" + said + "')",
            netcdf ? "the file's HDF5 structure is damaged (a disk fault or a broken copy)"
                   : "the file is damaged (a disk fault, a broken copy or a bad export)",
            message.fix, inspect(), netcdf ? " (Debian: netcdf-bin, hdf5-tools)" : "");
}

} // namespace armour::core
