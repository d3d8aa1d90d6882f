// SPDX-License-Identifier: GPL-3.0-or-later
#include "proxy/ProxyRun.hpp"

#include "proxy/CaseChecks.hpp"
#include "proxy/SurfaceSeries.hpp"

#include "core/Error.hpp"
#include "core/Log.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace armour::proxy {

namespace fs = std::filesystem;

namespace {

/// The core's std::invalid_argument (C++11, no fmt) becomes the house's InputError here.
template <typename F>
auto bridgeCall(const std::string& where, F&& f) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    core::failInput(where, "{}", e.what());
  }
}

void requireSameFaces(const Surface& a, const Surface& b) {
  if (a.faces() != b.faces()) {
    core::failInput(b.source, "{} faces but {} has {}: the two surfaces must sample the same patches",
                    b.faces(), a.source, a.faces());
  }
  for (std::size_t f = 0; f < a.faces(); ++f) {
    const double d = std::abs(a.centreX[f] - b.centreX[f]) + std::abs(a.centreY[f] - b.centreY[f]) +
                     std::abs(a.centreZ[f] - b.centreZ[f]);
    if (d > 1e-6) {
      core::failInput(b.source, "face {} is at ({}, {}, {}) m but at ({}, {}, {}) m in {}: the surfaces must list "
                                "the same faces in the same order (same `patches`)", f, b.centreX[f], b.centreY[f],
                      b.centreZ[f], a.centreX[f], a.centreY[f], a.centreZ[f], a.source);
    }
  }
}

} // namespace

