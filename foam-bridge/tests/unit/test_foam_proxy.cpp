// SPDX-License-Identifier: GPL-3.0-or-later
// foam-proxy's reading of the surfaces function object's output (proxy/SurfaceSeries), the storm
// file of a 2D run declared uniform along y (proxy/ProxyRun sampleSurfaces, functionDictionaries) and
// the comparison used by the alpha/beta calibration (proxy/ProxyRun compareStorms).

#include "proxy/CaseChecks.hpp"
#include "proxy/ProxyRun.hpp"
#include "proxy/SurfaceSeries.hpp"

#include "core/Error.hpp"
#include "storm/StormFile.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <filesystem>
#include <fstream>
#include <numbers>

namespace fs = std::filesystem;
using namespace armour;

namespace {

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("armour-foam-proxy-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// A legacy VTK file as OpenFOAM v1912 writes it (surfaceFormat vtk, legacy, ascii): a unit
/// square split into a quad and a triangle of the same plane, with p and U as cell data, the
/// connectivity wrapped over lines the way OpenFOAM wraps it.
void writeSurface(const fs::path& file, double p0) {
  std::ofstream f(file);
  f << "# vtk DataFile Version 2.0\ntime='0.05'\nASCII\nDATASET POLYDATA\nFIELD FieldData 1\nTimeValue 1 1 float\n0.05\n"
       "POINTS 5 float\n0 0 0 1 0 0 1 0 1\n0 0 1 2 0 0\n"
       "POLYGONS 2 9\n4 0 1 2 3 3\n1 4 2\n"
       "CELL_DATA 2\nFIELD FieldData 2\np 1 2 float\n" << p0 << " " << p0 + 1.0 << "\nU 3 2 float\n1 2 3 4 5 6\n";
}

} // namespace

TEST(SurfaceSeries, ReadsLegacyVtkOfTheSurfacesFunctionObject) {
  const fs::path d = tempDir("read");
  writeSurface(d / "units.vtk", 100.0);
  const proxy::Surface s = proxy::readSurface(d / "units.vtk");
  ASSERT_EQ(s.faces(), 2u);
  // The quad's centre is the centre of the square; the triangle's is the mean of its corners.
  EXPECT_NEAR(s.centreX[0], 0.5, 1e-12);
  EXPECT_NEAR(s.centreZ[0], 0.5, 1e-12);
  EXPECT_NEAR(s.centreX[1], (1.0 + 2.0 + 1.0) / 3.0, 1e-12);
  EXPECT_NEAR(s.centreZ[1], 1.0 / 3.0, 1e-12);
  // Area vectors: the quad 0-1-2-3 in the x-z plane has |S| = 1 along -y (right-hand rule).
  EXPECT_NEAR(s.areaY[0], -1.0, 1e-12);
  EXPECT_NEAR(std::abs(s.areaY[1]), 0.5, 1e-12);
  EXPECT_EQ(s.field("p", 1)[1], 101.0);
  EXPECT_EQ(s.field("U", 3)[4], 5.0);
  EXPECT_THROW(s.field("alpha.water", 1), core::InputError);
  EXPECT_THROW(s.field("p", 3), core::InputError);
  EXPECT_TRUE(s.containsXZ(0, 0.5, 0.5));
  EXPECT_FALSE(s.containsXZ(0, 1.5, 0.5));
  EXPECT_THROW(proxy::readSurface(d / "missing.vtk"), core::InputError);
  fs::remove_all(d);
}

// The raw surface format as v1912's rawSurfaceWriter writes it: one file per field, face centres
// and values as text. Values must come back bit for bit (17 digits written: the round trip of a
// double is exact), which is what makes the offline storm file equal the online one.
TEST(SurfaceSeries, ReadsRawOutputOfTheSurfacesFunctionObjectExactly) {
  const fs::path d = tempDir("raw");
  const double p1 = 117719.98765432101, z1 = 1.4999999999999998;
  {
    std::ofstream f(d / "p_units.raw");
    f.precision(17);
    f << "# p  FACE_DATA 2\n# x  y  z  p\n21 1.25 2.125 100.5\n24 3.75 " << z1 << " " << p1 << "\n";
    std::ofstream u(d / "U_units.raw");
    u.precision(17);
    u << "# U  FACE_DATA 2\n# x  y  z  U_x  U_y  U_z\n21 1.25 2.125 1 2 3\n24 3.75 " << z1 << " 4 5 -6e-05\n";
  }
  const proxy::Surface s = proxy::readSurfaceIn(d, "units", {"p", "U", "alpha.water"});
  ASSERT_EQ(s.faces(), 2u);
  EXPECT_FALSE(s.hasGeometry());
  EXPECT_EQ(s.centreX[1], 24.0);
  EXPECT_EQ(s.centreZ[1], z1);
  EXPECT_EQ(s.field("p", 1)[1], p1);
  EXPECT_EQ(s.field("U", 3)[5], -6e-05);
  EXPECT_THROW(s.field("alpha.water", 1), core::InputError);
  // A truncated file, a field whose faces are elsewhere, point data: refused with the file named.
  std::ofstream(d / "alpha.water_units.raw") << "# alpha.water  FACE_DATA 2\n# x  y  z  alpha.water\n21 1.25 2.125 1\n";
  EXPECT_THROW(proxy::readSurfaceIn(d, "units", {"p", "U", "alpha.water"}), core::InputError);
  std::ofstream(d / "alpha.water_units.raw") << "# alpha.water  FACE_DATA 2\n# x  y  z  alpha.water\n21 1.25 2.125 1\n24 3.75 1.5 1\n";
  EXPECT_THROW(proxy::readSurfaceIn(d, "units", {"p", "U", "alpha.water"}), core::InputError);
  std::ofstream(d / "p_cells.raw") << "# p  POINT_DATA 1\n# x  y  z  p\n0 0 0 1\n";
  EXPECT_THROW(proxy::readSurfaceIn(d, "cells", {"p"}), core::InputError);
  EXPECT_THROW(proxy::readSurfaceIn(d, "nothing", {"p"}), core::InputError);
  fs::remove_all(d);
}

// The sets function object's raw output: scalar fields share a file named after all of them
// (p_rgh must not be split into p and rgh), vectors have their own; values come back bit for bit;
// files holding none of the needed fields are not read; ragged lines are refused.
TEST(SurfaceSeries, ReadsSetsOutputAndSkipsUnneededFiles) {
  const fs::path d = tempDir("sets");
  std::ofstream(d / "eta_alpha.water_p_rgh.xy") << "21.5 3 0.25 1 98765.4321012345\n21.5\t3 0.75 0.25 -1e-07\n";
  std::ofstream(d / "eta_U.xy") << "21.5 3 0.25 1 2 3\n21.5 3 0.75 4 5 6\n";
  const std::vector<std::string> names = {"alpha.water", "p_rgh", "U"};
  const proxy::PointSet all = proxy::readPointSet(d, "eta", names);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all.z[1], 0.75);
  EXPECT_EQ(all.field("p_rgh", 1)[0], 98765.4321012345);
  EXPECT_EQ(all.field("p_rgh", 1)[1], -1e-07);
  EXPECT_EQ(all.field("U", 3)[5], 6.0);
  const proxy::PointSet alphaOnly = proxy::readPointSet(d, "eta", names, {"alpha.water"});
  EXPECT_EQ(alphaOnly.field("alpha.water", 1)[1], 0.25);
  EXPECT_THROW(alphaOnly.field("U", 3), core::InputError);
  EXPECT_THROW(proxy::readPointSet(d, "eta", names, {"T"}), core::InputError);
  std::ofstream(d / "bad_p.xy") << "1 2 3 4\n1 2 3\n";
  EXPECT_THROW(proxy::readPointSet(d, "bad", {"p"}), core::InputError);
  std::ofstream(d / "word_p.xy") << "1 2 3 four\n";
  EXPECT_THROW(proxy::readPointSet(d, "word", {"p"}), core::InputError);
  fs::remove_all(d);
}

