// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ProxyRun.hpp
/// The commands of foam-proxy (docs/foam-bridge.md):
///  - sampleSurfaces: the `surfaces` output of a run -> storm file, with the same statistics as the
///    armourSampler function object (bridge/VoxelStatistics);
///  - combineStorms: a 2D sea-state storm + the variability model of a 3D regular-wave storm;
///  - compareStorms: a 2D run against the y-averaged 3D pressures (the alpha/beta calibration).

#include "bridge/DeviationHistogram.hpp"
#include "bridge/VoxelStatistics.hpp"
#include "storm/StormFile.hpp"

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace armour::proxy {

struct SampleOptions {
  bridge::SamplerSettings sampler;
  std::filesystem::path caseDir;            ///< the OpenFOAM case
  std::string surfacesFunction = "armourSurfaces"; ///< name of the surfaces function object (3D)
  std::string unitsSurface = "units";       ///< patch surface: p and alpha on the unit faces
  std::string cellsSurface = "unitCells";   ///< patchInternalField surface: U of the wall cells ("" = U of `units`)
  std::string surfaceFormat = "raw";        ///< surfaces output that `dict` asks for: raw (text, double) or vtk (binary, float)
  std::string setsFunction = "armourSets";  ///< name of the sets function object
  std::string etaSet = "etaCells";          ///< cellCentre set of the eta band: alpha at the cell centres
  std::string centresFunction = "armourCentres"; ///< sets function object of the voxel centres (2D runs; else in setsFunction)
  std::string centresSet = "voxelCentres";  ///< cloud set of the voxel centres: p, U, alpha (2D runs)
  std::string pField = "p";
  std::string uField = "U";
  std::string alphaField = "alpha.water";
  bool twoD = false;                        ///< 2D run: cell values at the voxel centres (centresSet)
  double startTime = -std::numeric_limits<double>::infinity(); ///< first record (unit: s)
  double endTime = std::numeric_limits<double>::infinity();    ///< last record (unit: s)
  std::filesystem::path output;             ///< the storm file
  storm::StormWriteOptions write;
  storm::Provenance provenance;
};

struct SampleSummary {
  std::size_t records = 0;
  std::size_t samplePoints = 0;       ///< faces (3D) or voxel centres (2D) read
  std::size_t samplePointsInGrid = 0; ///< of those, in a voxel
  /// Mean interpolation weight on voxels without data at the faces in the grid (3D; VoxelStatistics::addGapWeight) (unit: -)
  double gapWeight = 0.0;
  std::size_t voxelsWithData = 0;
  bridge::DeviationHistogram histogram;
  storm::Variability variability;
  std::vector<double> pressureForce;  ///< 3 per record: sum of p S_f over the unit faces (unit: N); empty from raw surfaces (no areas)
  std::vector<double> times;          ///< unit: s
};

/// The function-object dictionaries for a case (foam-proxy dict): armourSampler, and the stock
/// surfaces and sets function objects that foam-proxy reads, with the same settings.
/// `which`: "both", "sampler" (armourSampler only) or "stock" (surfaces and sets only).
std::string functionDictionaries(const SampleOptions& options, const std::vector<std::string>& patches,
                                 double interval, const std::string& samplerLibrary,
                                 const std::string& which = "both");

/// Read postProcessing/<surfacesFunction>/<time>/*.raw or *.vtk (3D) and postProcessing/<setsFunction>/<time>/*.xy
/// of the case and write the storm file.
SampleSummary sampleSurfaces(const SampleOptions& options);

/// Write `output`: the records and grid of `seaState` with the variability model of `variabilityFrom`.
void combineStorms(const std::filesystem::path& seaState, const std::filesystem::path& variabilityFrom,
                   const std::filesystem::path& output, const storm::Provenance& provenance,
                   const storm::StormWriteOptions& write);

/// Agreement of a candidate (2D) storm with a reference (3D) storm at the voxels where both have data.
struct Comparison {
  std::string candidate;
  std::size_t voxels = 0;       ///< voxels compared
  std::size_t records = 0;      ///< reference records compared
  double rmse = 0.0;            ///< root mean square of p_candidate - p_reference (unit: Pa)
  double normalisedError = 0.0; ///< rmse / rms of the reference about each voxel's time mean (unit: -)
  double phaseLag = 0.0;        ///< shift of the candidate that best correlates the voxel-summed pressures (unit: s); > 0: candidate late
  double correlation = 0.0;     ///< correlation coefficient at zero lag of the voxel-summed pressures (unit: -)
};

/// The candidate is interpolated linearly in time to the reference record times within both runs.
/// The grids must share voxel centres (to 1e-6 m) where they overlap. maxLag bounds the lag search (s).
Comparison compareStorms(const std::filesystem::path& reference, const std::filesystem::path& candidate,
                         double maxLag = 1.0);

} // namespace armour::proxy