SampleSummary sampleSurfaces(const SampleOptions& o) {
  auto log = core::logger("foam-proxy");
  // The armourSampler's refusals (issue 23): a changing mesh, gravity not along -z.
  requireStaticMesh(o.caseDir);
  requireGravityAlongMinusZ(o.caseDir);
  const fs::path setsFolder = o.caseDir / "postProcessing" / o.setsFunction;
  const fs::path surfacesFolder = o.caseDir / "postProcessing" / o.surfacesFunction;
  std::vector<SampleTime> times = listSampleTimes(setsFolder);
  std::erase_if(times, [&o](const SampleTime& t) { return t.time < o.startTime || t.time > o.endTime; });
  if (times.size() < 2) {
    core::failInput(setsFolder.string(), "{} sample time(s) between {} s and {} s: a storm file needs at least 2",
                    times.size(), o.startTime, o.endTime);
  }
  bridge::VoxelStatistics stats = bridgeCall("foam-proxy settings", [&] { return bridge::VoxelStatistics(o.sampler); });
  const std::vector<std::string> names = {o.pField, o.uField, o.alphaField};
  SampleSummary summary;

  std::unique_ptr<storm::StormWriter> writer;
  bridge::SampleValues values;
  std::vector<double> sums, levels;
  storm::StormRecord record;
  for (const SampleTime& t : times) {
    const PointSet eta = readPointSet(t.folder, o.etaSet, names, {o.alphaField});
    const std::vector<double>& etaAlpha = eta.field(o.alphaField, 1);
    PointSet centres;
    Surface units, cells;
    const Surface* uSource = nullptr;
    if (o.twoD) {
      // The centres' own function object (foam-proxy dict), or the sets one (earlier dictionaries).
      const fs::path own = o.caseDir / "postProcessing" / o.centresFunction / t.folder.filename();
      centres = readPointSet(fs::is_directory(own) ? own : t.folder, o.centresSet, names);
    } else {
      const fs::path folder = surfacesFolder / t.folder.filename();
      units = readSurfaceIn(folder, o.unitsSurface, names);
      uSource = &units;
      if (!o.cellsSurface.empty()) {
        cells = readSurfaceIn(folder, o.cellsSurface, names);
        requireSameFaces(units, cells);
        uSource = &cells;
      }
    }
    if (!writer) {
      // Geometry, once (the mesh does not move): the unit faces, or the voxel centres found in cells.
      if (o.twoD) {
        std::vector<double> y(centres.size(), stats.grid().trunkMiddle());
        stats.setSamplePoints(centres.x, y, centres.z);
      } else {
        stats.setSamplePoints(units.centreX, units.centreY, units.centreZ);
      }
      stats.setCounts(stats.localCounts());
      summary.samplePoints = stats.samplePoints();
      summary.samplePointsInGrid = static_cast<std::size_t>(
          std::count_if(stats.pointVoxel().begin(), stats.pointVoxel().end(), [](long v) { return v >= 0; }));
      summary.voxelsWithData = static_cast<std::size_t>(
          std::count_if(stats.counts().begin(), stats.counts().end(), [](std::int32_t c) { return c > 0; }));
      if (summary.voxelsWithData == 0) {
        core::failInput(o.caseDir.string(), "none of the {} sample points falls in the voxel grid (x from {} m, z from "
                        "{} m, {} x {} voxels, trunk y from {} m over {} m): check the grid and trunk settings",
                        summary.samplePoints, o.sampler.grid.xMin, o.sampler.grid.zMin, o.sampler.grid.nx,
                        o.sampler.grid.nz, o.sampler.grid.trunkOrigin, o.sampler.grid.trunkLength);
      }
      if (!o.twoD) {
        double weight = 0.0, points = 0.0;
        stats.addGapWeight(weight, points);
        summary.gapWeight = points > 0.0 ? weight / points : 0.0;
        log->info("at the unit faces, {:.3g} % of the interpolation weight falls on voxels without data",
                  100.0 * summary.gapWeight);
        if (summary.gapWeight > bridge::VoxelStatistics::kGapWeightWarning) {
          log->warn("{}", bridge::VoxelStatistics::gapWeightWarning(summary.gapWeight));
        }
      }
      storm::StormHeader header = stats.header(!o.twoD);
      header.provenance = o.provenance;
      writer = std::make_unique<storm::StormWriter>(o.output.string(), header, o.write);
      log->info("{}: {} sample points, {} in the grid, {} voxels with data, eta from {} cells; {} records from {} s "
                "to {} s", o.caseDir.string(), summary.samplePoints, summary.samplePointsInGrid,
                summary.voxelsWithData, eta.size(), times.size(), times.front().time, times.back().time);
    }
    if (stats.samplePoints() != (o.twoD ? centres.size() : units.faces())) {
      core::failInput((o.twoD ? centres.source : units.source), "{} sample points, but {} at the first sample time: the "
                      "mesh and the sampled patches must not change", o.twoD ? centres.size() : units.faces(),
                      stats.samplePoints());
    }

    // Values of this record at the sample points.
    values.resize(stats.samplePoints());
    if (o.twoD) {
      const std::vector<double>& p = centres.field(o.pField, 1);
      const std::vector<double>& u = centres.field(o.uField, 3);
      const std::vector<double>& alpha = centres.field(o.alphaField, 1);
      for (std::size_t i = 0; i < centres.size(); ++i) {
        values.p[i] = p[i];
        values.u[i] = u[3 * i];
        values.v[i] = u[3 * i + 1];
        values.w[i] = u[3 * i + 2];
        values.alpha[i] = alpha[i];
      }
    } else {
      const std::vector<double>& p = units.field(o.pField, 1);
      const std::vector<double>& alpha = units.field(o.alphaField, 1);
      const std::vector<double>& u = uSource->field(o.uField, 3);
      for (std::size_t i = 0; i < units.faces(); ++i) {
        values.p[i] = p[i];
        values.u[i] = u[3 * i];
        values.v[i] = u[3 * i + 1];
        values.w[i] = u[3 * i + 2];
        values.alpha[i] = alpha[i];
      }
      if (units.hasGeometry()) {
        // The force of the face pressures needs the face areas: vtk/vtp output only (raw has none).
        double force[3] = {0.0, 0.0, 0.0};
        for (std::size_t i = 0; i < units.faces(); ++i) {
          const double pg = p[i] - o.sampler.pressureReference;
          force[0] += pg * units.areaX[i];
          force[1] += pg * units.areaY[i];
          force[2] += pg * units.areaZ[i];
        }
        summary.pressureForce.insert(summary.pressureForce.end(), force, force + 3);
      }
    }
    stats.sums(values, sums);
    stats.initColumnLevels(levels);
    for (int pass = 0; pass < bridge::VoxelStatistics::kEtaPasses; ++pass) {
      for (std::size_t i = 0; i < eta.size(); ++i) {
        if (stats.inEtaBand(eta.y[i])) stats.addEtaCell(pass, levels, eta.x[i], eta.z[i], etaAlpha[i]);
      }
    }
    stats.finishRecord(t.time, sums, levels, !o.twoD, record);
    if (!o.twoD) stats.addDeviations(values, record, summary.histogram);
    stats.observeEta(record.eta);
    writer->append(record);
    summary.times.push_back(t.time);
  }
  const std::string source = fmt::format("foam-proxy sample of {} ({} records, {} to {} s)", o.caseDir.string(),
                                         times.size(), times.front().time, times.back().time);
  summary.variability = bridgeCall("foam-proxy variability", [&] { return stats.variability(summary.histogram, source); });
  writer->setVariability(summary.variability);
  writer->finish();
  summary.records = times.size();
  return summary;
}