TEST(SurfaceSeries, ListsNumericTimeFoldersInOrder) {
  const fs::path d = tempDir("times");
  for (const char* t : {"0.1", "0.05", "1e-1x", "10", "0.15"}) fs::create_directories(d / t);
  const std::vector<proxy::SampleTime> times = proxy::listSampleTimes(d);
  ASSERT_EQ(times.size(), 4u);
  EXPECT_EQ(times[0].time, 0.05);
  EXPECT_EQ(times[3].time, 10.0);
  EXPECT_THROW(proxy::listSampleTimes(d / "nothing"), core::InputError);
  fs::remove_all(d);
}

// A 2D run's output as the stock sets function objects of `foam-proxy dict --2d` write it: 2 x 2
// voxels of 1 m from (0, 0), still water up to z = 1 m, one cell across (y in [0, 1] m). The storm
// file says uniform_along_y = 1 only when asked (--uniform-along-y), and the armourSampler
// dictionary carries the same setting.
TEST(SampleSurfaces, UniformAlongYIsDeclaredOnlyWhenAsked) {
  const fs::path d = tempDir("uniform");
  for (const char* t : {"0.1", "0.2"}) {
    const fs::path sets = d / "postProcessing" / "armourSets" / t;
    const fs::path centres = d / "postProcessing" / "armourCentres" / t;
    fs::create_directories(sets);
    fs::create_directories(centres);
    // eta: alpha at cell centres 0.25 m apart around the still water level of each column.
    std::ofstream eta(sets / "etaCells_alpha.water.xy");
    for (const double x : {0.5, 1.5}) {
      for (const double z : {0.25, 0.75, 1.25, 1.75}) eta << x << " 0.5 " << z << " " << (z < 1.0 ? 1 : 0) << "\n";
    }
    std::ofstream scalars(centres / "voxelCentres_alpha.water_p.xy");
    std::ofstream velocity(centres / "voxelCentres_U.xy");
    for (const double z : {0.5, 1.5}) {
      for (const double x : {0.5, 1.5}) {
        scalars << x << " 0.5 " << z << " " << (z < 1.0 ? 1 : 0) << " " << (z < 1.0 ? 4905.0 : 0.0) << "\n";
        velocity << x << " 0.5 " << z << " 0.25 0 -0.125\n";
      }
    }
  }
  proxy::SampleOptions o;
  o.caseDir = d;
  o.twoD = true;
  o.sampler.grid.xMin = 0.0;
  o.sampler.grid.zMin = 0.0;
  o.sampler.grid.dx = 1.0;
  o.sampler.grid.dz = 1.0;
  o.sampler.grid.nx = 2;
  o.sampler.grid.nz = 2;
  o.sampler.grid.trunkOrigin = 0.0;
  o.sampler.grid.trunkLength = 1.0;
  o.sampler.stillWaterLevel = 1.0;
  o.sampler.waterDensity = 1000.0;
  for (const bool uniform : {false, true}) {
    o.sampler.uniformAlongY = uniform;
    o.output = d / (uniform ? "uniform.nc" : "bounded.nc");
    const proxy::SampleSummary s = proxy::sampleSurfaces(o);
    EXPECT_EQ(s.records, 2u);
    const storm::StormReader r(o.output.string());
    EXPECT_EQ(r.header().uniformAlongY, uniform);
    // The y range averaged is recorded either way.
    EXPECT_EQ(r.header().trunkOrigin, 0.0);
    EXPECT_EQ(r.header().trunkLength, 1.0);
    storm::StormRecord rec;
    r.read(1, rec);
    EXPECT_FLOAT_EQ(static_cast<float>(rec.p[0]), 4905.0f); // stored as float
    const std::string dict = proxy::functionDictionaries(o, {"unit_.*"}, 0.05, "libarmourSampler.so", "sampler");
    EXPECT_NE(dict.find(uniform ? "uniformAlongY   true;" : "uniformAlongY   false;"), std::string::npos) << dict;
  }
  fs::remove_all(d);
}

