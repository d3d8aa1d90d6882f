// SPDX-License-Identifier: GPL-3.0-or-later
// The storm file (docs/storm-file.md): writer and reader round trips, the atomic write, and every
// refusal of the writer and the reader. Files are damaged with the netCDF C API to reach the
// reader's checks the writer never lets through.

#include "core/Error.hpp"
#include "storm/StormFile.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <netcdf.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace armour::storm;
using armour::core::InputError;

namespace {

/// A small grid: 6 x 4 voxels of 0.05 m, x from 10.025 m (a non-zero origin, so x and z are not
/// mistaken for indices), z from -0.1 m. Voxel (ix 0, iz 0) and (ix 5, iz 3) have no data.
StormHeader makeHeader(bool hasV = false) {
  StormHeader h;
  for (int i = 0; i < 6; ++i) {
    h.x.push_back(10.025 + 0.05 * i);
  }
  for (int j = 0; j < 4; ++j) {
    h.z.push_back(-0.1 + 0.05 * j);
  }
  h.samples.assign(h.voxels(), 3);
  h.samples[0] = 0;
  h.samples[h.voxels() - 1] = 0;
  h.samples[7] = 21;
  h.trunkOrigin = -2.0;
  h.trunkLength = 44.5;
  h.stillWaterLevel = 0.25;
  h.waterDensity = 1027.5;
  h.gravity = 9.80665;
  h.hasVelocityY = hasV;
  h.provenance.title = "unit test storm";
  h.provenance.sourceCase = "synthetic: test";
  h.provenance.openfoamVersion = "v1912";
  h.provenance.software = "armour test";
  h.provenance.command = "test_storm_file --gtest";
  h.provenance.comment = "six by four";
  return h;
}

/// Values that are not representable in float (irrational-looking), so float rounding is visible.
StormRecord makeRecord(const StormHeader& h, double t) {
  StormRecord r;
  r.time = t;
  const std::size_t n = h.voxels();
  for (std::size_t i = 0; i < n; ++i) {
    const double x = h.x[i % h.nx()];
    const double z = h.z[i / h.nx()];
    r.p.push_back(1025.0 * 9.81 * (0.25 - z) + 731.3 * std::sin(0.7 * x - 1.3 * t));
    r.u.push_back(1.1 * std::cos(0.7 * x - 1.3 * t) / 3.0);
    if (h.hasVelocityY) {
      r.v.push_back(0.01 * std::sin(t + z) / 7.0);
    }
    r.w.push_back(0.9 * std::sin(0.7 * x - 1.3 * t + z) / 3.0);
    r.alpha.push_back(0.5 + 0.49 * std::sin(3.0 * z + t));
  }
  for (std::size_t i = 0; i < h.nx(); ++i) {
    r.eta.push_back(0.3 * std::cos(0.7 * h.x[i] - 1.3 * t) / 3.0);
  }
  return r;
}

Variability makeVariability(double scale) {
  Variability v;
  v.present = true;
  for (int c = 0; c < kVariabilityClasses; ++c) {
    v.classes[static_cast<std::size_t>(c)] = WeibullFit{1.2 + 0.1 * c, scale + 0.01 * c, 0.03 * c - 0.01, 1000 + c};
  }
  v.probabilityAbove = {{0.45, 0.62}};
  v.normalisationPressure = 1025.0 * 9.81 * 1.5;
  v.normalisationElevation = 1.5;
  v.source = fmt::format("test fit {}", scale);
  return v;
}

/// A fresh folder per test, removed afterwards.
class StormFileTest : public ::testing::Test {
protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("armour_storm_file_{}_{}", info->name(), ::getpid());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string file(const std::string& name) const { return (dir_ / name).string(); }

  /// A complete file of `records` records at t = 0.1 k.
  std::string writeGood(const std::string& name, const StormWriteOptions& options = {}, std::size_t records = 3,
                        bool hasV = false) {
    const auto h = makeHeader(hasV);
    const auto path = file(name);
    StormWriter writer(path, h, options);
    for (std::size_t k = 0; k < records; ++k) {
      writer.append(makeRecord(h, 0.1 * static_cast<double>(k)));
    }
    writer.finish();
    return path;
  }

