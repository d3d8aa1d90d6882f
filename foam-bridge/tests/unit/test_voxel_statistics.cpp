// SPDX-License-Identifier: GPL-3.0-or-later
// The voxel grid and the per-record statistics (bridge/VoxelGrid, bridge/VoxelStatistics): binning
// at voxel faces and trunk ends, means, eta from the column cells, deviations by class, and the
// header handed to the storm writer.

#include "bridge/VoxelStatistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

using namespace armour::bridge;

namespace {

VoxelGridSettings smallGrid() {
  VoxelGridSettings g;
  g.xMin = 10.0; // a non-zero origin so that indices and coordinates are not confused
  g.zMin = -0.1;
  g.dx = 0.05;
  g.dz = 0.1;
  g.nx = 4;
  g.nz = 3;
  g.trunkOrigin = 2.0;
  g.trunkLength = 1.0;
  return g;
}

} // namespace

TEST(VoxelGrid, BinsByDivisionWithHalfOpenIntervals) {
  const VoxelGrid grid(smallGrid());
  EXPECT_EQ(grid.voxels(), 12u);
  EXPECT_EQ(grid.column(10.0), 0);
  EXPECT_EQ(grid.column(10.0499), 0);
  EXPECT_EQ(grid.column(10.0501), 1);
  EXPECT_EQ(grid.column(10.1999), 3);
  EXPECT_EQ(grid.column(10.2001), -1);   // beyond the far face of the last column
  EXPECT_EQ(grid.column(9.9999), -1);
  EXPECT_EQ(grid.row(-0.1), 0);
  EXPECT_EQ(grid.row(0.15), 2);
  EXPECT_EQ(grid.row(std::numeric_limits<double>::quiet_NaN()), -1);
  EXPECT_EQ(grid.voxel(10.07, 2.5, 0.05), 1 * 4 + 1);
  EXPECT_EQ(grid.voxel(10.07, 2.0, 0.05), 5);  // trunk ends are inside (closed interval)
  EXPECT_EQ(grid.voxel(10.07, 3.0, 0.05), 5);
  EXPECT_EQ(grid.voxel(10.07, 3.01, 0.05), -1);
  EXPECT_EQ(grid.voxel(10.07, 1.99, 0.05), -1);
  EXPECT_NEAR(grid.xCentre(3), 10.175, 1e-12);
  EXPECT_NEAR(grid.zCentre(0), -0.05, 1e-12);
  EXPECT_NEAR(grid.trunkMiddle(), 2.5, 1e-12);
}

// A face centre on a voxel boundary, computed two ways (mesh face centre online, recomputed from
// the written points offline), comes out a few ulp either side of it: both must land in the same
// voxel, the one above the boundary. 1e-12 m is ~1e3 ulp of x = 10 m, beyond any round-off of the
// two centre formulas; 1e-4 of a voxel below is a real position and stays in the voxel below.
TEST(VoxelGrid, CentresWithinRoundOffOfABoundaryGoAbove) {
  const VoxelGrid grid(smallGrid());
  const double boundaryX = 10.0 + 2 * 0.05, boundaryZ = -0.1 + 0.1;
  EXPECT_EQ(grid.column(std::nextafter(boundaryX, 0.0)), 2);
  EXPECT_EQ(grid.column(boundaryX - 1e-12), 2);
  EXPECT_EQ(grid.column(boundaryX + 1e-12), 2);
  EXPECT_EQ(grid.column(boundaryX - 1e-4 * 0.05), 1);
  EXPECT_EQ(grid.row(boundaryZ - 1e-12), 1);
  EXPECT_EQ(grid.row(boundaryZ + 1e-12), 1);
  EXPECT_EQ(grid.row(boundaryZ - 1e-4 * 0.1), 0);
  // The grid ends: the offshore face is in, the far face out, whichever side of them round-off puts a centre.
  EXPECT_EQ(grid.column(10.0 - 1e-12), 0);
  EXPECT_EQ(grid.column(10.2 - 1e-12), -1);
  EXPECT_EQ(grid.row(0.2 - 1e-12), -1);
  // The trunk ends are closed, also for centres a round-off outside them.
  EXPECT_EQ(grid.voxel(10.07, 2.0 - 1e-12, 0.05), 5);
  EXPECT_EQ(grid.voxel(10.07, 3.0 + 1e-12, 0.05), 5);
  EXPECT_EQ(grid.voxel(10.07, 2.0 - 1e-4, 0.05), -1);
}

