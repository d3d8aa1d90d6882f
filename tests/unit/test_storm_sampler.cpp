// SPDX-License-Identifier: GPL-3.0-or-later
// StormSampler: exact linear-in-time, bilinear-in-space interpolation of the storm file, the edge
// and gap rules, the time derivative, and the wave phase from the zero crossings of eta
// (docs/storm-file.md, "Sampling").

#include "core/Error.hpp"
#include "storm/StormSampler.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace armour::storm;

namespace {

/// A grid of 5 x 4 voxels, dx = 0.5 m, dz = 0.25 m, offset from the origin so that a mix-up of
/// index and coordinate shows.
StormHeader makeHeader(std::size_t nx = 5, std::size_t nz = 4, double dx = 0.5, double dz = 0.25) {
  StormHeader h;
  for (std::size_t i = 0; i < nx; ++i) {
    h.x.push_back(12.25 + dx * static_cast<double>(i));
  }
  for (std::size_t j = 0; j < nz; ++j) {
    h.z.push_back(-3.0 + dz * static_cast<double>(j));
  }
  h.samples.assign(h.voxels(), 1);
  h.trunkLength = 44.5;
  h.hasVelocityY = true;
  return h;
}

/// Field values per voxel and time, one function per variable (alpha must stay in [0, 1]).
struct Fields {
  std::function<double(double, double, double)> p, u, v, w, alpha, eta;
};

/// Non-uniform record times: the interpolation must not assume a constant record interval.
std::vector<double> recordTimes(std::size_t n) {
  std::vector<double> t;
  for (std::size_t k = 0; k < n; ++k) {
    const double kk = static_cast<double>(k);
    t.push_back(100.0 + 0.1 * kk + 0.003 * kk * kk);
  }
  return t;
}

class StormSamplerTest : public ::testing::Test {
protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("armour_storm_sampler_{}_{}", info->name(), ::getpid());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Write the fields at the given times, stored in double so the file adds no rounding.
  std::string write(const StormHeader& h, const Fields& f, const std::vector<double>& times) {
    const auto path = (dir_ / fmt::format("storm{}.nc", files_++)).string();
    StormWriteOptions options;
    options.doublePrecision = true;
    StormWriter writer(path, h, options);
    for (double t : times) {
      StormRecord r;
      r.time = t;
      for (std::size_t i = 0; i < h.voxels(); ++i) {
        const double x = h.x[i % h.nx()];
        const double z = h.z[i / h.nx()];
        r.p.push_back(f.p(x, z, t));
        r.u.push_back(f.u(x, z, t));
        if (h.hasVelocityY) {
          r.v.push_back(f.v(x, z, t));
        }
        r.w.push_back(f.w(x, z, t));
        r.alpha.push_back(f.alpha(x, z, t));
      }
      for (double x : h.x) {
        r.eta.push_back(f.eta(x, 0.0, t));
      }
      writer.append(r);
    }
    writer.finish();
    return path;
  }

  fs::path dir_;
  int files_ = 0;
};

Fields linearFields() {
  Fields f;
  f.p = [](double x, double z, double t) { return 3.0 + 2.5 * x - 7.0 * z + 1.5 * t; };
  f.u = [](double x, double z, double t) { return -1.0 + 0.3 * x + 0.7 * z - 0.02 * t; };
  f.v = [](double x, double z, double t) { return 0.1 - 0.05 * x + 0.2 * z + 0.01 * t; };
  f.w = [](double x, double z, double t) { return 0.4 * x - 0.3 * z + 0.03 * t; };
  f.alpha = [](double x, double z, double t) { return 0.5 + 0.02 * (x - 13.0) + 0.03 * z + 0.001 * (t - 100.0); };
  f.eta = [](double x, double, double t) { return 0.1 * x - 0.05 * t; };
  return f;
}

/// Round-off of the interpolation: a few ulps of the values (|p| < 60 here) per operation; 1e-12
/// relative to max(1, |value|) is ~50 ulps, far below any interpolation error (which would be
/// O(dx^2 f'') = O(0.1) for a non-exact scheme on a curved field).
constexpr double kExact = 1e-12;
double tolerance(double value) { return kExact * std::max(1.0, std::abs(value)); }

} // namespace