std::string functionDictionaries(const SampleOptions& o, const std::vector<std::string>& patches, double interval,
                                 const std::string& samplerLibrary, const std::string& which) {
  if (which != "both" && which != "sampler" && which != "stock") {
    core::failInput("--function-objects", "'{}': choose both, sampler (armourSampler) or stock (surfaces and sets)", which);
  }
  if (o.surfaceFormat != "raw" && o.surfaceFormat != "vtk") {
    core::failInput("--surface-format", "'{}': choose raw (text, the case's writePrecision digits: double) or vtk "
                                        "(binary legacy VTK: float, face areas for --forces-csv)", o.surfaceFormat);
  }
  const bool sampler = which != "stock", stock = which != "sampler";
  const bridge::VoxelStatistics stats = bridgeCall("foam-proxy dict", [&] { return bridge::VoxelStatistics(o.sampler); });
  const bridge::VoxelGridSettings& g = o.sampler.grid;
  const double x0 = stats.grid().xCentre(0) - stats.etaColumnHalfWidth(),
               x1 = stats.grid().xCentre(g.nx - 1) + stats.etaColumnHalfWidth(),
               y0 = stats.etaPlaneY() - stats.etaHalfWidth(),
               y1 = stats.etaPlaneY() + stats.etaHalfWidth();
  std::string patchList;
  for (const std::string& p : patches) {
    if (!patchList.empty()) patchList += ' ';
    patchList += '"';
    patchList += p;
    patchList += '"';
  }
  const std::string control = fmt::format(
      "        executeControl  adjustableRunTime;\n        executeInterval {0};\n"
      "        writeControl    adjustableRunTime;\n        writeInterval   {0};\n", interval);
  std::string d = fmt::format(
      "// Function objects of armour's foam-bridge, written by: foam-proxy dict (docs/foam-bridge.md).\n"
      "// Put them in the `functions` of system/controlDict. Either armourSampler (compiled) or the stock\n"
      "// surfaces and sets function objects (read by foam-proxy sample) is enough; both give the same storm file.\n"
      "// Set writePrecision 15 in controlDict: the sets output and the raw surfaces output are text with\n"
      "// that many digits (15: the offline storm file matches the online one to round-off; 8 would\n"
      "// keep p to ~1e-8 relative and eta to ~1e-7 m).\n\n");
  if (sampler) d += fmt::format(
      "    armourSampler\n    {{\n        type            armourSampler;\n        libs            (\"{}\");\n{}"
      "        twoD            {};\n        patches         ({});\n"
      "        grid            {{ xMin {}; zMin {}; dx {}; dz {}; nx {}; nz {}; }}\n"
      "        trunkOrigin     {};  // m\n        trunkLength     {};  // m\n"
      "        uniformAlongY   {};  // the fields hold at every y (2D tank)\n"
      "        stillWaterLevel {};  // m\n        rho             {};  // kg/m^3\n"
      "        etaPlaneY       {};  // m\n        etaHalfWidth    {};  // m\n        etaColumnHalfWidth {};  // m\n"
      "        normalisationAmplitude {};  // m, 0 = from the eta range\n        pRef            {};  // Pa\n"
      "        file            \"postProcessing/armourSampler/storm.nc\";\n    }}\n\n",
      samplerLibrary, control, o.twoD ? "true" : "false", patchList, g.xMin, g.zMin, g.dx, g.dz, g.nx, g.nz,
      g.trunkOrigin, g.trunkLength, o.sampler.uniformAlongY ? "true" : "false", o.sampler.stillWaterLevel,
      o.sampler.waterDensity, stats.etaPlaneY(), stats.etaHalfWidth(), stats.etaColumnHalfWidth(),
      o.sampler.normalisationAmplitude, o.sampler.pressureReference);
  if (!stock) return d;
  if (!o.twoD) {
    d += fmt::format(
        "    {}\n    {{\n        type            surfaces;\n        libs            (\"libsampling.so\");\n{}"
        "{}"
        "        fields          ({} {} {});\n        interpolationScheme cell;\n        surfaces\n        (\n"
        "            {} {{ type patch; patches ({}); interpolate false; triangulate false; }}\n"
        "            // U of the wall-adjacent cells (U on a no-slip wall is zero)\n"
        "            {} {{ type patchInternalField; patches ({}); offsetMode normal; distance 1e-6;\n"
        "                        interpolate false; triangulate false; }}\n        );\n    }}\n\n",
        o.surfacesFunction, control,
        o.surfaceFormat == "raw"
            ? "        // raw: face centres and values as text, writePrecision digits (double; vtk stores float)\n"
              "        surfaceFormat   raw;\n"
            : "        // vtk: binary legacy VTK, float values; the face areas give foam-proxy's --forces-csv\n"
              "        surfaceFormat   vtk;\n        formatOptions   { vtk { format binary; legacy true; } }\n",
        o.pField, o.alphaField, o.uField, o.unitsSurface, patchList, o.cellsSurface,
        patchList);
  }
  d += fmt::format(
      "    {}\n    {{\n        type            sets;\n        libs            (\"libsampling.so\");\n{}"
      "        setFormat       raw;\n        interpolationScheme cell;\n        fields          ({});\n"
      "        sets\n        (\n"
      "            // eta: the cell centres within etaHalfWidth of y = etaPlaneY\n"
      "            {} {{ type cellCentre; axis xyz; bounds ({:.12g} {:.12g} -1e6) ({:.12g} {:.12g} 1e6); }}\n",
      o.setsFunction, control, o.alphaField, o.etaSet, x0, y0, x1, y1);
  d += "        );\n    }\n";
  if (o.twoD) {
    // The voxel centres in a function object of their own: a sets function object has one fields
    // list for all its sets, and eta needs alpha only (with p and U too, the 2D smoke case wrote
    // 253 MB of eta text at 15 digits).
    d += fmt::format(
        "\n    {}\n    {{\n        type            sets;\n        libs            (\"libsampling.so\");\n{}"
        "        setFormat       raw;\n        interpolationScheme cell;\n        fields          ({} {} {});\n"
        "        sets\n        (\n"
        "            // 2D runs: the cell values at the voxel centres\n"
        "            {} {{ type cloud; axis xyz; points\n            (\n",
        o.centresFunction, control, o.alphaField, o.pField, o.uField, o.centresSet);
    for (int iz = 0; iz < g.nz; ++iz)
      for (int ix = 0; ix < g.nx; ++ix)
        d += fmt::format("                ({:.12g} {:.12g} {:.12g})\n", stats.grid().xCentre(ix), stats.etaPlaneY(),
                         stats.grid().zCentre(iz));
    d += "            ); }\n        );\n    }\n";
  }
  return d;
}