// The calibration metrics against known signals: a candidate equal to the reference delayed by
// 0.2 s has that phase lag; a candidate with an error of 10 % of the amplitude everywhere has a
// normalised error of 0.1 / (1 / sqrt 2) = 0.141.
TEST(CompareStorms, RecoversLagAndNormalisedError) {
  const fs::path d = tempDir("compare");
  auto write = [&](const fs::path& file, double lag, double offset) {
    storm::StormHeader h;
    h.x = {0.025, 0.075, 0.125};
    h.z = {0.025, 0.075};
    h.trunkLength = 1.0;
    h.samples = {1, 1, 0, 1, 1, 1};
    storm::StormWriter w(file.string(), h);
    storm::StormRecord r;
    r.u.assign(6, 0.0);
    r.w.assign(6, 0.0);
    r.alpha.assign(6, 1.0);
    r.eta.assign(3, 0.0);
    for (int k = 0; k <= 400; ++k) {
      r.time = 0.01 * k;
      r.p.assign(6, 0.0);
      for (int v = 0; v < 6; ++v) r.p[static_cast<std::size_t>(v)] = 1000.0 * std::sin(2.0 * std::numbers::pi * (r.time - lag) / 2.0) + offset;
      w.append(r);
    }
    w.finish();
  };
  write(d / "ref.nc", 0.0, 0.0);
  write(d / "late.nc", 0.2, 0.0);
  write(d / "offset.nc", 0.0, 100.0);
  const proxy::Comparison late = proxy::compareStorms(d / "ref.nc", d / "late.nc");
  EXPECT_NEAR(late.phaseLag, 0.2, 0.005); // parabolic refinement of a 0.01 s record spacing
  EXPECT_EQ(late.voxels, 5u);
  const proxy::Comparison offset = proxy::compareStorms(d / "ref.nc", d / "offset.nc");
  EXPECT_NEAR(offset.rmse, 100.0, 1e-3); // float storage of p
  EXPECT_NEAR(offset.normalisedError, 0.1 * std::sqrt(2.0), 2e-3);
  EXPECT_NEAR(offset.phaseLag, 0.0, 1e-9);
  const proxy::Comparison self = proxy::compareStorms(d / "ref.nc", d / "ref.nc");
  EXPECT_EQ(self.rmse, 0.0);
  EXPECT_NEAR(self.correlation, 1.0, 1e-12);
  fs::remove_all(d);
}