TEST_F(StormSamplerTest, LinearFieldIsReproducedExactly) {
  const auto h = makeHeader();
  const auto f = linearFields();
  const auto times = recordTimes(12);
  StormReader reader(write(h, f, times));
  StormSampler sampler(reader);
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> ux(h.x.front(), h.x.back());
  std::uniform_real_distribution<double> uz(h.z.front(), h.z.back());
  std::uniform_real_distribution<double> ut(times.front(), times.back());
  for (int step = 0; step < 200; ++step) {
    // Random times (forwards and backwards) exercise every way the two held records are replaced.
    const double t = step % 10 == 0 ? times[static_cast<std::size_t>(step / 10) % times.size()] : ut(rng);
    sampler.setTime(t);
    EXPECT_EQ(sampler.time(), t);
    for (int point = 0; point < 10; ++point) {
      const double x = ux(rng);
      const double z = uz(rng);
      const auto s = sampler.sample(x, z);
      ASSERT_TRUE(s.valid) << x << ", " << z;
      EXPECT_NEAR(s.p, f.p(x, z, t), tolerance(s.p));
      EXPECT_NEAR(s.u, f.u(x, z, t), tolerance(s.u));
      EXPECT_NEAR(s.v, f.v(x, z, t), tolerance(s.v));
      EXPECT_NEAR(s.w, f.w(x, z, t), tolerance(s.w));
      EXPECT_NEAR(s.alpha, f.alpha(x, z, t), tolerance(s.alpha));
    }
  }
}

TEST_F(StormSamplerTest, BilinearFieldIsReproducedExactly) {
  // x z is bilinear: reproduced exactly inside every cell (a scheme that is only linear, e.g.
  // triangles, would miss it by up to dx dz / 4 = 0.03).
  const auto h = makeHeader();
  auto f = linearFields();
  f.p = [](double x, double z, double t) { return x * z + 0.5 * t; };
  const auto times = recordTimes(3);
  StormReader reader(write(h, f, times));
  StormSampler sampler(reader);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ux(h.x.front(), h.x.back());
  std::uniform_real_distribution<double> uz(h.z.front(), h.z.back());
  const double t = 0.3 * times[1] + 0.7 * times[2];
  sampler.setTime(t);
  for (int point = 0; point < 500; ++point) {
    const double x = ux(rng);
    const double z = uz(rng);
    const auto s = sampler.sample(x, z);
    ASSERT_TRUE(s.valid);
    EXPECT_NEAR(s.p, x * z + 0.5 * t, tolerance(s.p));
  }
}

TEST_F(StormSamplerTest, EdgeValueHeldWithinHalfAVoxelAndInvalidBeyond) {
  const auto h = makeHeader();
  const auto f = linearFields();
  const auto times = recordTimes(3);
  StormReader reader(write(h, f, times));
  StormSampler sampler(reader);
  const double t = times[1];
  sampler.setTime(t);
  const double dx = h.dx();
  const double dz = h.dz();
  const double zMid = 0.5 * (h.z[1] + h.z[2]);
  const double xMid = 0.5 * (h.x[2] + h.x[3]);
  // Within half a voxel outside: the value at the edge centre line (the linear field is NOT
  // extrapolated, so the test would fail if it were).
  for (double frac : {0.01, 0.3, 0.5}) {
    const auto left = sampler.sample(h.x.front() - frac * dx, zMid);
    ASSERT_TRUE(left.valid) << frac;
    EXPECT_NEAR(left.p, f.p(h.x.front(), zMid, t), tolerance(left.p));
    const auto right = sampler.sample(h.x.back() + frac * dx, zMid);
    ASSERT_TRUE(right.valid);
    EXPECT_NEAR(right.u, f.u(h.x.back(), zMid, t), tolerance(right.u));
    const auto bottom = sampler.sample(xMid, h.z.front() - frac * dz);
    ASSERT_TRUE(bottom.valid);
    EXPECT_NEAR(bottom.w, f.w(xMid, h.z.front(), t), tolerance(bottom.w));
    const auto corner = sampler.sample(h.x.back() + frac * dx, h.z.back() + frac * dz);
    ASSERT_TRUE(corner.valid);
    EXPECT_NEAR(corner.p, f.p(h.x.back(), h.z.back(), t), tolerance(corner.p));
  }
  // Beyond half a voxel: outside, values zero.
  for (const auto& [x, z] : std::vector<std::pair<double, double>>{{h.x.front() - 0.51 * dx, zMid},
                                                                   {h.x.back() + 0.51 * dx, zMid},
                                                                   {xMid, h.z.front() - 0.51 * dz},
                                                                   {xMid, h.z.back() + 0.51 * dz},
                                                                   {1e6, zMid},
                                                                   {std::nan(""), zMid},
                                                                   {xMid, std::nan("")}}) {
    const auto s = sampler.sample(x, z);
    EXPECT_FALSE(s.valid) << x << ", " << z;
    EXPECT_EQ(s.p, 0.0);
    EXPECT_EQ(s.alpha, 0.0);
    EXPECT_FALSE(sampler.rate(x, z).valid);
  }
}

