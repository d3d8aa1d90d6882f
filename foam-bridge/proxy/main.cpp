// SPDX-License-Identifier: GPL-3.0-or-later
// foam-proxy: the portable path from OpenFOAM to the storm file (docs/foam-bridge.md).
//   foam-proxy sample  --case DIR --x-min .. --nx .. -o storm.nc   surfaces/sets output -> storm file
//   foam-proxy dict    --x-min .. --nx .. --patches 'unit.*'        the function-object dictionaries
//   foam-proxy combine --sea-state 2d.nc --variability 3d.nc -o storm.nc
//   foam-proxy compare --reference 3d.nc run1.nc run2.nc ...       alpha/beta calibration metrics
//   foam-proxy fit     deviations.txt                              Weibull MLE of a column of numbers

#include "bridge/WeibullMle.hpp"
#include "proxy/CaseChecks.hpp"
#include "proxy/ProxyRun.hpp"

#include "core/BuildInfo.hpp"
#include "core/Error.hpp"
#include "core/Log.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/os.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <stdexcept>

using namespace armour;

namespace {

std::string commandLine(int argc, char** argv) {
  std::string s;
  for (int i = 0; i < argc; ++i) s += (i ? " " : "") + std::string(argv[i]);
  return s;
}

storm::Provenance provenance(const std::string& command, const std::string& title, const std::string& comment) {
  storm::Provenance p;
  p.software = "armour foam-proxy " + core::version();
  p.command = command;
  p.title = title;
  p.comment = comment;
  p.openfoamVersion = "v1912";
  return p;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"foam-proxy: OpenFOAM surfaces output -> armour storm file (docs/foam-bridge.md)"};
  app.require_subcommand(1);
  const std::string command = commandLine(argc, argv);

  // ---- sample (and dict, which takes the same settings) ----
  proxy::SampleOptions so;
  std::string title, comment, forcesCsv;
  bool doublePrecision = false;
  std::vector<double> centreAt;
  auto addSettings = [&so, &centreAt](CLI::App* c) {
    c->add_option("--surfaces-function", so.surfacesFunction, "name of the surfaces function object (3D)")->capture_default_str();
    c->add_option("--units-surface", so.unitsSurface, "surface of the unit patches (p, alpha)")->capture_default_str();
    c->add_option("--cells-surface", so.cellsSurface, "patchInternalField surface of the unit patches (U); '' = U of the units surface")->capture_default_str();
    c->add_option("--sets-function", so.setsFunction, "name of the sets function object")->capture_default_str();
    c->add_option("--eta-set", so.etaSet, "cellCentre set of the eta band")->capture_default_str();
    c->add_option("--centres-function", so.centresFunction, "sets function object of the voxel centres (2D; "
                  "absent: the sets function object's folder)")->capture_default_str();
    c->add_option("--centres-set", so.centresSet, "cloud set of the voxel centres (2D)")->capture_default_str();
    c->add_option("--p-field", so.pField)->capture_default_str();
    c->add_option("--u-field", so.uField)->capture_default_str();
    c->add_option("--alpha-field", so.alphaField)->capture_default_str();
    c->add_flag("--2d", so.twoD, "2D run: cell values at the voxel centres (cloud set)");
    c->add_option("--x-min", so.sampler.grid.xMin, "x of the first voxel column's offshore face (m)")->required();
    c->add_option("--z-min", so.sampler.grid.zMin, "z of the first voxel row's bottom face (m)")->required();
    c->add_option("--dx", so.sampler.grid.dx, "voxel width (m)")->capture_default_str();
    c->add_option("--dz", so.sampler.grid.dz, "voxel height (m)")->capture_default_str();
    c->add_option("--nx", so.sampler.grid.nx, "voxel columns")->required();
    c->add_option("--nz", so.sampler.grid.nz, "voxel rows")->required();
    c->add_option("--trunk-origin", so.sampler.grid.trunkOrigin, "y where the averaged trunk section starts (m)")->required();
    c->add_option("--trunk-length", so.sampler.grid.trunkLength, "length of the trunk section (m)")->required();
    c->add_flag("--uniform-along-y", so.sampler.uniformAlongY, "the fields hold at every y (a 2D tank): the storm "
                "file says uniform_along_y = 1 and the solver loads units at any y, not only on the trunk section");
    c->add_option("--swl", so.sampler.stillWaterLevel, "z of the still water level (m)")->required();
    c->add_option("--rho", so.sampler.waterDensity, "water density (kg/m^3)")->capture_default_str();
    c->add_option("--g", so.sampler.gravity, "|g| (m/s^2)")->capture_default_str();
    c->add_option("--wet-alpha", so.sampler.wetAlpha, "alpha at and above which a cell is wet (-)")->capture_default_str();
    c->add_option("--eta-plane-y", so.sampler.etaPlaneY, "y of the middle of the eta band (m); default: trunk middle");
    c->add_option("--eta-half-width", so.sampler.etaHalfWidth, "half width of the eta band along y (m); default: dz/2");
    c->add_option("--eta-column-half-width", so.sampler.etaColumnHalfWidth, "cells within this x distance of a column centre give its eta (m); default: dx/2");
    c->add_option("--amplitude", so.sampler.normalisationAmplitude, "a_n of P_n = rho g a_n (m); 0 = from eta")->capture_default_str();
    c->add_option("--p-ref", so.sampler.pressureReference, "subtracted from p (Pa)")->capture_default_str();
    c->add_option("--min-samples", so.sampler.minimumSamples, "fewest faces per voxel for deviations")->capture_default_str();
    c->add_option("--centre-at", centreAt, "X Z: move --x-min and --z-min by at most half a voxel so that voxel "
                  "centres lie at x = X and z = Z (e.g. on the flat faces of axis-aligned units; docs/foam-bridge.md, "
                  "\"Where the voxels sit\")")->expected(2);
  };
  CLI::App* sample = app.add_subcommand("sample", "read the surfaces and sets output of a run and write a storm file");
  addSettings(sample);
  sample->add_option("--case", so.caseDir, "OpenFOAM case folder")->default_val(".");
  sample->add_option("-o,--output", so.output, "storm file to write (.nc)")->required();
  sample->add_option("--start", so.startTime, "first sample time (s)");
  sample->add_option("--end", so.endTime, "last sample time (s)");
  sample->add_flag("--double", doublePrecision, "store data as double (default float)");
  sample->add_option("--deflate", so.write.deflateLevel, "deflate level 0-9")->capture_default_str();
  sample->add_option("--title", title, "title of the storm");
  sample->add_option("--comment", comment, "free text");
  sample->add_option("--forces-csv", forcesCsv, "write time, Fx, Fy, Fz of the summed face pressures (N) here");

