// SPDX-License-Identifier: GPL-3.0-or-later
// foam-bridge end to end on OpenFOAM: the still-water case (tests/cases/stillWater, a tank with a
// box-shaped "unit" patch below the still water level z = 0.45 m) run with interFoam, serial and on
// 2 MPI ranks, sampled online by the armourSampler function object and offline by foam-proxy from
// the stock surfaces and sets function objects, next to OpenFOAM's forces function object.
// The runs are made once (SetUpTestSuite, about 15 s on 2 cores); the tests check:
//  - every sampled unit-face pressure is rho g (SWL - z) within 1 % (the tolerance);
//  - online and offline voxel statistics agree to 1e-6 relative;
//  - the force of the sampled face pressures matches the forces function object within 2 %;
//  - the storm files are readable by the solver's reader, serial and parallel.

#include "storm/StormFile.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;
using armour::storm::StormReader;
using armour::storm::StormRecord;

namespace {

constexpr double kRho = 1000.0;       // water density of the case (kg/m^3)
constexpr double kG = 9.81;           // |g| (m/s^2)
constexpr double kSwl = 0.45;         // still water level (m)

const fs::path kCase = fs::path(ARMOUR_FOAM_BRIDGE_DIR) / "tests/cases/stillWater";
const fs::path kWork = fs::path(ARMOUR_FOAM_BRIDGE_WORK) / "still-water";

// The grid is offset from the 0.025 m mesh so that no face centre lies on a voxel face (a centre on
// a face could fall on either side by round-off, online and offline).
const char* kGridArgs =
    " --x-min 0.17 --z-min 0.12 --dx 0.05 --dz 0.05 --nx 6 --nz 6 --trunk-origin 0 --trunk-length 0.3"
    " --swl 0.45 --rho 1000 --eta-plane-y 0.1625 --eta-half-width 0.0125";

std::string run(const std::string& command, const fs::path& dir, const std::string& log) {
  const std::string full = "cd '" + dir.string() + "' && WM_PROJECT_DIR=/usr/share/openfoam " + command + " > '" +
                           log + "' 2>&1";
  const int rc = std::system(full.c_str());
  if (rc != 0) return "'" + command + "' failed in " + dir.string() + " (see " + (dir / log).string() + ")";
  return "";
}

struct Runs {
  std::string error;
};
Runs runs;

std::vector<std::vector<double>> readTable(const fs::path& file, char separator) {
  std::ifstream in(file);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || std::isalpha(static_cast<unsigned char>(line[0]))) continue;
    for (char& c : line)
      if (c == separator || c == '(' || c == ')' || c == '\t') c = ' ';
    std::istringstream s(line);
    std::vector<double> row;
    double v;
    while (s >> v) row.push_back(v);
    if (!row.empty()) rows.push_back(row);
  }
  return rows;
}

/// Largest |a - b| over the data voxels of two records, relative to the largest |a| of the
/// variable in the record (velocities of still water are ~1e-6 m/s of noise: relative to their own
/// largest value, not to zero).
double relativeDifference(const std::vector<double>& a, const std::vector<double>& b,
                          const std::vector<std::int32_t>& samples) {
  double scale = 0.0, diff = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (samples[i] <= 0) continue;
    scale = std::max(scale, std::abs(a[i]));
    diff = std::max(diff, std::abs(a[i] - b[i]));
  }
  return scale > 0.0 ? diff / scale : diff;
}