void combineStorms(const fs::path& seaState, const fs::path& variabilityFrom, const fs::path& output,
                   const storm::Provenance& provenance, const storm::StormWriteOptions& write) {
  const storm::StormReader variability(variabilityFrom.string());
  const storm::Variability& model = variability.header().variability;
  if (!model.present) {
    core::failInput(variabilityFrom.string(), "has no variability model (variability_present = 0): give the storm "
                                              "file of a 3D regular-wave run sampled on its armour-unit faces");
  }
  const storm::StormReader sea(seaState.string());
  storm::StormHeader header = sea.header();
  if (std::abs(header.waterDensity - variability.header().waterDensity) > 1e-6 * header.waterDensity) {
    core::logger("foam-proxy")->warn("water density {} kg/m^3 in {} but {} kg/m^3 in {}: the normalised "
                                     "deviations carry over; check that the runs belong together",
                                     header.waterDensity, seaState.string(), variability.header().waterDensity,
                                     variabilityFrom.string());
  }
  header.variability = model;
  header.variability.source = model.source + "; combined by foam-proxy from " + variabilityFrom.string();
  header.provenance = provenance;
  if (header.provenance.sourceCase.empty()) header.provenance.sourceCase = sea.header().provenance.sourceCase;
  if (header.provenance.openfoamVersion.empty()) header.provenance.openfoamVersion = sea.header().provenance.openfoamVersion;
  storm::StormWriter writer(output.string(), header, write);
  storm::StormRecord record;
  for (std::size_t k = 0; k < sea.times().size(); ++k) {
    sea.read(k, record);
    writer.append(record);
  }
  writer.finish();
}