  std::vector<std::string> patches{"unit.*"};
  double interval = 0.05;
  std::string samplerLibrary = "libarmourSampler.so";
  std::string dictOutput, dictCase, which = "both";
  CLI::App* dict = app.add_subcommand("dict", "write the function-object dictionaries (armourSampler, surfaces, sets)");
  addSettings(dict);
  dict->add_option("--patches", patches, "armour-unit patch names or regular expressions")->capture_default_str();
  dict->add_option("--interval", interval, "sampling interval (s)")->capture_default_str();
  dict->add_option("--sampler-library", samplerLibrary, "libs entry of armourSampler")->capture_default_str();
  dict->add_option("-o,--output", dictOutput, "file to write (default: standard output)");
  dict->add_option("--case", dictCase, "the case the dictionaries are for: its constant/g and constant/dynamicMeshDict "
                   "are checked (default: the folder above system/ when -o is CASE/system/FILE)");
  dict->add_option("--function-objects", which, "both, sampler (armourSampler) or stock (surfaces and sets)")->capture_default_str();
  dict->add_option("--surface-format", so.surfaceFormat, "surfaces output: raw (text, double precision) or vtk "
                   "(binary, float; face areas for sample --forces-csv)")->capture_default_str();

  // ---- combine ----
  std::string seaState, variabilityFrom, combined;
  CLI::App* combine = app.add_subcommand("combine", "2D sea-state storm + variability of a 3D regular-wave storm");
  combine->add_option("--sea-state", seaState, "storm file of the 2D sea-state run")->required();
  combine->add_option("--variability", variabilityFrom, "storm file of the 3D run with the variability model")->required();
  combine->add_option("-o,--output", combined, "storm file to write")->required();
  combine->add_option("--title", title);

  // ---- compare ----
  std::string reference, csv;
  std::vector<std::string> candidates;
  double maxLag = 1.0;
  CLI::App* compare = app.add_subcommand("compare", "compare 2D storm files with the y-averaged 3D pressures");
  compare->add_option("--reference", reference, "storm file of the 3D run")->required();
  compare->add_option("candidates", candidates, "storm files of the 2D runs")->required();
  compare->add_option("--max-lag", maxLag, "largest phase lag searched (s)")->capture_default_str();
  compare->add_option("--csv", csv, "write the ranked table here");

  // ---- fit ----
  std::string samplesFile;
  CLI::App* fit = app.add_subcommand("fit", "Weibull MLE of positive numbers, one per line");
  fit->add_option("file", samplesFile)->required();