TEST(VoxelGrid, RefusesBadSettings) {
  VoxelGridSettings g = smallGrid();
  g.nx = 1;
  EXPECT_THROW(VoxelGrid{g}, std::invalid_argument);
  g = smallGrid();
  g.dz = 0.0;
  EXPECT_THROW(VoxelGrid{g}, std::invalid_argument);
  g = smallGrid();
  g.trunkLength = -1.0;
  EXPECT_THROW(VoxelGrid{g}, std::invalid_argument);
  g = smallGrid();
  g.xMin = std::numeric_limits<double>::infinity();
  EXPECT_THROW(VoxelGrid{g}, std::invalid_argument);
}

// Hydrostatic pressure on faces at known heights: p is linear in z, so the voxel mean is
// rho g (SWL - mean z) to round-off, and the deviations are rho g |z - mean z| exactly.
TEST(VoxelStatistics, MeansEtaAndDeviationsOfAHydrostaticRecord) {
  SamplerSettings s;
  s.grid = smallGrid();
  s.stillWaterLevel = 0.3;
  s.waterDensity = 1000.0;
  s.gravity = 9.81;
  VoxelStatistics stats(s);
  const double rg = 1000.0 * 9.81;
  // Voxel (ix 1, iz 1): three faces at z = 0.01, 0.02, 0.06; voxel (ix 2, iz 0): one face; one face
  // outside the trunk and one outside the grid.
  const std::vector<double> x = {10.06, 10.07, 10.08, 10.11, 10.06, 11.0};
  const std::vector<double> y = {2.1, 2.5, 2.9, 2.5, 3.5, 2.5};
  const std::vector<double> z = {0.01, 0.02, 0.06, -0.05, 0.02, 0.0};
  stats.setSamplePoints(x, y, z);
  const std::vector<double> local = stats.localCounts();
  stats.setCounts(local);
  EXPECT_EQ(stats.counts()[5], 3);
  EXPECT_EQ(stats.counts()[2], 1);
  int total = 0;
  for (int c : stats.counts()) total += c;
  EXPECT_EQ(total, 4);

  SampleValues values;
  values.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    values.p[i] = rg * (0.3 - z[i]);
    values.u[i] = 1.0 + i;
    values.v[i] = 0.5;
    values.w[i] = -0.25;
    values.alpha[i] = 1.0;
  }
  std::vector<double> sums, levels;
  stats.sums(values, sums);
  stats.initColumnLevels(levels);
  // Cells of the eta band: column 1 wet up to the centre 0.25 (alpha 0.9) under a centre 0.35 with
  // alpha 0.3: alpha crosses 0.5 at 0.25 + (0.9 - 0.5) / (0.9 - 0.3) 0.1 = 0.3167 on the line
  // between them. Column 2 dry down to its lowest centre -0.05 (below SWL: a trough). Column 3: a
  // splash (alpha 0.8) above a dry cell with nothing above it counts at its centre (the highest
  // wet centre). Column 0 has no cells.
  EXPECT_TRUE(stats.inEtaBand(2.5));
  EXPECT_TRUE(stats.inEtaBand(2.55)); // half width dz / 2 = 0.05 m by default, closed
  EXPECT_FALSE(stats.inEtaBand(2.56));
  struct Cell {
    double x, z, alpha;
  };
  const Cell cells[] = {{10.075, 0.15, 1.0},  {10.075, 0.25, 0.9}, {10.075, 0.35, 0.3}, {10.075, 0.45, 0.0},
                        {10.125, -0.05, 0.1}, {10.175, 0.05, 0.0}, {10.175, 0.45, 0.8},
                        {9.0, 0.45, 1.0}}; // the last outside the grid: ignored
  for (int pass = 0; pass < VoxelStatistics::kEtaPasses; ++pass)
    for (const Cell& c : cells) stats.addEtaCell(pass, levels, c.x, c.z, c.alpha);
  armour::storm::StormRecord record;
  stats.finishRecord(1.5, sums, levels, true, record);
  EXPECT_EQ(record.time, 1.5);
  EXPECT_NEAR(record.p[5], rg * (0.3 - 0.03), 1e-9);
  EXPECT_NEAR(record.p[2], rg * (0.3 + 0.05), 1e-9);
  EXPECT_NEAR(record.u[5], (1.0 + 2.0 + 3.0) / 3.0, 1e-12);
  EXPECT_NEAR(record.v[5], 0.5, 1e-12);
  EXPECT_NEAR(record.w[5], -0.25, 1e-12);
  EXPECT_EQ(record.alpha[5], 1.0);
  EXPECT_EQ(record.p[0], 0.0); // no data
  ASSERT_EQ(record.eta.size(), 4u);
  EXPECT_EQ(record.eta[0], 0.0);
  EXPECT_NEAR(record.eta[1], 0.25 + 0.4 / 0.6 * 0.1 - 0.3, 1e-12);
  EXPECT_NEAR(record.eta[2], -0.05 - 0.3, 1e-12);
  EXPECT_NEAR(record.eta[3], 0.45 - 0.3, 1e-12);

  // Deviations only from the voxel with m = 3 (column 1, a crest: eta = +0.0167 m): +0.02, +0.01,
  // -0.03 m of head.
  DeviationHistogram h;
  stats.addDeviations(values, record, h);
  EXPECT_EQ(h.classCount(0), 2.0); // crest above (the two lower faces)
  EXPECT_EQ(h.classCount(1), 1.0); // crest below
  EXPECT_EQ(h.classCount(2) + h.classCount(3), 0.0);
  int bin = -1;
  for (int b = 0; b < DeviationHistogram::kBins; ++b) {
    if (h.binCount(1, b) > 0.0) bin = b;
  }
  ASSERT_GE(bin, 0);
  EXPECT_NEAR(DeviationHistogram::binCentre(bin) / (rg * 0.03), 1.0, 0.006); // within half a bin

  // Without velocity y the record has no v.
  stats.finishRecord(2.0, sums, levels, false, record);
  EXPECT_TRUE(record.v.empty());

  const armour::storm::StormHeader header = stats.header(true);
  EXPECT_EQ(header.nx(), 4u);
  EXPECT_NEAR(header.dz(), 0.1, 1e-12);
  EXPECT_EQ(header.samples[5], 3);
  EXPECT_EQ(header.stillWaterLevel, 0.3);
}