namespace {

/// Map each reference voxel with data to the candidate voxel at the same centre (or -1).
std::vector<long> matchVoxels(const storm::StormHeader& r, const storm::StormHeader& c, const std::string& where) {
  std::vector<long> match(r.voxels(), -1);
  const double dx = c.dx(), dz = c.dz();
  for (std::size_t iz = 0; iz < r.nz(); ++iz) {
    for (std::size_t ix = 0; ix < r.nx(); ++ix) {
      if (r.samples[iz * r.nx() + ix] <= 0) continue;
      const double jx = std::round((r.x[ix] - c.x[0]) / dx), jz = std::round((r.z[iz] - c.z[0]) / dz);
      if (jx < 0 || jz < 0 || jx >= static_cast<double>(c.nx()) || jz >= static_cast<double>(c.nz())) continue;
      const std::size_t cx = static_cast<std::size_t>(jx), cz = static_cast<std::size_t>(jz);
      if (std::abs(c.x[cx] - r.x[ix]) > 1e-6 || std::abs(c.z[cz] - r.z[iz]) > 1e-6) {
        core::failInput(where, "voxel centres differ from the reference's (x {} vs {} m, z {} vs {} m): sample both "
                               "runs on the same grid", c.x[cx], r.x[ix], c.z[cz], r.z[iz]);
      }
      if (c.samples[cz * c.nx() + cx] <= 0) continue;
      match[iz * r.nx() + ix] = static_cast<long>(cz * c.nx() + cx);
    }
  }
  return match;
}

} // namespace