  fs::path dir_;
};

/// Opens a finished file for editing with the C API (to damage it) and closes it afterwards.
struct EditFile {
  int ncid = -1;
  explicit EditFile(const std::string& path) { EXPECT_EQ(nc_open(path.c_str(), NC_WRITE, &ncid), NC_NOERR); }
  ~EditFile() { nc_close(ncid); }
  int var(const char* name) const {
    int id = -1;
    EXPECT_EQ(nc_inq_varid(ncid, name, &id), NC_NOERR) << name;
    return id;
  }
};

/// `action` must throw InputError whose message contains every string of `parts`.
void expectInputError(const std::function<void()>& action, std::initializer_list<std::string> parts) {
  try {
    action();
    ADD_FAILURE() << "no InputError thrown; expected one mentioning '" << *parts.begin() << "'";
  } catch (const InputError& e) {
    const std::string message = e.what();
    for (const auto& part : parts) {
      EXPECT_NE(message.find(part), std::string::npos) << "message lacks '" << part << "': " << message;
    }
  }
}

std::size_t voxel(const StormHeader& h, std::size_t ix, std::size_t iz) { return iz * h.nx() + ix; }

} // namespace

// ---------------------------------------------------------------------------------------------
// Round trips
// ---------------------------------------------------------------------------------------------

TEST_F(StormFileTest, RoundTripFloatEqualsFloatRounding) {
  // Stored as float: each value must come back as exactly the float nearest to what was written
  // (tolerance: float rounding, nothing more: the conversion double -> float -> double is exact).
  const auto path = writeGood("float.nc");
  const auto h = makeHeader();
  StormReader reader(path);
  const auto& rh = reader.header();
  EXPECT_EQ(rh.x, h.x); // coordinates are double: exact
  EXPECT_EQ(rh.z, h.z);
  EXPECT_EQ(rh.samples, h.samples);
  EXPECT_EQ(rh.trunkOrigin, h.trunkOrigin);
  EXPECT_EQ(rh.trunkLength, h.trunkLength);
  EXPECT_EQ(rh.stillWaterLevel, h.stillWaterLevel);
  EXPECT_EQ(rh.waterDensity, h.waterDensity);
  EXPECT_EQ(rh.gravity, h.gravity);
  EXPECT_FALSE(rh.hasVelocityY);
  EXPECT_FALSE(rh.variability.present);
  EXPECT_EQ(rh.provenance.title, h.provenance.title);
  EXPECT_EQ(rh.provenance.sourceCase, h.provenance.sourceCase);
  EXPECT_EQ(rh.provenance.openfoamVersion, h.provenance.openfoamVersion);
  EXPECT_EQ(rh.provenance.software, h.provenance.software);
  EXPECT_EQ(rh.provenance.command, h.provenance.command);
  EXPECT_EQ(rh.provenance.comment, h.provenance.comment);
  ASSERT_EQ(reader.times().size(), 3u);

  StormRecord r;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto expected = makeRecord(h, 0.1 * static_cast<double>(k));
    EXPECT_EQ(reader.times()[k], expected.time);
    reader.read(k, r);
    EXPECT_EQ(r.time, expected.time);
    EXPECT_TRUE(r.v.empty());
    for (std::size_t i = 0; i < h.voxels(); ++i) {
      if (h.samples[i] == 0) {
        EXPECT_TRUE(std::isnan(r.p[i]) && std::isnan(r.u[i]) && std::isnan(r.w[i]) && std::isnan(r.alpha[i])) << i;
        continue;
      }
      EXPECT_EQ(r.p[i], static_cast<double>(static_cast<float>(expected.p[i]))) << i;
      EXPECT_EQ(r.u[i], static_cast<double>(static_cast<float>(expected.u[i]))) << i;
      EXPECT_EQ(r.w[i], static_cast<double>(static_cast<float>(expected.w[i]))) << i;
      EXPECT_EQ(r.alpha[i], static_cast<double>(static_cast<float>(expected.alpha[i]))) << i;
      // Guard against a test that cannot fail: float rounding must actually have changed p.
      if (i == 1) {
        EXPECT_NE(r.p[i], expected.p[i]);
      }
    }
    for (std::size_t i = 0; i < h.nx(); ++i) {
      EXPECT_EQ(r.eta[i], static_cast<double>(static_cast<float>(expected.eta[i])));
      EXPECT_EQ(reader.eta(k)[i], r.eta[i]);
    }
  }
}