TEST_F(StormSamplerTest, CornersWithoutDataAreDroppedAndTheRestRenormalised) {
  auto h = makeHeader();
  // Voxel (ix 1, iz 1) has no data; the whole cell block ix 3..4, iz 2..3 has none either.
  const auto at = [&](std::size_t ix, std::size_t iz) { return iz * h.nx() + ix; };
  h.samples[at(1, 1)] = 0;
  for (std::size_t ix = 3; ix <= 4; ++ix) {
    for (std::size_t iz = 2; iz <= 3; ++iz) {
      h.samples[at(ix, iz)] = 0;
    }
  }
  auto f = linearFields();
  // A curved field, so that the mean of the corners differs from the value at the cell centre.
  f.p = [](double x, double z, double) { return x * x + 10.0 * z * z * z; };
  const auto times = recordTimes(3);
  StormReader reader(write(h, f, times));
  StormSampler sampler(reader);
  sampler.setTime(times[0]);

  // The centre of the cell ix 0..1, iz 0..1: equal weights 1/4, one corner (1, 1) dropped: the mean
  // of the other three.
  const double xc = 0.5 * (h.x[0] + h.x[1]);
  const double zc = 0.5 * (h.z[0] + h.z[1]);
  const double mean3 = (f.p(h.x[0], h.z[0], 0) + f.p(h.x[1], h.z[0], 0) + f.p(h.x[0], h.z[1], 0)) / 3.0;
  const auto s = sampler.sample(xc, zc);
  ASSERT_TRUE(s.valid);
  EXPECT_NEAR(s.p, mean3, tolerance(mean3));
  // Not the plain bilinear value with the dropped corner (which the reader gives as NaN anyway).
  EXPECT_GT(std::abs(s.p - (mean3 * 3.0 + f.p(h.x[1], h.z[1], 0)) / 4.0), 1e-3);

  // An off-centre point: weights (1-tx)(1-tz), tx(1-tz), (1-tx)tz renormalised by their sum.
  const double tx = 0.2, tz = 0.7;
  const double x = h.x[0] + tx * h.dx();
  const double z = h.z[0] + tz * h.dz();
  const double w00 = (1 - tx) * (1 - tz), w10 = tx * (1 - tz), w01 = (1 - tx) * tz;
  const double expected =
      (w00 * f.p(h.x[0], h.z[0], 0) + w10 * f.p(h.x[1], h.z[0], 0) + w01 * f.p(h.x[0], h.z[1], 0)) / (w00 + w10 + w01);
  EXPECT_NEAR(sampler.sample(x, z).p, expected, tolerance(expected));

  // Inside the block without data: no corner left.
  EXPECT_FALSE(sampler.sample(0.5 * (h.x[3] + h.x[4]), 0.5 * (h.z[2] + h.z[3])).valid);
  // At the centre of the isolated empty voxel every weight falls on it: no data there either.
  EXPECT_FALSE(sampler.sample(h.x[1], h.z[1]).valid);
  // ... but a hair away the neighbours take over, and the value is theirs (continuity).
  const auto near = sampler.sample(h.x[1] + 1e-9, h.z[1]);
  ASSERT_TRUE(near.valid);
  EXPECT_NEAR(near.p, f.p(h.x[2], h.z[1], 0), 1e-6);
}