Comparison compareStorms(const fs::path& reference, const fs::path& candidate, double maxLag) {
  const storm::StormReader ref(reference.string());
  const storm::StormReader cand(candidate.string());
  const std::vector<long> match = matchVoxels(ref.header(), cand.header(), candidate.string());
  std::vector<std::size_t> rv;
  for (std::size_t v = 0; v < match.size(); ++v)
    if (match[v] >= 0) rv.push_back(v);
  if (rv.empty()) {
    core::failInput(candidate.string(), "no voxel has data in both this file and the reference {}: the grids do not "
                                        "overlap where the reference has data", reference.string());
  }
  const std::vector<double>& tc = cand.times();
  std::vector<std::size_t> records;
  for (std::size_t k = 0; k < ref.times().size(); ++k)
    if (ref.times()[k] >= tc.front() && ref.times()[k] <= tc.back()) records.push_back(k);
  if (records.size() < 2) {
    core::failInput(candidate.string(), "its times ({} to {} s) overlap fewer than 2 reference records", tc.front(),
                    tc.back());
  }
  // Reference and candidate pressures at the matched voxels, record by record.
  const std::size_t n = rv.size(), m = records.size();
  std::vector<double> pr(n * m), pc(n * m);
  storm::StormRecord a, b, rr;
  std::size_t loaded = static_cast<std::size_t>(-1);
  for (std::size_t j = 0; j < m; ++j) {
    const double t = ref.times()[records[j]];
    ref.read(records[j], rr);
    std::size_t k = static_cast<std::size_t>(std::upper_bound(tc.begin(), tc.end(), t) - tc.begin());
    k = std::min(std::max<std::size_t>(k, 1), tc.size() - 1); // interval [k-1, k]
    if (loaded != k) {
      cand.read(k - 1, a);
      cand.read(k, b);
      loaded = k;
    }
    const double s = (t - tc[k - 1]) / (tc[k] - tc[k - 1]);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t cvx = static_cast<std::size_t>(match[rv[i]]);
      pr[i * m + j] = rr.p[rv[i]];
      pc[i * m + j] = (1.0 - s) * a.p[cvx] + s * b.p[cvx];
    }
  }
  Comparison out;
  out.candidate = candidate.string();
  out.voxels = n;
  out.records = m;
  double se = 0.0, sr = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    double mean = 0.0;
    for (std::size_t j = 0; j < m; ++j) mean += pr[i * m + j];
    mean /= static_cast<double>(m);
    for (std::size_t j = 0; j < m; ++j) {
      se += (pc[i * m + j] - pr[i * m + j]) * (pc[i * m + j] - pr[i * m + j]);
      sr += (pr[i * m + j] - mean) * (pr[i * m + j] - mean);
    }
  }
  out.rmse = std::sqrt(se / static_cast<double>(n * m));
  out.normalisedError = sr > 0.0 ? std::sqrt(se / sr) : (se > 0.0 ? INFINITY : 0.0);
  // Phase lag: the shift (in reference records) maximising the correlation of the voxel-summed
  // pressures, refined by a parabola through the peak.
  std::vector<double> sumR(m, 0.0), sumC(m, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < m; ++j) {
      sumR[j] += pr[i * m + j];
      sumC[j] += pc[i * m + j];
    }
  const double meanR = std::accumulate(sumR.begin(), sumR.end(), 0.0) / static_cast<double>(m);
  const double meanC = std::accumulate(sumC.begin(), sumC.end(), 0.0) / static_cast<double>(m);
  for (double& v : sumR) v -= meanR;
  for (double& v : sumC) v -= meanC;
  const double dt = (ref.times()[records.back()] - ref.times()[records.front()]) / static_cast<double>(m - 1);
  const long maxShift = std::min<long>(static_cast<long>(std::ceil(maxLag / dt)), static_cast<long>(m / 2));
  auto corr = [&](long shift) {
    double sxy = 0.0, sxx = 0.0, syy = 0.0;
    for (long j = 0; j < static_cast<long>(m); ++j) {
      const long jc = j + shift;
      if (jc < 0 || jc >= static_cast<long>(m)) continue;
      sxy += sumR[static_cast<std::size_t>(j)] * sumC[static_cast<std::size_t>(jc)];
      sxx += sumR[static_cast<std::size_t>(j)] * sumR[static_cast<std::size_t>(j)];
      syy += sumC[static_cast<std::size_t>(jc)] * sumC[static_cast<std::size_t>(jc)];
    }
    return sxx > 0.0 && syy > 0.0 ? sxy / std::sqrt(sxx * syy) : 0.0;
  };
  long best = 0;
  double bestCorr = corr(0);
  out.correlation = bestCorr;
  for (long s = -maxShift; s <= maxShift; ++s) {
    const double c = corr(s);
    if (c > bestCorr) {
      bestCorr = c;
      best = s;
    }
  }
  double refine = 0.0;
  if (best > -maxShift && best < maxShift) {
    const double cm = corr(best - 1), c0 = bestCorr, cp = corr(best + 1);
    const double den = cm - 2.0 * c0 + cp;
    if (den < 0.0) refine = 0.5 * (cm - cp) / den;
  }
  out.phaseLag = (static_cast<double>(best) + refine) * dt;
  return out;
}

} // namespace armour::proxy