TEST_F(StormFileTest, RoundTripDoubleIsExact) {
  StormWriteOptions options;
  options.doublePrecision = true;
  options.deflateLevel = 4;
  const auto path = writeGood("double.nc", options, 4, true);
  const auto h = makeHeader(true);
  StormReader reader(path);
  EXPECT_TRUE(reader.header().hasVelocityY);
  StormRecord r;
  for (std::size_t k = 0; k < 4; ++k) {
    const auto expected = makeRecord(h, 0.1 * static_cast<double>(k));
    reader.read(k, r);
    for (std::size_t i = 0; i < h.voxels(); ++i) {
      if (h.samples[i] == 0) {
        EXPECT_TRUE(std::isnan(r.p[i]) && std::isnan(r.v[i]));
        continue;
      }
      EXPECT_EQ(r.p[i], expected.p[i]);
      EXPECT_EQ(r.u[i], expected.u[i]);
      EXPECT_EQ(r.v[i], expected.v[i]);
      EXPECT_EQ(r.w[i], expected.w[i]);
      EXPECT_EQ(r.alpha[i], expected.alpha[i]);
    }
    EXPECT_EQ(r.eta, expected.eta);
  }
}

TEST_F(StormFileTest, UniformAlongYRoundTripsAndIsAlwaysWritten) {
  // A 2D tank's file says its fields hold at every y; a bounded file says 0 explicitly, and a file
  // without the attribute (written before it existed) reads as bounded.
  const auto h = makeHeader();
  StormHeader uniform = h;
  uniform.uniformAlongY = true;
  const auto uniformPath = file("uniform.nc");
  {
    StormWriter writer(uniformPath, uniform);
    writer.append(makeRecord(uniform, 0.0));
    writer.append(makeRecord(uniform, 0.1));
    writer.finish();
  }
  const auto boundedPath = writeGood("bounded.nc");
  const auto attribute = [](const std::string& path) {
    EditFile f(path);
    nc_type type = NC_NAT;
    std::size_t length = 0;
    EXPECT_EQ(nc_inq_att(f.ncid, NC_GLOBAL, "uniform_along_y", &type, &length), NC_NOERR) << path;
    EXPECT_EQ(type, NC_INT);
    EXPECT_EQ(length, 1u);
    int value = -1;
    EXPECT_EQ(nc_get_att_int(f.ncid, NC_GLOBAL, "uniform_along_y", &value), NC_NOERR);
    return value;
  };
  EXPECT_EQ(attribute(uniformPath), 1);
  EXPECT_EQ(attribute(boundedPath), 0);
  {
    StormReader reader(uniformPath);
    EXPECT_TRUE(reader.header().uniformAlongY);
    // The y range averaged is still recorded.
    EXPECT_EQ(reader.header().trunkOrigin, h.trunkOrigin);
    EXPECT_EQ(reader.header().trunkLength, h.trunkLength);
  }
  EXPECT_FALSE(StormReader(boundedPath).header().uniformAlongY);
  {
    EditFile f(uniformPath);
    ASSERT_EQ(nc_del_att(f.ncid, NC_GLOBAL, "uniform_along_y"), NC_NOERR);
  }
  EXPECT_FALSE(StormReader(uniformPath).header().uniformAlongY) << "absent must read as 0 (older files)";
}

TEST_F(StormFileTest, ReaderRefusesUniformAlongYOtherThanZeroOrOne) {
  const auto path = writeGood("uniform_bad.nc");
  {
    EditFile f(path);
    const int two = 2;
    ASSERT_EQ(nc_put_att_int(f.ncid, NC_GLOBAL, "uniform_along_y", NC_INT, 1, &two), NC_NOERR);
  }
  expectInputError([&] { StormReader reader(path); }, {path, "uniform_along_y = 2", "0", "1", "ncatted"});
  {
    EditFile f(path);
    const std::string yes = "yes";
    ASSERT_EQ(nc_put_att_text(f.ncid, NC_GLOBAL, "uniform_along_y", yes.size(), yes.c_str()), NC_NOERR);
  }
  expectInputError([&] { StormReader reader(path); }, {path, "uniform_along_y", "'yes'", "one integer", "ncatted"});
  {
    // 1.0 as a double: the meaning is clear, but the layout says int; refusing keeps one spelling.
    EditFile f(path);
    ASSERT_EQ(nc_del_att(f.ncid, NC_GLOBAL, "uniform_along_y"), NC_NOERR);
    const double one = 1.0;
    ASSERT_EQ(nc_put_att_double(f.ncid, NC_GLOBAL, "uniform_along_y", NC_DOUBLE, 1, &one), NC_NOERR);
  }
  expectInputError([&] { StormReader reader(path); }, {path, "uniform_along_y", "one integer"});
  {
    EditFile f(path);
    ASSERT_EQ(nc_del_att(f.ncid, NC_GLOBAL, "uniform_along_y"), NC_NOERR);
    const short one = 1;
    ASSERT_EQ(nc_put_att_short(f.ncid, NC_GLOBAL, "uniform_along_y", NC_SHORT, 1, &one), NC_NOERR);
  }
  EXPECT_TRUE(StormReader(path).header().uniformAlongY) << "any integer type holding 1 is accepted";
}