TEST_F(StormSamplerTest, GapFillIsStillWaterUnderTheFreeSurfaceMovingWithTheNearestWetData) {
  // 5 x 8 voxels (z from -3 to -1.25 m), still water level -2 m; the block ix 3..4, iz 4..7 has no
  // data. Water (alpha 1) only below z = -2.6 m in the file's voxels, so in column 4 the nearest
  // voxels with data to the block (iz 3, 2: z -2.25, -2.5) are dry and the fill's flow comes from
  // iz 1 (z -2.75). Fields linear in t, eta linear in x and t: the fill is exact.
  auto h = makeHeader(5, 8);
  h.stillWaterLevel = -2.0;
  h.waterDensity = 1025.0;
  h.gravity = 9.81;
  const auto at = [&](std::size_t ix, std::size_t iz) { return iz * h.nx() + ix; };
  for (std::size_t ix = 3; ix <= 4; ++ix) {
    for (std::size_t iz = 4; iz <= 7; ++iz) {
      h.samples[at(ix, iz)] = 0;
    }
  }
  auto f = linearFields();
  f.alpha = [](double, double z, double) { return z < -2.6 ? 1.0 : 0.0; };
  f.eta = [](double x, double, double t) { return 0.1 * (x - 13.0) + 0.2 + 0.05 * (t - 100.0); };
  const auto times = recordTimes(3);
  StormReader reader(write(h, f, times));
  StormSampler sampler(reader);
  EXPECT_TRUE(sampler.hasGaps());
  const double t = 0.5 * (times[0] + times[1]);
  sampler.setTime(t);
  const double rhoG = 1025.0 * 9.81;

  // Wet: x 14.1 (between columns 3 and 4), z -1.9 (between iz 4 and 5): all four corners empty,
  // all below the surface; the fill is linear in x and z, so its bilinear value is exact: the
  // hydrostatic pressure under the surface at -2 + eta(14.1, t).
  const double x = 14.1, z = -1.9;
  const double surface = -2.0 + f.eta(x, 0.0, t);
  ASSERT_LT(z, surface);
  EXPECT_FALSE(sampler.sample(x, z).valid); // sample() keeps its contract
  const auto wet = sampler.sampleExtended(x, z);
  ASSERT_TRUE(wet.valid);
  EXPECT_TRUE(wet.filled);
  EXPECT_EQ(wet.alpha, 1.0);
  EXPECT_NEAR(wet.p, rhoG * (surface - z), tolerance(rhoG));
  // Each corner moves with iz 1 of its column; between the columns, linearly.
  EXPECT_NEAR(wet.u, f.u(x, h.z[1], t), tolerance(1.0));
  EXPECT_NEAR(wet.v, f.v(x, h.z[1], t), tolerance(1.0));
  EXPECT_NEAR(wet.w, f.w(x, h.z[1], t), tolerance(1.0));
  const auto rate = sampler.rateExtended(x, z);
  ASSERT_TRUE(rate.valid && rate.filled);
  EXPECT_NEAR(rate.p, rhoG * 0.05, tolerance(rhoG));
  EXPECT_NEAR(rate.u, -0.02, kExact);
  EXPECT_NEAR(rate.v, 0.01, kExact);
  EXPECT_NEAR(rate.w, 0.03, kExact);

  // Dry: above the surface in the same block: air, no flow.
  const auto dry = sampler.sampleExtended(x, -1.3);
  ASSERT_GT(-1.3, -2.0 + f.eta(x, 0.0, t));
  EXPECT_TRUE(dry.valid && dry.filled);
  EXPECT_EQ(dry.alpha, 0.0);
  EXPECT_EQ(dry.p, 0.0);
  EXPECT_EQ(dry.u, 0.0);

  // Half data, half fill: between iz 3 (data) and iz 4 (empty) of columns 3 and 4, each corner
  // weighted as bilinear interpolation weights it (no renormalisation).
  {
    const double xm = 14.1, zm = -2.1, tx = (xm - h.x[3]) / h.dx(), tz = (zm - h.z[3]) / h.dz();
    const auto fillP = [&](std::size_t ix) { return rhoG * (-2.0 + f.eta(h.x[ix], 0.0, t) - h.z[4]); };
    const double expected = (1 - tx) * (1 - tz) * f.p(h.x[3], h.z[3], t) + tx * (1 - tz) * f.p(h.x[4], h.z[3], t) +
                            (1 - tx) * tz * fillP(3) + tx * tz * fillP(4);
    const auto mixed = sampler.sampleExtended(xm, zm);
    EXPECT_TRUE(mixed.valid && mixed.filled);
    EXPECT_NEAR(mixed.p, expected, tolerance(expected));
    EXPECT_NEAR(mixed.alpha, tz, kExact); // data corners dry (z > -2.6), filled ones wet
  }

  // With data at every corner the file's value, bit for bit; a NaN coordinate gives nothing.
  const double xd = 0.5 * (h.x[0] + h.x[1]), zd = -2.1;
  const auto data = sampler.sampleExtended(xd, zd);
  EXPECT_FALSE(data.filled);
  EXPECT_EQ(data.p, sampler.sample(xd, zd).p);
  EXPECT_EQ(data.u, sampler.sample(xd, zd).u);
  EXPECT_FALSE(sampler.rateExtended(std::nan(""), z).valid);
  EXPECT_FALSE(sampler.sampleExtended(xd, std::nan("")).valid);

  // A file with data everywhere has no gaps.
  StormReader full(write(makeHeader(), linearFields(), times));
  EXPECT_FALSE(StormSampler(full).hasGaps());
}

