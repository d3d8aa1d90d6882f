// SPDX-License-Identifier: GPL-3.0-or-later
// The armourSampler function object on cases the project did not write (issue 23, items 1 to 4),
// on the still-water case of tests/cases/stillWater (6656 cells, a box-shaped `unit` patch of 256
// faces below the still water level), serial runs of Debian's interFoam:
//  - a dynamicRefineFvMesh (the unit patch grows from 256 to 1024 faces at the first step) is
//    refused before the first sample with a message that names the mesh type and the fix, with the
//    sampler built with AddressSanitizer: no memory error (before the fix the run wrote past its
//    arrays and died with a segmentation fault / double free at the first sample);
//  - a whole static run under AddressSanitizer: no report, a valid storm file;
//  - the storm file's provenance: source_case, openfoam_version and a history naming the solver
//    (before: empty, empty, "armour storm writer");
//  - a run killed with SIGKILL after 4 samples leaves storm.nc.partial with every record appended
//    (before: 0 records);
//  - g along -y is refused, naming constant/g and transformPoints.
// About 20 s.

#include "storm/StormFile.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;
using armour::storm::StormReader;

namespace {

const fs::path kCase = fs::path(ARMOUR_FOAM_BRIDGE_DIR) / "tests/cases/stillWater";
const fs::path kWork = fs::path(ARMOUR_FOAM_BRIDGE_WORK) / "sampler-user-cases";

// The grid of the still-water test (offset from the 0.025 m mesh).
const char* kGridArgs =
    " --x-min 0.17 --z-min 0.12 --dx 0.05 --dz 0.05 --nx 6 --nz 6 --trunk-origin 0 --trunk-length 0.3"
    " --swl 0.45 --rho 1000 --eta-plane-y 0.1625 --eta-half-width 0.0125";

// interFoam with the AddressSanitizer build of the sampler: libasan must come first in the
// process (Debian's interFoam is not instrumented). OpenFOAM frees its run-time tables at exit in
// an order LeakSanitizer reports: leaks are not what is tested.
const std::string kAsanEnv = std::string("LD_PRELOAD=") + ARMOUR_LIBASAN + " ASAN_OPTIONS=detect_leaks=0 ";

std::string slurp(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void replaceInFile(const fs::path& f, const std::string& pattern, const std::string& with) {
  const std::string s = std::regex_replace(slurp(f), std::regex(pattern), with);
  std::ofstream(f) << s;
}

/// Runs `command` in `dir` with its output in `log`; returns the exit status (shell convention).
int run(const std::string& command, const fs::path& dir, const std::string& log) {
  const std::string full = "cd '" + dir.string() + "' && WM_PROJECT_DIR=/usr/share/openfoam " + command + " > '" +
                           log + "' 2>&1";
  const int rc = std::system(full.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : 128 + WTERMSIG(rc);
}

/// A copy of the meshed still-water case (blockMesh, setFields done) with the sampler of `library`.
fs::path caseWith(const std::string& name, const std::string& library) {
  const fs::path dir = kWork / name;
  fs::remove_all(dir);
  fs::copy(kWork / "base", dir, fs::copy_options::recursive);
  replaceInFile(dir / "system/armourFunctions", "SAMPLER_LIBRARY", library);
  return dir;
}

class SamplerUserCases : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    fs::remove_all(kWork);
    const fs::path base = kWork / "base";
    fs::create_directories(kWork);
    fs::copy(kCase, base, fs::copy_options::recursive);
    fs::copy(base / "0.orig", base / "0", fs::copy_options::recursive);
    error_.clear();
    if (run(std::string(ARMOUR_FOAM_PROXY) + " dict --function-objects sampler --patches unit --sampler-library "
            "SAMPLER_LIBRARY" + kGridArgs + " -o system/armourFunctions", base, "log.dict") != 0) {
      error_ = "foam-proxy dict failed in " + base.string();
      return;
    }
    for (const char* step : {"blockMesh", "setFields"}) {
      if (run(step, base, std::string("log.") + step) != 0) {
        error_ = std::string(step) + " failed in " + base.string();
        return;
      }
    }
  }
  void SetUp() override { ASSERT_TRUE(error_.empty()) << error_; }
  static std::string error_;
};
std::string SamplerUserCases::error_;

TEST_F(SamplerUserCases, DynamicRefineMeshIsRefusedBeforeTheFirstSampleWithoutMemoryErrors) {
  const fs::path dir = caseWith("dynamic", ARMOUR_SAMPLER_ASAN_LIB);
  // A common interFoam setting: refine where the water is. Every water cell is refined at the
  // first step, the unit patch with them (256 -> 1024 faces), before the first sample at 0.05 s.
  std::ofstream(dir / "constant/dynamicMeshDict") << R"(FoamFile { version 2.0; format ascii; class dictionary; object dynamicMeshDict; }
dynamicFvMesh   dynamicRefineFvMesh;
dynamicRefineFvMeshCoeffs
{
    refineInterval 1; field alpha.water; lowerRefineLevel 0.5; upperRefineLevel 2; unrefineLevel -1;
    nBufferLayers 1; maxRefinement 1; maxCells 200000; dumpLevel false;
    correctFluxes ((phi none) (nHatf none) (rhoPhi none) (alphaPhi0.water none) (ghf none));
}
)";
  replaceInFile(dir / "system/controlDict", "endTime +0.2;", "endTime 0.05;");
  const int rc = run(kAsanEnv + "interFoam", dir, "log.interFoam");
  const std::string log = slurp(dir / "log.interFoam");
  EXPECT_EQ(rc, 1) << "interFoam should stop with OpenFOAM's fatal error (exit 1); see " << (dir / "log.interFoam");
  EXPECT_EQ(log.find("AddressSanitizer"), std::string::npos) << log;
  EXPECT_EQ(log.find("Segmentation fault"), std::string::npos) << log;
  EXPECT_NE(log.find("the mesh is a dynamicRefineFvMesh"), std::string::npos) << log;
  EXPECT_NE(log.find("dynamicFvMesh staticFvMesh;"), std::string::npos) << log;
  EXPECT_NE(log.find("constant/dynamicMeshDict"), std::string::npos) << log;
  // Refused before any time step: nothing was sampled.
  EXPECT_FALSE(fs::exists(dir / "postProcessing/armourSampler/storm.nc.partial"));
  // foam-proxy dict refuses the case too (its stock sets object of the eta band has died with
  // SIGFPE during refinement), and writes nothing.
  EXPECT_EQ(run(std::string(ARMOUR_FOAM_PROXY) + " dict --patches unit" + kGridArgs + " -o system/again", dir, "log.dict"), 1);
  EXPECT_NE(slurp(dir / "log.dict").find("dynamicFvMesh = dynamicRefineFvMesh"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "system/again"));
}