TEST_F(StormFileTest, FillValueStoredWhereSamplesIsZero) {
  // The file itself (as ncdump or Python see it) holds _FillValue in the voxels without data and
  // the CF attributes of docs/storm-file.md.
  const auto path = writeGood("fill.nc");
  int ncid = -1;
  ASSERT_EQ(nc_open(path.c_str(), NC_NOWRITE, &ncid), NC_NOERR);
  int p = -1;
  ASSERT_EQ(nc_inq_varid(ncid, "p", &p), NC_NOERR);
  float fill = 0.0f;
  ASSERT_EQ(nc_get_att_float(ncid, p, "_FillValue", &fill), NC_NOERR);
  EXPECT_EQ(fill, NC_FILL_FLOAT);
  const auto h = makeHeader();
  float value = 0.0f;
  const std::size_t empty[3] = {1, 0, 0};
  ASSERT_EQ(nc_get_var1_float(ncid, p, empty, &value), NC_NOERR);
  EXPECT_EQ(value, NC_FILL_FLOAT);
  const std::size_t data[3] = {1, 0, 1};
  ASSERT_EQ(nc_get_var1_float(ncid, p, data, &value), NC_NOERR);
  EXPECT_NE(value, NC_FILL_FLOAT);

  const auto textAttribute = [&](int var, const char* name) {
    std::size_t length = 0;
    EXPECT_EQ(nc_inq_attlen(ncid, var, name, &length), NC_NOERR) << name;
    std::string s(length, '\0');
    nc_get_att_text(ncid, var, name, s.data());
    return s;
  };
  EXPECT_EQ(textAttribute(NC_GLOBAL, "Conventions"), "CF-1.8");
  EXPECT_EQ(textAttribute(p, "units"), "Pa");
  EXPECT_EQ(textAttribute(p, "standard_name"), "sea_water_pressure_due_to_sea_water");
  EXPECT_EQ(textAttribute(p, "cell_methods"), "y: mean");
  int version = 0;
  ASSERT_EQ(nc_get_att_int(ncid, NC_GLOBAL, "armour_storm_version", &version), NC_NOERR);
  EXPECT_EQ(version, kStormFormatVersion);
  int v = -1;
  EXPECT_NE(nc_inq_varid(ncid, "v", &v), NC_NOERR) << "v written although hasVelocityY is false";
  int formatCode = 0;
  ASSERT_EQ(nc_inq_format(ncid, &formatCode), NC_NOERR);
  EXPECT_EQ(formatCode, NC_FORMAT_NETCDF4);
  nc_close(ncid);
}

TEST_F(StormFileTest, VariabilityWrittenAtCreationAndReplacedLater) {
  auto h = makeHeader();
  h.variability = makeVariability(0.3);
  const auto path = file("variability.nc");
  const auto replaced = file("replaced.nc");
  {
    StormWriter writer(path, h);
    writer.append(makeRecord(h, 0.0));
    writer.append(makeRecord(h, 0.05));
    writer.finish();
  }
  {
    StormWriter writer(replaced, h);
    writer.append(makeRecord(h, 0.0));
    writer.append(makeRecord(h, 0.05));
    writer.setVariability(makeVariability(0.7)); // after the records, as foam-bridge fits it
    writer.finish();
  }
  const auto check = [](const Variability& got, const Variability& want) {
    EXPECT_TRUE(got.present);
    for (std::size_t c = 0; c < kVariabilityClasses; ++c) {
      EXPECT_EQ(got.classes[c].shape, want.classes[c].shape);
      EXPECT_EQ(got.classes[c].scale, want.classes[c].scale);
      EXPECT_EQ(got.classes[c].ksStatistic, want.classes[c].ksStatistic);
      EXPECT_EQ(got.classes[c].samples, want.classes[c].samples);
    }
    EXPECT_EQ(got.probabilityAbove, want.probabilityAbove);
    EXPECT_EQ(got.normalisationPressure, want.normalisationPressure);
    EXPECT_EQ(got.normalisationElevation, want.normalisationElevation);
    EXPECT_EQ(got.source, want.source);
  };
  check(StormReader(path).header().variability, makeVariability(0.3));
  check(StormReader(replaced).header().variability, makeVariability(0.7));

  // Removing the model afterwards is allowed too (present = false).
  const auto removed = file("removed.nc");
  {
    StormWriter writer(removed, h);
    writer.append(makeRecord(h, 0.0));
    writer.append(makeRecord(h, 0.05));
    writer.setVariability(Variability{});
    writer.finish();
  }
  EXPECT_FALSE(StormReader(removed).header().variability.present);
}