// combine: the records and grid of the sea state with the variability of the 3D run, unchanged.
TEST(CombineStorms, TakesRecordsFromOneAndVariabilityFromTheOther) {
  const fs::path d = tempDir("combine");
  auto header = [](double x0) {
    storm::StormHeader h;
    h.x = {x0, x0 + 0.05, x0 + 0.1};
    h.z = {-0.1, -0.05};
    h.trunkLength = 44.5;
    h.samples = {1, 1, 1, 1, 0, 1};
    return h;
  };
  auto write = [](const fs::path& file, storm::StormHeader h, double scale) {
    storm::StormWriter w(file.string(), h);
    storm::StormRecord r;
    r.u.assign(6, 0.5);
    r.w.assign(6, -0.5);
    r.alpha.assign(6, 1.0);
    r.eta.assign(3, 0.1);
    for (int k = 0; k < 3; ++k) {
      r.time = 0.05 * k;
      r.p.assign(6, scale * (k + 1));
      w.append(r);
    }
    w.finish();
  };
  storm::StormHeader sea = header(10.0);
  sea.uniformAlongY = true; // a 2D sea-state run
  write(d / "sea.nc", sea, 1000.0);
  storm::StormHeader h3 = header(20.0);
  h3.variability.present = true;
  h3.variability.classes[0] = {1.7, 0.08, 0.01, 5000};
  h3.variability.classes[3] = {1.2, 0.05, 0.02, 4000};
  h3.variability.probabilityAbove = {{0.45, 0.55}};
  h3.variability.normalisationPressure = 32000.0;
  h3.variability.normalisationElevation = 3.25;
  h3.variability.source = "3D regular waves";
  write(d / "3d.nc", h3, 7.0);
  proxy::combineStorms(d / "sea.nc", d / "3d.nc", d / "storm.nc", storm::Provenance(), storm::StormWriteOptions());
  const storm::StormReader r((d / "storm.nc").string());
  EXPECT_EQ(r.header().x[0], 10.0);
  EXPECT_TRUE(r.header().uniformAlongY) << "the combined file keeps the sea state's y extent";
  ASSERT_EQ(r.times().size(), 3u);
  storm::StormRecord rec;
  r.read(2, rec);
  EXPECT_FLOAT_EQ(static_cast<float>(rec.p[0]), 3000.0f);
  const storm::Variability& v = r.header().variability;
  ASSERT_TRUE(v.present);
  EXPECT_EQ(v.classes[0].shape, 1.7);
  EXPECT_EQ(v.classes[3].samples, 4000);
  EXPECT_EQ(v.probabilityAbove[1], 0.55);
  EXPECT_EQ(v.normalisationPressure, 32000.0);
  EXPECT_NE(v.source.find("3D regular waves"), std::string::npos);
  // A variability file without a model is refused.
  EXPECT_THROW(proxy::combineStorms(d / "sea.nc", d / "sea.nc", d / "bad.nc", storm::Provenance(),
                                    storm::StormWriteOptions()),
               core::InputError);
  fs::remove_all(d);
}

// ---- the cases foam-proxy refuses, as the armourSampler does (issue 23 items 1 and 4) ----------