TEST_F(SamplerUserCases, StaticRunUnderAddressSanitizerWritesAValidStormFile) {
  const fs::path dir = caseWith("static-asan", ARMOUR_SAMPLER_ASAN_LIB);
  const int rc = run(kAsanEnv + "interFoam", dir, "log.interFoam");
  const std::string log = slurp(dir / "log.interFoam");
  ASSERT_EQ(rc, 0) << log;
  EXPECT_EQ(log.find("AddressSanitizer"), std::string::npos) << log;
  const StormReader reader((dir / "postProcessing/armourSampler/storm.nc").string());
  EXPECT_NO_THROW(reader.validateAllRecords());
  EXPECT_EQ(reader.times().size(), 4u);
  // The provenance foam-proxy writes, filled by the function object too (issue 23 item 3).
  const auto& p = reader.header().provenance;
  EXPECT_EQ(fs::path(p.sourceCase), fs::canonical(dir)) << "source_case";
  EXPECT_EQ(p.openfoamVersion, "v1912") << "openfoam_version";
  EXPECT_NE(p.command.find("interFoam"), std::string::npos) << "history: " << p.command;
  EXPECT_NE(p.command.find("armourSampler"), std::string::npos) << "history: " << p.command;
  EXPECT_EQ(p.software.rfind("armour foam-bridge armourSampler ", 0), 0u) << "source: " << p.software;
}