TEST_F(StormSamplerTest, BeyondTheGridTheEdgeColumnIsHeldAndTheEdgeRowGoesOnHydrostatically) {
  // The water goes on beyond the sampling box: any distance beyond the outermost columns gives the
  // edge column's flow; beyond the outermost rows the pressure changes by rho g per metre from the
  // edge row's (alpha and velocity held), and above the top row it reaches air where it is gone.
  auto h = makeHeader();
  h.waterDensity = 1025.0;
  h.gravity = 9.81;
  const double rhoG = 1025.0 * 9.81;
  auto f = linearFields();
  f.p = [](double x, double z, double t) { return 20000.0 + 100.0 * x - 300.0 * z + 50.0 * (t - 100.0); };
  f.alpha = [](double, double, double) { return 1.0; };
  const auto times = recordTimes(3);
  StormReader reader(write(h, f, times));
  StormSampler sampler(reader);
  const double t = 0.3 * times[0] + 0.7 * times[1];
  sampler.setTime(t);
  const double zMid = 0.5 * (h.z[1] + h.z[2]);
  for (const double x : {h.x.front() - 0.1, h.x.front() - 40.0}) {
    const auto s = sampler.sampleExtended(x, zMid);
    ASSERT_TRUE(s.valid) << x;
    EXPECT_EQ(s.p, sampler.sample(h.x.front(), zMid).p) << x;
    EXPECT_EQ(s.u, sampler.sample(h.x.front(), zMid).u) << x;
  }
  EXPECT_EQ(sampler.sampleExtended(h.x.back() + 1e3, zMid).w, sampler.sample(h.x.back(), zMid).w);
  const double x = 0.5 * (h.x[1] + h.x[2]);
  // Below the bottom row: 2 m deeper, rho g 2 m more; the rate is the edge row's.
  const auto below = sampler.sampleExtended(x, h.z.front() - 2.0);
  const auto edge = sampler.sample(x, h.z.front());
  EXPECT_NEAR(below.p, edge.p + rhoG * 2.0, tolerance(below.p));
  EXPECT_EQ(below.u, edge.u);
  EXPECT_EQ(below.alpha, 1.0);
  EXPECT_NEAR(sampler.rateExtended(x, h.z.front() - 2.0).p, 50.0, 1e-9);
  // Above the top row: less by rho g per metre while any is left, then air.
  const double top = h.z.back();
  const double pTop = sampler.sample(x, top).p;
  const double reach = pTop / rhoG; // where the continued pressure reaches 0
  ASSERT_GT(reach, 1.0);
  const auto above = sampler.sampleExtended(x, top + 0.5 * reach);
  EXPECT_NEAR(above.p, 0.5 * pTop, tolerance(pTop));
  EXPECT_EQ(above.alpha, 1.0);
  const auto air = sampler.sampleExtended(x, top + 1.01 * reach);
  EXPECT_TRUE(air.valid);
  EXPECT_EQ(air.p, 0.0);
  EXPECT_EQ(air.alpha, 0.0);
  EXPECT_EQ(air.u, 0.0);
  EXPECT_EQ(sampler.rateExtended(x, top + 1.01 * reach).u, 0.0);
}