// A mesh coarser than the voxels: a cell centred between two column centres gives eta to both when
// etaColumnHalfWidth reaches them, and to no other column.
TEST(VoxelStatistics, CoarseCellsGiveEtaToEveryColumnWithinReach) {
  SamplerSettings s;
  s.grid = smallGrid();
  s.stillWaterLevel = 0.0;
  s.etaColumnHalfWidth = 0.04;
  VoxelStatistics stats(s);
  stats.setCounts(std::vector<double>(stats.grid().voxels(), 0.0));
  std::vector<double> levels, sums(VoxelStatistics::kSumFields * stats.grid().voxels(), 0.0);
  stats.initColumnLevels(levels);
  for (int pass = 0; pass < VoxelStatistics::kEtaPasses; ++pass)
    stats.addEtaCell(pass, levels, 10.1, 0.3, 1.0); // between the centres 10.075 and 10.125
  armour::storm::StormRecord record;
  stats.finishRecord(0.0, sums, levels, false, record);
  EXPECT_EQ(record.eta[0], 0.0); // no cell within reach
  EXPECT_NEAR(record.eta[1], 0.3, 1e-12);
  EXPECT_NEAR(record.eta[2], 0.3, 1e-12);
  EXPECT_EQ(record.eta[3], 0.0);
}

TEST(VoxelStatistics, NormalisationAmplitudeFromTheEtaRange) {
  SamplerSettings s;
  s.grid = smallGrid();
  VoxelStatistics stats(s);
  std::vector<double> counts(stats.grid().voxels(), 0.0);
  counts[1] = 2.0; // column 1 has data; column 0 does not
  stats.setCounts(counts);
  stats.observeEta({5.0, 0.4, 0.0, 0.0});
  stats.observeEta({-5.0, -0.2, 0.0, 0.0});
  std::string how;
  EXPECT_NEAR(stats.normalisationAmplitude(how), 0.3, 1e-12); // only the column with data
  VoxelStatistics calm(s);
  calm.setCounts(counts);
  calm.observeEta({0.0, 0.0, 0.0, 0.0});
  EXPECT_EQ(calm.normalisationAmplitude(how), 1.0);
  s.normalisationAmplitude = 2.0;
  VoxelStatistics given(s);
  EXPECT_EQ(given.normalisationAmplitude(how), 2.0);
}

TEST(VoxelStatistics, NoDeviationsMeansNoVariabilityModel) {
  SamplerSettings s;
  s.grid = smallGrid();
  VoxelStatistics stats(s);
  const armour::storm::Variability v = stats.variability(DeviationHistogram(), "test");
  EXPECT_FALSE(v.present);
}