TEST_F(StormFileTest, WriteIsAtomic) {
  const auto h = makeHeader();
  const auto path = file("atomic.nc");
  {
    StormWriter writer(path, h);
    EXPECT_TRUE(fs::exists(path + ".partial"));
    EXPECT_FALSE(fs::exists(path));
    writer.append(makeRecord(h, 0.0));
    writer.append(makeRecord(h, 0.1));
    EXPECT_FALSE(fs::exists(path));
    EXPECT_EQ(writer.records(), 2u);
    writer.finish();
    EXPECT_TRUE(fs::exists(path));
    EXPECT_FALSE(fs::exists(path + ".partial"));
  }
  // An unfinished writer leaves only the .partial file.
  const auto killed = file("killed.nc");
  {
    StormWriter writer(killed, h);
    writer.append(makeRecord(h, 0.0));
    writer.append(makeRecord(h, 0.1));
  }
  EXPECT_FALSE(fs::exists(killed));
  EXPECT_TRUE(fs::exists(killed + ".partial"));
  // ... which is a readable netCDF file with the records written so far.
  StormReader partial(killed + ".partial");
  EXPECT_EQ(partial.times().size(), 2u);
}

// syncEachRecord (the function object's setting): the file is closed between records, so the
// .partial is whole and readable after every record; a variability model set after the records
// and the finished file are as without it. (A reader in another process holding the file while
// the writer reopens it is OutputFiles.SeriesIsReadableWhileTheRunGoesOn's case: the same
// HDF5_USE_FILE_LOCKING setting. In one process HDF5 cannot open a file for writing that it
// holds open for reading.)
TEST_F(StormFileTest, WriterSyncingEachRecordLeavesAWholeFileAfterEveryRecord) {
  const auto h = makeHeader();
  StormWriteOptions options;
  options.syncEachRecord = true;
  const auto path = file("synced.nc");
  {
    StormWriter writer(path, h, options);
    writer.append(makeRecord(h, 0.0));
    for (int k = 1; k < 4; ++k) { // a reader needs two records
      writer.append(makeRecord(h, 0.05 * k));
      StormReader partial(path + ".partial");
      EXPECT_EQ(partial.times().size(), static_cast<std::size_t>(k + 1));
      EXPECT_NO_THROW(partial.validateAllRecords());
    }
    writer.setVariability(makeVariability(0.7));
    EXPECT_TRUE(StormReader(path + ".partial").header().variability.present);
    writer.finish();
  }
  const StormReader synced(path);
  EXPECT_EQ(synced.times().size(), 4u);
  EXPECT_NO_THROW(synced.validateAllRecords());
  EXPECT_EQ(synced.header().variability.classes[0].scale, makeVariability(0.7).classes[0].scale);
  EXPECT_FALSE(fs::exists(path + ".partial"));
}

// ---------------------------------------------------------------------------------------------
// Writer refusals
// ---------------------------------------------------------------------------------------------