void expectSameStatistics(const fs::path& online, const fs::path& offline, double tolerance, bool velocities = true,
                          double etaTolerance = 1e-9, bool variability = true) {
  const StormReader a(online.string()), b(offline.string());
  ASSERT_EQ(a.header().samples, b.header().samples);
  ASSERT_EQ(a.times().size(), b.times().size());
  StormRecord ra, rb;
  double worst = 0.0;
  for (std::size_t k = 0; k < a.times().size(); ++k) {
    EXPECT_NEAR(a.times()[k], b.times()[k], 1e-9);
    a.read(k, ra);
    b.read(k, rb);
    for (const auto& [name, x, y] : {std::tuple{"p", &ra.p, &rb.p}, std::tuple{"u", &ra.u, &rb.u},
                                     std::tuple{"v", &ra.v, &rb.v}, std::tuple{"w", &ra.w, &rb.w},
                                     std::tuple{"alpha", &ra.alpha, &rb.alpha}}) {
      if (!velocities && std::string(name) != "p" && std::string(name) != "alpha") continue;
      const double d = relativeDifference(*x, *y, a.header().samples);
      worst = std::max(worst, d);
      EXPECT_LE(d, tolerance) << name << " at t = " << a.times()[k] << " s";
    }
    for (std::size_t i = 0; i < ra.eta.size(); ++i) EXPECT_NEAR(ra.eta[i], rb.eta[i], etaTolerance) << "eta column " << i;
  }
  std::printf("%s vs %s: largest relative difference %.3g\n", online.filename().c_str(), offline.filename().c_str(), worst);
  if (!variability) return;
  const auto& va = a.header().variability;
  const auto& vb = b.header().variability;
  ASSERT_EQ(va.present, vb.present);
  for (std::size_t c = 0; c < va.classes.size(); ++c) {
    EXPECT_EQ(va.classes[c].samples, vb.classes[c].samples) << c;
    // A deviation computed from float-rounded pressures (the VTK files hold floats) can fall into
    // the neighbouring 1.16 % bin; one such move changes a fit by ~1e-5.
    EXPECT_NEAR(va.classes[c].shape, vb.classes[c].shape, 1e-3 * va.classes[c].shape) << c;
    EXPECT_NEAR(va.classes[c].scale, vb.classes[c].scale, 1e-3 * va.classes[c].scale + 1e-300) << c;
  }
}

} // namespace

class StillWater : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    fs::remove_all(kWork);
    fs::create_directories(kWork);
    const fs::path serial = kWork / "serial", parallel = kWork / "parallel";
    fs::copy(kCase, serial, fs::copy_options::recursive);
    // The function objects, from foam-proxy dict, with the sampler's per-face debug output. The
    // surfaces in binary VTK (float, with the polygons): the offline pressure force needs the face
    // areas; the raw (double) format is checked by cases.nwt3d.sampled.
    runs.error = run(std::string(ARMOUR_FOAM_PROXY) + " dict --surface-format vtk --patches unit --sampler-library " + ARMOUR_SAMPLER_LIB +
                         kGridArgs + " -o system/armourFunctions", serial, "log.dict");
    if (!runs.error.empty()) return;
    {
      std::ifstream in(serial / "system/armourFunctions");
      std::stringstream text;
      text << in.rdbuf();
      std::string s = text.str();
      const std::string key = "type            armourSampler;\n";
      s.insert(s.find(key) + key.size(), "        doublePrecision true;\n        debugFaceFile \"postProcessing/armourSampler/faces.txt\";\n");
      std::ofstream(serial / "system/armourFunctions") << s;
    }
    fs::copy(serial / "0.orig", serial / "0", fs::copy_options::recursive);
    for (const char* step : {"blockMesh", "setFields"}) {
      runs.error = run(step, serial, std::string("log.") + step);
      if (!runs.error.empty()) return;
    }
    fs::copy(serial, parallel, fs::copy_options::recursive);
    runs.error = run("interFoam", serial, "log.interFoam");
    if (!runs.error.empty()) return;
    const std::string proxy = std::string(ARMOUR_FOAM_PROXY) + " sample --double" + kGridArgs;
    runs.error = run(proxy + " -o offline.nc --forces-csv offline-force.csv", serial, "log.proxy");
    if (!runs.error.empty()) return;
    runs.error = run("decomposePar", parallel, "log.decomposePar");
    if (!runs.error.empty()) return;
    const std::string mpi = std::string("mpirun -np 2 --oversubscribe ") + (geteuid() == 0 ? "--allow-run-as-root " : "") +
                            "-x WM_PROJECT_DIR interFoam -parallel";
    runs.error = run(mpi, parallel, "log.interFoam");
    if (!runs.error.empty()) return;
    runs.error = run(proxy + " -o offline.nc --forces-csv offline-force.csv", parallel, "log.proxy");
  }
  void SetUp() override { ASSERT_TRUE(runs.error.empty()) << runs.error; }
};