TEST(VoxelStatistics, RefusesBadSettings) {
  SamplerSettings s;
  s.grid = smallGrid();
  s.wetAlpha = 0.0;
  EXPECT_THROW(VoxelStatistics{s}, std::invalid_argument);
  s = SamplerSettings();
  s.grid = smallGrid();
  s.waterDensity = -1.0;
  EXPECT_THROW(VoxelStatistics{s}, std::invalid_argument);
  s = SamplerSettings();
  s.grid = smallGrid();
  s.minimumSamples = 1;
  EXPECT_THROW(VoxelStatistics{s}, std::invalid_argument);
  s = SamplerSettings();
  s.grid = smallGrid();
  s.etaHalfWidth = 0.0;
  EXPECT_THROW(VoxelStatistics{s}, std::invalid_argument);
}

TEST(VoxelStatistics, GapWeightSaysWhetherVoxelEdgesOrCentresLieOnTheFaces) {
  // The vertical face x = 1 of a unit filling x > 1 (a 2D section: faces every 0.01 m from z = 0
  // to 0.6), on a grid of 0.1 m voxels. Its faces are the only sample points.
  const auto share = [](double xMin) {
    SamplerSettings s;
    s.grid.xMin = xMin;
    s.grid.zMin = 0.0;
    s.grid.dx = 0.1;
    s.grid.dz = 0.1;
    s.grid.nx = 10;
    s.grid.nz = 6;
    s.grid.trunkOrigin = 0.0;
    s.grid.trunkLength = 1.0;
    s.stillWaterLevel = 1.0;
    VoxelStatistics stats(s);
    std::vector<double> x, y, z;
    for (int k = 0; k < 60; ++k) {
      x.push_back(1.0);
      y.push_back(0.5);
      z.push_back(0.005 + 0.01 * k);
    }
    stats.setSamplePoints(x, y, z);
    stats.setCounts(stats.localCounts());
    double weight = 0.0, points = 0.0;
    stats.addGapWeight(weight, points);
    EXPECT_EQ(points, 60.0);
    return weight / points;
  };
  // Voxel edges on the face: its faces go to the voxel above (x 1.0 .. 1.1), the solver
  // interpolates at x = 1 half from it and half from the empty voxel in front: 0.5.
  EXPECT_NEAR(share(0.5), 0.5, 1e-12);
  // Column centres on the face: the whole weight on the column with the data.
  EXPECT_NEAR(share(0.45), 0.0, 1e-12);
  // A quarter of a voxel off: 0.25 on the empty voxel.
  EXPECT_NEAR(share(0.475), 0.25, 1e-9);
  EXPECT_GT(0.25, VoxelStatistics::kGapWeightWarning); // warned
  const std::string warning = VoxelStatistics::gapWeightWarning(0.5);
  EXPECT_NE(warning.find("50 %"), std::string::npos) << warning;
  EXPECT_NE(warning.find("Shift the grid (xMin, zMin)"), std::string::npos) << warning;
}

TEST(VoxelGrid, CentreVoxelsOnMovesTheOriginByAtMostHalfAVoxel) {
  VoxelGridSettings g = smallGrid(); // xMin 10, dx 0.05; zMin -0.1, dz 0.1
  // Edges on x = 10.2 and z = 0.2 (a tie): the origin moves down half a voxel.
  centreVoxelsOn(g, 10.2, 0.2);
  EXPECT_NEAR(g.xMin, 9.975, 1e-12);
  EXPECT_NEAR(g.zMin, -0.15, 1e-12);
  const VoxelGrid grid(g);
  EXPECT_NEAR(grid.xCentre(4), 10.2, 1e-12);
  EXPECT_NEAR(grid.zCentre(3), 0.2, 1e-12);
  // Already centred: nothing moves; a small offset: the nearest lattice.
  centreVoxelsOn(g, 10.2, 0.2);
  EXPECT_NEAR(g.xMin, 9.975, 1e-12);
  g.xMin = 9.99;
  centreVoxelsOn(g, 10.2, std::numeric_limits<double>::quiet_NaN());
  EXPECT_NEAR(g.xMin, 9.975, 1e-12);
  EXPECT_NEAR(g.zMin, -0.15, 1e-12); // NaN: z untouched
  g.xMin = 10.01;
  centreVoxelsOn(g, 10.2, std::numeric_limits<double>::quiet_NaN());
  EXPECT_NEAR(g.xMin, 10.025, 1e-12);
}