  CLI11_PARSE(app, argc, argv);
  auto log = core::logger("foam-proxy");
  try {
    if (centreAt.size() == 2) {
      const bridge::VoxelGridSettings before = so.sampler.grid;
      bridge::centreVoxelsOn(so.sampler.grid, centreAt[0], centreAt[1]);
      log->info("--centre-at {} {}: x-min {} -> {} m, z-min {} -> {} m (voxel centres at x = {} m and z = {} m)",
                centreAt[0], centreAt[1], before.xMin, so.sampler.grid.xMin, before.zMin, so.sampler.grid.zMin,
                centreAt[0], centreAt[1]);
    }
    if (*sample) {
      so.write.doublePrecision = doublePrecision;
      so.provenance = provenance(command, title, comment);
      so.provenance.sourceCase = proxy::sourceCasePath(so.caseDir);
      const auto start = std::chrono::steady_clock::now();
      const proxy::SampleSummary s = proxy::sampleSurfaces(so);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      log->info("wrote {}: {} records, {} sample points ({} in the grid), {} voxels with data, {:.2f} s ({:.3g} "
                "samples/s)", so.output.string(), s.records, s.samplePoints, s.samplePointsInGrid, s.voxelsWithData,
                seconds, static_cast<double>(s.samplePoints * s.records) / seconds);
      if (s.variability.present) {
        for (int c = 0; c < storm::kVariabilityClasses; ++c) {
          const storm::WeibullFit& f = s.variability.classes[static_cast<std::size_t>(c)];
          log->info("  {:13s} shape {:.4g} scale {:.4g} KS {:.4f} from {} deviations", storm::kVariabilityClassNames[c],
                    f.shape, f.scale, f.ksStatistic, f.samples);
        }
        log->info("  P(above) crest {:.3f} trough {:.3f}; P_n {:.6g} Pa, a_n {:.6g} m", s.variability.probabilityAbove[0],
                  s.variability.probabilityAbove[1], s.variability.normalisationPressure,
                  s.variability.normalisationElevation);
      } else {
        log->info("  no variability model: {}", s.variability.source);
      }
      if (!forcesCsv.empty()) {
        if (s.pressureForce.size() != 3 * s.times.size()) {
          core::failInput("--forces-csv", "the surfaces output has no face areas (surfaceFormat raw): write it with "
                                          "`foam-proxy dict --surface-format vtk` to get the pressure force");
        }
        std::ofstream out(forcesCsv);
        out << "time_s,Fx_N,Fy_N,Fz_N\n";
        for (std::size_t k = 0; k < s.times.size() && 3 * k + 2 < s.pressureForce.size(); ++k) {
          out << fmt::format("{},{:.12g},{:.12g},{:.12g}\n", s.times[k], s.pressureForce[3 * k],
                             s.pressureForce[3 * k + 1], s.pressureForce[3 * k + 2]);
        }
      }
    } else if (*dict) {
      // The case's refusals first (issue 23): nothing is written for a case the function objects cannot sample.
      std::filesystem::path caseDir = dictCase;
      if (caseDir.empty() && !dictOutput.empty()) {
        const std::filesystem::path system = std::filesystem::absolute(dictOutput).parent_path();
        if (system.filename() == "system") caseDir = system.parent_path();
      }
      if (!caseDir.empty()) {
        proxy::requireStaticMesh(caseDir);
        proxy::requireGravityAlongMinusZ(caseDir);
      }
      const std::string text = proxy::functionDictionaries(so, patches, interval, samplerLibrary, which);
      if (dictOutput.empty()) {
        std::fputs(text.c_str(), stdout);
      } else {
        // Written whole or not at all: a temporary file next to it, renamed into place.
        const std::string partial = dictOutput + ".partial";
        {
          std::ofstream out(partial);
          out << text;
          out.close();
          if (!out) core::failInput(partial, "cannot write the file; check the folder exists and is writable");
        }
        std::error_code ec;
        std::filesystem::rename(partial, dictOutput, ec);
        if (ec) core::failInput(dictOutput, "cannot move '{}' into place ({})", partial, ec.message());
      }
    } else if (*combine) {
      storm::StormWriteOptions write;
      proxy::combineStorms(seaState, variabilityFrom, combined, provenance(command, title, ""), write);
      log->info("wrote {}: the records of {} with the variability of {}", combined, seaState, variabilityFrom);
    } else if (*compare) {
      std::vector<proxy::Comparison> results;
      for (const std::string& c : candidates) results.push_back(proxy::compareStorms(reference, c, maxLag));
      std::stable_sort(results.begin(), results.end(), [](const proxy::Comparison& a, const proxy::Comparison& b) {
        return a.normalisedError < b.normalisedError;
      });
      std::string table = "rank,candidate,normalised_error,rmse_Pa,phase_lag_s,correlation,voxels,records\n";
      for (std::size_t i = 0; i < results.size(); ++i) {
        const proxy::Comparison& r = results[i];
        table += fmt::format("{},{},{:.6g},{:.6g},{:.4g},{:.6f},{},{}\n", i + 1, r.candidate, r.normalisedError, r.rmse,
                             r.phaseLag, r.correlation, r.voxels, r.records);
      }
      std::fputs(table.c_str(), stdout);
      if (!csv.empty()) std::ofstream(csv) << table;
    } else if (*fit) {
      std::ifstream in(samplesFile);
      if (!in) core::failInput(samplesFile, "cannot open the file");
      std::vector<double> d;
      double v;
      while (in >> v) d.push_back(v);
      storm::WeibullFit f;
      try {
        f = bridge::fitWeibull(d);
      } catch (const std::invalid_argument& e) {
        core::failInput(samplesFile, "{}", e.what());
      }
      std::printf("shape %.8g\nscale %.8g\nks %.6g\nsamples %lld\n", f.shape, f.scale, f.ksStatistic,
                  static_cast<long long>(f.samples));
    }
  } catch (const std::exception& e) {
    log->error("{}", e.what());
    return 1;
  }
  return 0;
}