TEST_F(StillWater, EveryUnitFacePressureIsHydrostatic) {
  // time x y z p alpha per face and record; every unit face is below the still water level.
  const auto rows = readTable(kWork / "serial/postProcessing/armourSampler/faces.txt", ' ');
  ASSERT_EQ(rows.size(), 256u * 4u); // 256 faces of the box, 4 records (0.05 to 0.2 s)
  double worst = 0.0;
  for (const auto& r : rows) {
    const double expected = kRho * kG * (kSwl - r[3]);
    worst = std::max(worst, std::abs(r[4] - expected) / expected);
    EXPECT_NEAR(r[4], expected, 0.01 * expected) << "face at (" << r[1] << ", " << r[2] << ", " << r[3] << ") t = " << r[0];
    EXPECT_GT(r[5], 0.999); // submerged
  }
  std::printf("largest relative deviation from rho g (SWL - z): %.3g\n", worst);
}

TEST_F(StillWater, OnlineAndOfflineStatisticsAgree) {
  expectSameStatistics(kWork / "serial/postProcessing/armourSampler/storm.nc", kWork / "serial/offline.nc", 1e-6);
  expectSameStatistics(kWork / "parallel/postProcessing/armourSampler/storm.nc", kWork / "parallel/offline.nc", 1e-6);
}

TEST_F(StillWater, ParallelRunGivesTheSameStatistics) {
  // Not the same run: the linear solvers converge differently on 2 ranks (p_rgh to 1e-8 of its
  // residual), so p and alpha to 1e-5 of the largest value; the velocities of still water are
  // spurious currents of 1e-7 m/s that differ completely between the runs and are not compared;
  // eta to 1e-6 m (alpha of the air cell above the surface, ~1e-7, differs between the runs), and
  // not the variability: the phase of calm water (the sign of eta ~ 1e-8 m) is noise.
  expectSameStatistics(kWork / "serial/postProcessing/armourSampler/storm.nc",
                       kWork / "parallel/postProcessing/armourSampler/storm.nc", 1e-5, false, 1e-6, false);
}

TEST_F(StillWater, SampledPressureForceMatchesForcesFunctionObject) {
  for (const char* dir : {"serial", "parallel"}) {
    const auto forces = readTable(kWork / dir / "postProcessing/unitForces/0/force.dat", ' ');
    const auto online = readTable(kWork / dir / "postProcessing/armourSampler/storm-pressure-force.csv", ',');
    const auto offline = readTable(kWork / dir / "offline-force.csv", ',');
    ASSERT_EQ(forces.size(), 4u) << dir;
    ASSERT_EQ(online.size(), forces.size()) << dir;
    ASSERT_EQ(offline.size(), forces.size()) << dir;
    // Buoyancy of the 0.2 x 0.1 x 0.2 m box: rho g V = 39.24 N up.
    for (std::size_t k = 0; k < forces.size(); ++k) {
      const double fx = forces[k][4], fy = forces[k][5], fz = forces[k][6]; // the pressure force
      const double mag = std::sqrt(fx * fx + fy * fy + fz * fz);
      EXPECT_NEAR(fz, kRho * kG * 0.2 * 0.1 * 0.2, 0.01 * 39.24) << dir;
      for (const auto* mine : {&online[k], &offline[k]}) {
        EXPECT_NEAR((*mine)[0], forces[k][0], 1e-9) << dir;
        const double d = std::sqrt(std::pow((*mine)[1] - fx, 2) + std::pow((*mine)[2] - fy, 2) + std::pow((*mine)[3] - fz, 2));
        EXPECT_LE(d, 0.02 * mag) << dir << " t = " << forces[k][0];
      }
      std::printf("%s t = %g s: forces %.10g N, armourSampler %.10g N, foam-proxy %.10g N\n", dir, forces[k][0], fz,
                  online[k][3], offline[k][3]);
    }
  }
}

TEST_F(StillWater, StormFilesAreReadableBySolver) {
  for (const char* file : {"serial/postProcessing/armourSampler/storm.nc", "parallel/postProcessing/armourSampler/storm.nc",
                           "serial/offline.nc"}) {
    const StormReader reader((kWork / file).string());
    EXPECT_NO_THROW(reader.validateAllRecords()) << file;
    EXPECT_EQ(reader.times().size(), 4u);
    int voxels = 0;
    for (std::int32_t m : reader.header().samples) voxels += m > 0;
    EXPECT_EQ(voxels, 25) << file; // the box's 0.2 x 0.2 m side spans 5 x 5 voxels of the grid
    EXPECT_TRUE(reader.header().variability.present) << file;
    EXPECT_TRUE(reader.header().hasVelocityY);
  }
}