TEST_F(StormSamplerTest, SetTimeOutsideTheRecordsThrowsNamingFileAndRange) {
  const auto h = makeHeader();
  const auto times = recordTimes(4);
  const auto path = write(h, linearFields(), times);
  StormReader reader(path);
  StormSampler sampler(reader);
  EXPECT_NO_THROW(sampler.setTime(times.front()));
  EXPECT_NO_THROW(sampler.setTime(times.back()));
  for (double t : {times.front() - 1e-9, times.back() + 0.5, std::nan("")}) {
    try {
      sampler.setTime(t);
      ADD_FAILURE() << "no error for t = " << t;
    } catch (const armour::core::InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path), std::string::npos) << message;
      EXPECT_NE(message.find(fmt::format("[{}, {}] s", times.front(), times.back())), std::string::npos) << message;
    }
  }
}

TEST_F(StormSamplerTest, RateOfAFieldLinearInTimeIsItsSlope) {
  const auto h = makeHeader();
  const auto f = linearFields();
  const auto times = recordTimes(6);
  StormReader reader(write(h, f, times));
  StormSampler sampler(reader);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ut(times.front(), times.back());
  for (int step = 0; step < 50; ++step) {
    sampler.setTime(ut(rng));
    const auto r = sampler.rate(12.9, -2.6);
    ASSERT_TRUE(r.valid);
    // (b - a) / dt of values ~50 with dt >= 0.1 s: round-off ~ 1e-14 / 0.1.
    EXPECT_NEAR(r.p, 1.5, 1e-11);
    EXPECT_NEAR(r.u, -0.02, 1e-11);
    EXPECT_NEAR(r.v, 0.01, 1e-11);
    EXPECT_NEAR(r.w, 0.03, 1e-11);
    EXPECT_NEAR(r.alpha, 0.001, 1e-11);
  }
  // A field quadratic in t: the rate is the chord slope of the bracketing records, not the
  // derivative at t.
  auto g = linearFields();
  g.u = [](double, double, double t) { return (t - 100.0) * (t - 100.0); };
  StormReader quadratic(write(h, g, times));
  StormSampler s2(quadratic);
  const double t = 0.25 * times[2] + 0.75 * times[3];
  s2.setTime(t);
  const double chord = (g.u(0, 0, times[3]) - g.u(0, 0, times[2])) / (times[3] - times[2]);
  EXPECT_NEAR(s2.rate(13.0, -2.5).u, chord, 1e-11);
}