TEST_F(StormFileTest, WriterRefusesBadValuesNamingVariableTimeAndVoxel) {
  const auto h = makeHeader();
  StormWriter writer(file("bad.nc"), h);
  writer.append(makeRecord(h, 0.0));

  auto r = makeRecord(h, 0.1);
  const std::size_t ix = 2, iz = 1;
  r.p[voxel(h, ix, iz)] = std::numeric_limits<double>::quiet_NaN();
  expectInputError([&] { writer.append(r); },
                   {"p = nan", "t = 0.1 s", fmt::format("x = {} m", h.x[ix]), fmt::format("z = {} m", h.z[iz])});

  r = makeRecord(h, 0.1);
  r.u[voxel(h, 4, 2)] = std::numeric_limits<double>::infinity();
  expectInputError([&] { writer.append(r); }, {"u = inf", fmt::format("x = {} m", h.x[4])});

  r = makeRecord(h, 0.1);
  r.alpha[voxel(h, 3, 3)] = 1.5;
  expectInputError([&] { writer.append(r); }, {"alpha = 1.5", fmt::format("z = {} m", h.z[3])});

  r = makeRecord(h, 0.1);
  r.w.pop_back();
  expectInputError([&] { writer.append(r); }, {"w has 23 values", "24"});

  r = makeRecord(h, 0.1);
  r.eta[1] = std::numeric_limits<double>::quiet_NaN();
  expectInputError([&] { writer.append(r); }, {"eta = nan", fmt::format("x = {} m", h.x[1])});

  r = makeRecord(h, 0.1);
  r.v.assign(h.voxels(), 0.0);
  expectInputError([&] { writer.append(r); }, {"v has", "hasVelocityY"});

  r = makeRecord(h, 0.0);
  expectInputError([&] { writer.append(r); }, {"time = 0 s", "increase strictly"});

  // None of the refused records was written.
  EXPECT_EQ(writer.records(), 1u);

  // A NaN in a voxel without data is ignored (the writer stores _FillValue there), and alpha
  // within 1e-6 of [0, 1] is VOF round-off: accepted, clamped.
  r = makeRecord(h, 0.1);
  r.p[voxel(h, 0, 0)] = std::numeric_limits<double>::quiet_NaN();
  r.alpha[voxel(h, 1, 0)] = 1.0 + 5e-7;
  writer.append(r);
  EXPECT_EQ(writer.records(), 2u);
  writer.finish();
  StormReader reader(file("bad.nc"));
  StormRecord back;
  reader.read(1, back);
  EXPECT_EQ(back.alpha[voxel(h, 1, 0)], 1.0);
}

TEST_F(StormFileTest, WriterRefusesToFinishWithOneRecord) {
  const auto h = makeHeader();
  const auto path = file("short.nc");
  StormWriter writer(path, h);
  expectInputError([&] { writer.finish(); }, {"0 record(s)", "two records"});
  writer.append(makeRecord(h, 0.0));
  expectInputError([&] { writer.finish(); }, {"1 record(s)", "two records"});
  EXPECT_FALSE(fs::exists(path));
  writer.append(makeRecord(h, 0.1)); // still usable after a refused finish()
  writer.finish();
  EXPECT_TRUE(fs::exists(path));
}

TEST_F(StormFileTest, WriterRefusesBadHeaderNamingTheField) {
  const auto path = file("header.nc");
  const auto refuses = [&](const std::function<void(StormHeader&)>& spoil, std::initializer_list<std::string> parts) {
    auto h = makeHeader();
    spoil(h);
    expectInputError([&] { StormWriter writer(path, h); }, parts);
    EXPECT_FALSE(fs::exists(path + ".partial")) << "a refused header must not create a file";
  };
  refuses([](StormHeader& h) { h.x.resize(1); h.samples.resize(4); }, {"header.x", "at least 2"});
  refuses([](StormHeader& h) { h.z[2] += 0.01; }, {"header.z[2] - header.z[1]", "uniformly"});
  refuses([](StormHeader& h) { std::swap(h.x[0], h.x[1]); }, {"header.x[0]", "increase"});
  refuses([](StormHeader& h) { h.samples.pop_back(); }, {"header.samples has 23 values", "24"});
  refuses([](StormHeader& h) { h.samples[5] = -1; }, {"header.samples[5] = -1", ">= 0"});
  refuses([](StormHeader& h) { h.waterDensity = 0.0; }, {"header.waterDensity = 0", "positive"});
  refuses([](StormHeader& h) { h.gravity = -9.81; }, {"header.gravity = -9.81", "positive"});
  refuses([](StormHeader& h) { h.trunkLength = 0.0; }, {"header.trunkLength = 0", "positive"});
  refuses([](StormHeader& h) { h.stillWaterLevel = std::nan(""); }, {"header.stillWaterLevel", "finite"});
  refuses([](StormHeader& h) { h.variability = makeVariability(0.3); h.variability.classes[2].shape = 0.0; },
          {"variability.classes[trough_above].shape = 0", "positive"});
  refuses([](StormHeader& h) { h.variability = makeVariability(0.3); h.variability.classes[1].scale = -0.1; },
          {"variability.classes[crest_below].scale = -0.1"});
  refuses([](StormHeader& h) { h.variability = makeVariability(0.3); h.variability.probabilityAbove[1] = 1.5; },
          {"variability.probabilityAbove[1] = 1.5", "[0, 1]"});
  refuses([](StormHeader& h) { h.variability = makeVariability(0.3); h.variability.normalisationPressure = 0.0; },
          {"variability.normalisationPressure = 0", "Pa"});
  refuses([](StormHeader& h) { h.variability = makeVariability(0.3); h.variability.normalisationElevation = -1.0; },
          {"variability.normalisationElevation = -1"});

  // An absent model is not checked (its defaults have zero normalisations).
  auto h = makeHeader();
  h.variability.normalisationPressure = 0.0;
  EXPECT_NO_THROW((StormWriter{path, h}));
  // ... but setVariability() checks what it is given.
  StormWriter writer(file("later.nc"), h);
  auto v = makeVariability(0.3);
  v.classes[0].shape = -1.0;
  expectInputError([&] { writer.setVariability(v); }, {"variability.classes[crest_above].shape = -1"});
}