namespace {

std::string inputError(const std::function<void()>& f) {
  try {
    f();
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(CaseChecks, DynamicMeshIsRefusedNamingTheMeshTypeAndTheFix) {
  const fs::path d = tempDir("dynamic");
  fs::create_directories(d / "constant");
  EXPECT_EQ(proxy::dynamicMeshType(d), "staticFvMesh"); // no dynamicMeshDict: OpenFOAM builds a static mesh
  EXPECT_NO_THROW(proxy::requireStaticMesh(d));
  std::ofstream(d / "constant/dynamicMeshDict") << "FoamFile { version 2.0; format ascii; class dictionary; object "
                                                   "dynamicMeshDict; }\n// dynamicFvMesh staticFvMesh;\n"
                                                   "dynamicFvMesh   dynamicRefineFvMesh;\n"
                                                   "dynamicRefineFvMeshCoeffs { refineInterval 1; field alpha.water; }\n";
  EXPECT_EQ(proxy::dynamicMeshType(d), "dynamicRefineFvMesh"); // the commented-out line is not read
  const std::string error = inputError([&] { proxy::requireStaticMesh(d); });
  EXPECT_NE(error.find("constant/dynamicMeshDict"), std::string::npos) << error;
  EXPECT_NE(error.find("dynamicFvMesh = dynamicRefineFvMesh"), std::string::npos) << error;
  EXPECT_NE(error.find("`dynamicFvMesh staticFvMesh;`"), std::string::npos) << error;
  std::ofstream(d / "constant/dynamicMeshDict") << "dynamicFvMesh staticFvMesh;\n";
  EXPECT_NO_THROW(proxy::requireStaticMesh(d));
  fs::remove_all(d);
}

TEST(CaseChecks, GravityNotAlongMinusZIsRefusedNamingTransformPoints) {
  const fs::path d = tempDir("gravity");
  fs::create_directories(d / "constant");
  EXPECT_NO_THROW(proxy::requireGravityAlongMinusZ(d)); // no constant/g: nothing to check
  const auto writeG = [&](const std::string& value) {
    std::ofstream(d / "constant/g") << "FoamFile { version 2.0; format ascii; class uniformDimensionedVectorField; "
                                       "object g; }\ndimensions [0 1 -2 0 0 0 0];\nvalue " << value << ";\n";
  };
  writeG("(0 0 -9.81)");
  EXPECT_NO_THROW(proxy::requireGravityAlongMinusZ(d));
  writeG("( 0  0  -9.80665 )");
  EXPECT_NO_THROW(proxy::requireGravityAlongMinusZ(d));
  for (const char* bad : {"(0 -9.81 0)", "(0 0 9.81)", "(-9.81 0 0)", "(0 0.1 -9.81)"}) {
    writeG(bad);
    const std::string error = inputError([&] { proxy::requireGravityAlongMinusZ(d); });
    EXPECT_NE(error.find("constant/g: value = "), std::string::npos) << bad << ": " << error;
    EXPECT_NE(error.find("gravity must point along -z"), std::string::npos) << bad << ": " << error;
    EXPECT_NE(error.find("transformPoints"), std::string::npos) << bad << ": " << error;
  }
  writeG("(0 0 -9.81x)");
  EXPECT_NE(inputError([&] { proxy::requireGravityAlongMinusZ(d); }).find("'-9.81x' is not a number"), std::string::npos);

  // sample refuses the case before reading anything.
  writeG("(0 -9.81 0)");
  proxy::SampleOptions o;
  o.caseDir = d;
  o.output = d / "storm.nc";
  const std::string error = inputError([&] { proxy::sampleSurfaces(o); });
  EXPECT_NE(error.find("transformPoints"), std::string::npos) << error;
  EXPECT_FALSE(fs::exists(o.output));
  fs::remove_all(d);
}

TEST(CaseChecks, SourceCaseIsWrittenAsTheSamplerWritesIt) {
  // The function object writes the case's global path, absolute and without a trailing '/'.
  const fs::path d = tempDir("source-case");
  const std::string expected = fs::canonical(d).string();
  EXPECT_EQ(proxy::sourceCasePath(d), expected);
  EXPECT_EQ(proxy::sourceCasePath(d / ""), expected);        // "case/"
  EXPECT_EQ(proxy::sourceCasePath(d / "."), expected);       // "case/." (foam-proxy's default --case .)
  EXPECT_EQ(proxy::sourceCasePath(d / "x" / ".."), expected);
  EXPECT_EQ(proxy::sourceCasePath("/"), "/");
  fs::remove_all(d);
}