TEST_F(StormSamplerTest, PhaseFromZeroCrossingsOfASine) {
  // eta = a sin(2 pi t / T) in every column. Records every dt from t0 = 0.0003 s (so that no record
  // falls on a crossing) over 2.5 periods. Crossings at k T / 2. The chord through the two records
  // around a zero of a sine misses it by at most ~ omega^2 dt^3 / 60 = 0.6 * 8e-9 / 60 < 1e-10 (the
  // sine has no curvature at its zeros), so the crossing times are checked to 1e-9.
  auto h = makeHeader(3, 2, 0.5, 0.25);
  h.hasVelocityY = false;
  const double a = 1.3, period = 8.0, dt = 0.002;
  const double omega = 2.0 * std::numbers::pi / period;
  std::vector<double> times;
  for (double t = 0.0003; t < 2.5 * period; t += dt) {
    times.push_back(t);
  }
  auto f = linearFields();
  f.eta = [&](double, double, double t) { return a * std::sin(omega * t); };
  StormReader reader(write(h, f, times));
  StormSampler sampler(reader);

  for (double x : {h.x[0], h.x[1], h.x[2], h.x[0] - 10.0, h.x[2] + 10.0}) {
    for (int k = 1; k <= 4; ++k) {
      const double crossing = 0.5 * period * k;
      sampler.setTime(crossing - 1e-9);
      const auto before = sampler.phase(x);
      sampler.setTime(crossing + 1e-9);
      const auto after = sampler.phase(x);
      EXPECT_EQ(before.halfWave, k - 1) << "crossing " << k << " at x = " << x;
      EXPECT_EQ(after.halfWave, k) << "crossing " << k << " at x = " << x;
      // Half wave 0 starts in a crest (sin > 0 after t = 0): even half waves are crests.
      EXPECT_EQ(before.crest, (k - 1) % 2 == 0);
      EXPECT_EQ(after.crest, k % 2 == 0);
    }
  }
  // Between crossings: the elevation is the linear interpolation of the records, within
  // a omega^2 dt^2 / 8 = 4e-7 m of the sine.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> ut(times.front(), times.back());
  for (int i = 0; i < 200; ++i) {
    const double t = ut(rng);
    sampler.setTime(t);
    const auto ph = sampler.phase(h.x[1]);
    EXPECT_NEAR(ph.elevation, a * std::sin(omega * t), 1e-6);
    const auto expectedHalfWave = static_cast<std::int64_t>(std::floor(t / (0.5 * period)));
    if (std::abs(t / (0.5 * period) - std::round(t / (0.5 * period))) > 1e-6) { // away from a crossing
      EXPECT_EQ(ph.halfWave, expectedHalfWave) << t;
      EXPECT_EQ(ph.crest, expectedHalfWave % 2 == 0) << t;
    }
  }
}

TEST_F(StormSamplerTest, PhaseColumnsAreIndependent) {
  // A wave travelling in x: the columns cross zero at different times, and phase(x) uses the
  // nearest column.
  auto h = makeHeader(4, 2, 1.0, 0.25);
  h.hasVelocityY = false;
  const double period = 4.0, dt = 0.01, c = 2.0; // celerity (m/s): column i lags by i dx / c
  const double omega = 2.0 * std::numbers::pi / period;
  std::vector<double> times;
  for (double t = 0.005; t < 3.0 * period; t += dt) {
    times.push_back(t);
  }
  auto f = linearFields();
  const double x0 = h.x[0];
  f.eta = [&](double x, double, double t) { return std::sin(omega * (t - (x - x0) / c)); };
  StormReader reader(write(h, f, times));
  StormSampler sampler(reader);
  const double t = 5.3;
  sampler.setTime(t);
  for (std::size_t i = 0; i < h.nx(); ++i) {
    const double lagged = t - (h.x[i] - x0) / c; // the column's own clock
    // Crossings inside the record span only: the first record is at 0.005 s, so a column whose
    // eta is negative there has its first crossing later.
    const double start = times.front() - (h.x[i] - x0) / c;
    const auto countBefore = [&](double s) { return static_cast<std::int64_t>(std::floor(s / (0.5 * period))); };
    const auto expected = countBefore(lagged) - countBefore(start);
    const auto ph = sampler.phase(h.x[i] + 0.4 * h.dx()); // nearest column is i
    EXPECT_EQ(ph.halfWave, expected) << "column " << i;
    EXPECT_EQ(ph.crest, std::sin(omega * lagged) > 0.0) << "column " << i;
  }
}