// ---------------------------------------------------------------------------------------------
// Reader refusals
// ---------------------------------------------------------------------------------------------

TEST_F(StormFileTest, ReaderRefusesMissingVariable) {
  const auto path = writeGood("missing.nc");
  {
    EditFile f(path);
    ASSERT_EQ(nc_rename_var(f.ncid, f.var("u"), "u_renamed"), NC_NOERR);
  }
  expectInputError([&] { StormReader reader(path); }, {path, "'u' is missing"});
}

TEST_F(StormFileTest, ReaderRefusesWrongUnitsAndAcceptsSynonyms) {
  const auto path = writeGood("units.nc");
  {
    EditFile f(path);
    ASSERT_EQ(nc_put_att_text(f.ncid, f.var("u"), "units", 3, "m/s"), NC_NOERR); // a listed synonym
    ASSERT_EQ(nc_put_att_text(f.ncid, f.var("alpha"), "units", 1, "-"), NC_NOERR);
    // A netCDF-4 string attribute instead of a char array, as some Python writers make them.
    const char* units = "m s-1";
    ASSERT_EQ(nc_del_att(f.ncid, f.var("w"), "units"), NC_NOERR);
    ASSERT_EQ(nc_put_att_string(f.ncid, f.var("w"), "units", 1, &units), NC_NOERR);
  }
  EXPECT_NO_THROW(StormReader{path});
  {
    EditFile f(path);
    ASSERT_EQ(nc_put_att_text(f.ncid, f.var("p"), "units", 3, "kPa"), NC_NOERR);
  }
  expectInputError([&] { StormReader reader(path); }, {"p has units 'kPa'", "expected 'Pa'"});
  {
    EditFile f(path);
    ASSERT_EQ(nc_put_att_text(f.ncid, f.var("p"), "units", 2, "Pa"), NC_NOERR);
    ASSERT_EQ(nc_put_att_text(f.ncid, f.var("z"), "units", 2, "cm"), NC_NOERR);
  }
  expectInputError([&] { StormReader reader(path); }, {"z has units 'cm'"});
}

TEST_F(StormFileTest, ReaderRefusesTruncatedAndForeignFiles) {
  const auto path = writeGood("whole.nc");
  const auto cut = file("cut.nc");
  fs::copy_file(path, cut);
  fs::resize_file(cut, fs::file_size(path) / 2);
  expectInputError([&] { StormReader reader(cut); }, {cut, "not a readable netCDF-4 file"});

  const auto text = file("text.nc");
  std::ofstream(text) << "time,p\n0,1\n";
  expectInputError([&] { StormReader reader(text); }, {text, "not a readable netCDF-4 file"});

  expectInputError([&] { StormReader reader(file("absent.nc")); }, {"absent.nc", "no such file"});

  // A netCDF file that is not a storm file.
  const auto other = file("other.nc");
  int ncid = -1;
  ASSERT_EQ(nc_create(other.c_str(), NC_NETCDF4, &ncid), NC_NOERR);
  nc_close(ncid);
  expectInputError([&] { StormReader reader(other); }, {"armour_storm_version is missing"});
}

TEST_F(StormFileTest, ReaderRefusesNonMonotonicTime) {
  const auto path = writeGood("time.nc", {}, 4);
  {
    EditFile f(path);
    const std::size_t index = 2;
    const double t = 0.05; // before time[1] = 0.1
    ASSERT_EQ(nc_put_var1_double(f.ncid, f.var("time"), &index, &t), NC_NOERR);
  }
  expectInputError([&] { StormReader reader(path); }, {"time[2] = 0.05 s", "time[1] = 0.1 s", "increase"});
}

TEST_F(StormFileTest, ReaderRefusesNonUniformX) {
  const auto path = writeGood("x.nc");
  {
    EditFile f(path);
    const std::size_t index = 3;
    const double x = 10.025 + 0.05 * 3 + 0.01;
    ASSERT_EQ(nc_put_var1_double(f.ncid, f.var("x"), &index, &x), NC_NOERR);
  }
  expectInputError([&] { StormReader reader(path); }, {"x[3] - x[2]", "uniformly"});
}

