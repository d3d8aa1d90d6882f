// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ProbeInChild.hpp
/// Open a file in a forked child first, so that a library that crashes on a damaged file kills the
/// child and not armour.
///
/// Why: libhdf5 1.10.8 (Debian 12) frees memory twice or reads through a wild pointer inside
/// nc_open when bytes of a netCDF-4 file's HDF5 metadata are damaged (docs/validation.md, "Fuzz
/// pass over the readers": about 1 in 15 files with flipped bytes). No check of ours runs before
/// the crash, so the reader cannot refuse the file in-process. probeInChild() runs the same reading
/// code in a child process; if the child dies by a signal (or hangs past the time limit), the file
/// is refused with an InputError naming the file, the signal and the fix. If the child ends
/// normally (the file read, or refused with an ordinary error), the caller opens it in-process.
///
/// Cost: one fork and the child's read, about 2-3 ms for a small storm file
/// (docs/validation.md has the measurement).
///
/// Threads. fork() copies only the calling thread. The child then calls netCDF/HDF5, which is
/// not async-signal-safe: this is sound only if no other thread of the parent holds a lock the
/// child needs (HDF5's global lock, a stdio lock) at the moment of the fork. glibc's malloc is
/// made consistent across fork by glibc itself. armour calls netCDF from the main thread only and
/// outside OpenMP parallel regions (OpenMP workers sit idle in the runtime between regions), so
/// the condition holds; call probeInChild() likewise from serial code only. Should it ever be
/// broken, the child would wait on the held lock and the time limit would refuse the file as a
/// hang: a wrong message, not a crash of armour.
///
/// Debugging: ARMOUR_PROBE_IN_CHILD=0 in the environment skips the probe (to see the library's
/// crash in-process, under gdb or a sanitizer); ARMOUR_PROBE_SECONDS=N sets the time limit (tests).

#include <functional>
#include <string>
#include <utility>

namespace armour::core {

/// The child's time limit: a damaged file whose metadata loops, or a stalled file system, must not
/// hang armour. 60 s is ours: reading a storm file's header and two records takes milliseconds, a
/// checkpoint of 10^5 bodies well under a second (unit: s).
constexpr unsigned kProbeSeconds = 60;

/// What to say about a file the child could not read.
struct ProbeMessage {
  std::string kind; ///< "storm file", "checkpoint", ... (unit: -)
  std::string fix;  ///< what the user should do, e.g. "regenerate the storm file (...) or copy it again"
  std::string library = "netCDF/HDF5"; ///< the library that reads it, named when it crashes
  /// How to inspect the file; empty: the netCDF tools (`ncdump -h`, `h5dump -H`).
  std::string inspect;

  ProbeMessage(std::string kind_, std::string fix_, std::string library_ = "netCDF/HDF5", std::string inspect_ = {})
      : kind(std::move(kind_)), fix(std::move(fix_)), library(std::move(library_)), inspect(std::move(inspect_)) {}
};

/// Run `probe` (which should open `path` and read what the caller will read) in a forked child.
/// Returns normally if the child ended by itself, whatever `probe` did (returned or threw: the
/// caller's own in-process read then gives the same result, or the same error). Throws InputError
/// if the child died by a signal other than an interruption (SIGINT, SIGTERM, SIGHUP, SIGQUIT:
/// those are the user's, and the caller's stop handling sees them too), ran past `seconds`, or
/// exited with a code other than 0 (which the child never does itself: a library's exit(), or
/// AddressSanitizer's report of the library's memory error).
/// In the child itself (a probe that opens another file), and with ARMOUR_PROBE_IN_CHILD=0,
/// returns at once without forking. Throws InputError if fork() fails (out of processes or
/// memory), naming the file.
void probeInChild(const std::string& path, const ProbeMessage& message, const std::function<void()>& probe,
                  unsigned seconds = kProbeSeconds);

/// True in a child started by probeInChild().
[[nodiscard]] bool inProbeChild();

} // namespace armour::core
