// SPDX-License-Identifier: GPL-3.0-or-later
// core::probeInChild (core/ProbeInChild.hpp): a read that crashes or hangs in the child becomes an
// InputError naming the file, the signal and the fix; a read that ends normally, or throws, lets
// the caller go on; a probe inside the child runs in place; the cost of one probe is recorded.

#include "core/Error.hpp"
#include "core/ProbeInChild.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

using armour::core::InputError;
using armour::core::probeInChild;

namespace {

const armour::core::ProbeMessage kMessage{"storm file", "regenerate it"};

/// The InputError of a probe, or "" if it returned.
std::string errorOf(const std::function<void()>& probe, unsigned seconds = armour::core::kProbeSeconds) {
  try {
    probeInChild("storm.nc", kMessage, probe, seconds);
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

#define EXPECT_CONTAINS(text, fragment) \
  EXPECT_NE(std::string(text).find(fragment), std::string::npos) << "missing \"" << (fragment) << "\" in:\n" << (text)

} // namespace

TEST(ProbeInChild, ACrashInTheChildIsAnInputErrorNamingFileSignalAndFix) {
  const std::string e = errorOf([] { std::raise(SIGSEGV); });
  EXPECT_CONTAINS(e, "storm.nc: reading this storm file crashed the netCDF/HDF5 library with signal 11");
  EXPECT_CONTAINS(e, "the file's HDF5 structure is damaged");
  EXPECT_CONTAINS(e, "regenerate it");
  EXPECT_CONTAINS(e, "ncdump -h storm.nc");
  // glibc's last words (written to stderr before abort) are passed on.
  const std::string a = errorOf([] {
    std::fputs("HDF5: noise\ndouble free or corruption (out)\n", stderr);
    std::fflush(stderr);
    std::abort();
  });
  EXPECT_CONTAINS(a, "signal 6");
  EXPECT_CONTAINS(a, "(the library said: 'double free or corruption (out)')");
}

TEST(ProbeInChild, AnExitCodeFromTheChildIsAnInputError) {
  // The child exits 0 whatever the probe does; another code is a library's exit() or a
  // sanitizer's report (AddressSanitizer exits with 1).
  const std::string e = errorOf([] { _exit(1); });
  EXPECT_CONTAINS(e, "storm.nc: reading this storm file ended the child process");
  EXPECT_CONTAINS(e, "with exit code 1");
  EXPECT_CONTAINS(e, "regenerate it");
}

TEST(ProbeInChild, AHangIsStoppedAtTheTimeLimit) {
  const auto start = std::chrono::steady_clock::now();
  const std::string e = errorOf([] { pause(); }, 1);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_CONTAINS(e, "storm.nc: reading this storm file did not finish in 1 s");
  EXPECT_CONTAINS(e, "regenerate it");
  EXPECT_LT(seconds, 10.0) << "the child is stopped at the limit (1 s), not waited for";
}

TEST(ProbeInChild, ANormalEndOrAnExceptionLetsTheCallerGoOn) {
  EXPECT_EQ(errorOf([] {}), "");
  EXPECT_EQ(errorOf([] { throw InputError("storm.nc: not a storm file"); }), "")
      << "the caller's own read gives the same error in-process";
  EXPECT_EQ(errorOf([] { throw std::runtime_error("anything"); }), "");
  EXPECT_FALSE(armour::core::inProbeChild());
}

TEST(ProbeInChild, AProbeInsideTheChildRunsInPlace) {
  // The reader's probe constructs the same reader in the child, whose own probe must not fork
  // again: inside, probeInChild returns without running its function.
  const std::string e = errorOf([] {
    if (!armour::core::inProbeChild()) _exit(0); // not seen from the child: the test would pass wrongly
    probeInChild("inner.nc", kMessage, [] { std::raise(SIGSEGV); });
    std::raise(SIGABRT); // reached only if the inner probe returned without running its crash
  });
  EXPECT_CONTAINS(e, "signal 6") << "the inner probe ran in place (no second child) and returned";
}

TEST(ProbeInChild, OffInTheEnvironmentSkipsTheChild) {
  setenv("ARMOUR_PROBE_IN_CHILD", "0", 1);
  bool ran = false;
  probeInChild("storm.nc", kMessage, [&] { ran = true; });
  unsetenv("ARMOUR_PROBE_IN_CHILD");
  EXPECT_FALSE(ran) << "skipped: neither a child nor an in-process run";
}

TEST(ProbeInChild, CostOfOneProbe) {
  // The fork, the child's exit and the wait, with an empty probe: the overhead every open pays.
  constexpr int kProbes = 20;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kProbes; ++i) {
    probeInChild("storm.nc", kMessage, [] {});
  }
  const double ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / kProbes;
  RecordProperty("probe_ms", std::to_string(ms));
  std::printf("one empty probe: %.2f ms\n", ms);
  EXPECT_LT(ms, 100.0) << "a fork of a small process is milliseconds";
}