TEST_F(StormFileTest, ReaderRefusesWrongDimensionOrder) {
  // A p laid out (time, x, z): the transposed layout of another tool.
  const auto path = writeGood("order.nc");
  {
    EditFile f(path);
    int timeDim = -1, xDim = -1, zDim = -1;
    nc_inq_dimid(f.ncid, "time", &timeDim);
    nc_inq_dimid(f.ncid, "x", &xDim);
    nc_inq_dimid(f.ncid, "z", &zDim);
    ASSERT_EQ(nc_rename_var(f.ncid, f.var("p"), "p_original"), NC_NOERR);
    const int dims[3] = {timeDim, xDim, zDim};
    int p = -1;
    ASSERT_EQ(nc_redef(f.ncid), NC_NOERR);
    ASSERT_EQ(nc_def_var(f.ncid, "p", NC_FLOAT, 3, dims, &p), NC_NOERR);
    ASSERT_EQ(nc_put_att_text(f.ncid, p, "units", 2, "Pa"), NC_NOERR);
    ASSERT_EQ(nc_enddef(f.ncid), NC_NOERR);
  }
  expectInputError([&] { StormReader reader(path); }, {"p has dimensions (time, x, z)", "expected (time, z, x)"});
}

TEST_F(StormFileTest, ReaderRefusesNaNInDataVoxelWhenTheRecordIsRead) {
  const auto path = writeGood("nan.nc");
  const auto h = makeHeader();
  const std::size_t ix = 3, iz = 2;
  {
    EditFile f(path);
    const std::size_t index[3] = {1, iz, ix};
    const float nan = std::numeric_limits<float>::quiet_NaN();
    ASSERT_EQ(nc_put_var1_float(f.ncid, f.var("p"), index, &nan), NC_NOERR);
  }
  StormReader reader(path); // records are checked when read, not at open
  StormRecord r;
  EXPECT_NO_THROW(reader.read(0, r));
  expectInputError([&] { reader.read(1, r); },
                   {"p = nan", "t = 0.1 s", fmt::format("x = {} m", h.x[ix]), fmt::format("z = {} m", h.z[iz])});
  expectInputError([&] { reader.validateAllRecords(); }, {"p = nan"});
}

TEST_F(StormFileTest, ReaderRefusesFillValueInDataVoxel) {
  const auto path = writeGood("hole.nc");
  const auto h = makeHeader();
  {
    EditFile f(path);
    const std::size_t index[3] = {2, 1, 4};
    const float fill = NC_FILL_FLOAT;
    ASSERT_EQ(nc_put_var1_float(f.ncid, f.var("w"), index, &fill), NC_NOERR);
  }
  StormReader reader(path);
  StormRecord r;
  expectInputError([&] { reader.read(2, r); }, {"w = _FillValue", "t = 0.2 s", fmt::format("x = {} m", h.x[4])});
}

TEST_F(StormFileTest, ReaderRefusesNewerVersion) {
  const auto path = writeGood("version.nc");
  {
    EditFile f(path);
    const int newer = kStormFormatVersion + 1;
    ASSERT_EQ(nc_put_att_int(f.ncid, NC_GLOBAL, "armour_storm_version", NC_INT, 1, &newer), NC_NOERR);
  }
  expectInputError([&] { StormReader reader(path); },
                   {fmt::format("armour_storm_version = {}", kStormFormatVersion + 1), "newer"});
}

TEST_F(StormFileTest, ReaderRefusesNegativeSamplesAndBadAttributes) {
  const auto path = writeGood("attributes.nc");
  {
    EditFile f(path);
    const double density = -1.0;
    ASSERT_EQ(nc_put_att_double(f.ncid, NC_GLOBAL, "water_density", NC_DOUBLE, 1, &density), NC_NOERR);
  }
  expectInputError([&] { StormReader reader(path); }, {"water_density = -1", "positive"});
  {
    EditFile f(path);
    const double density = 1025.0;
    ASSERT_EQ(nc_put_att_double(f.ncid, NC_GLOBAL, "water_density", NC_DOUBLE, 1, &density), NC_NOERR);
    ASSERT_EQ(nc_del_att(f.ncid, NC_GLOBAL, "gravity"), NC_NOERR);
  }
  expectInputError([&] { StormReader reader(path); }, {"gravity", "missing"});
}