TEST_F(SamplerUserCases, KilledRunKeepsEveryRecordInThePartialFile) {
  const fs::path dir = caseWith("killed", ARMOUR_SAMPLER_LIB);
  replaceInFile(dir / "system/controlDict", "endTime +0.2;", "endTime 20;");
  const fs::path logFile = dir / "log.interFoam";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    if (chdir(dir.c_str()) != 0) _exit(127);
    const int fd = open(logFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    setenv("WM_PROJECT_DIR", "/usr/share/openfoam", 1);
    execlp("interFoam", "interFoam", static_cast<char*>(nullptr));
    _exit(127);
  }
  // Kill (SIGKILL: no handler, no destructor runs) once a time step after 0.2 s has started: the
  // samples at 0.05, 0.1, 0.15 and 0.2 s were appended at the end of their steps.
  const std::regex timeLine(R"(\nTime = ([0-9.eE+-]+)\n)");
  bool killed = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(300);
  while (!killed && std::chrono::steady_clock::now() < deadline) {
    // Every 2 ms: the next sample (0.25 s) is several time steps away, so the kill lands between
    // appends, not inside one (a record cut short would show as "never completed").
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const std::string log = slurp(logFile);
    double last = -1.0;
    for (std::sregex_iterator it(log.begin(), log.end(), timeLine), end; it != end; ++it) last = std::stod((*it)[1]);
    if (last > 0.2 + 1e-9) {
      kill(pid, SIGKILL);
      killed = true;
    }
    int status = 0;
    if (!killed && waitpid(pid, &status, WNOHANG) == pid) break; // ended on its own: a failure below
  }
  if (!killed) kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(killed) << "interFoam ended or did not pass t = 0.2 s; see " << logFile;
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  const fs::path partial = dir / "postProcessing/armourSampler/storm.nc.partial";
  ASSERT_TRUE(fs::exists(partial));
  EXPECT_FALSE(fs::exists(dir / "postProcessing/armourSampler/storm.nc")); // not finished: no complete-looking file
  const StormReader reader(partial.string());
  EXPECT_NO_THROW(reader.validateAllRecords());
  ASSERT_GE(reader.times().size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_NEAR(reader.times()[k], 0.05 * double(k + 1), 1e-9) << k;
  std::printf("killed after t = 0.2 s: %zu records in %s\n", reader.times().size(), partial.c_str());
}

TEST_F(SamplerUserCases, GravityNotAlongMinusZIsRefusedNamingTransformPoints) {
  const fs::path dir = caseWith("y-up", ARMOUR_SAMPLER_LIB);
  replaceInFile(dir / "constant/g", R"(value \(0 0 -9.81\);)", "value (0 -9.81 0);");
  ASSERT_NE(slurp(dir / "constant/g").find("(0 -9.81 0)"), std::string::npos);
  const int rc = run("interFoam", dir, "log.interFoam");
  const std::string log = slurp(dir / "log.interFoam");
  EXPECT_EQ(rc, 1) << log;
  EXPECT_NE(log.find("constant/g: value = (0 -9.81 0): gravity must point along -z"), std::string::npos) << log;
  EXPECT_NE(log.find("transformPoints"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "postProcessing/armourSampler/storm.nc.partial"));
  // foam-proxy refuses it too: dict (the case is the folder above system/) and sample.
  for (const std::string& command : {std::string(" dict --patches unit") + kGridArgs + " -o system/again",
                                     std::string(" sample") + kGridArgs + " -o offline.nc"}) {
    EXPECT_EQ(run(ARMOUR_FOAM_PROXY + command, dir, "log.proxy"), 1) << command;
    EXPECT_NE(slurp(dir / "log.proxy").find("constant/g: value = (0 -9.81 0): gravity must point along -z"),
              std::string::npos) << command << ": " << slurp(dir / "log.proxy");
  }
  EXPECT_FALSE(fs::exists(dir / "system/again"));
  EXPECT_FALSE(fs::exists(dir / "offline.nc"));
}

} // namespace
