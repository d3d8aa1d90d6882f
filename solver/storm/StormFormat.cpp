// SPDX-License-Identifier: GPL-3.0-or-later
#include "storm/StormFormat.hpp"

#include "core/Error.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstddef>

namespace armour::storm::detail {
namespace {

/// Relative tolerance of the uniform-spacing check of x and z. Coordinates written as x0 + i dx in
/// double differ from uniform by a few ulps of |x| (1e-13 relative to dx for |x| ~ 100 m, dx = 0.05 m);
/// a grid that is really non-uniform differs by far more than 1e-9.
constexpr double kUniformTolerance = 1e-9;

void checkAxis(const std::string& where, const std::string& label, const std::vector<double>& c) {
  if (c.size() < 2) {
    core::failInput(where, "{} has {} value(s): at least 2 voxel centres are needed (values are interpolated "
                           "between neighbours)", label, c.size());
  }
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!std::isfinite(c[i])) {
      core::failInput(where, "{}[{}] = {}: voxel centres must be finite (unit: m)", label, i, c[i]);
    }
  }
  const double d = c[1] - c[0];
  if (!(d > 0.0)) {
    core::failInput(where, "{}[0] = {} m, {}[1] = {} m: voxel centres must increase strictly; sort them", label, c[0],
                    label, c[1]);
  }
  for (std::size_t i = 1; i + 1 < c.size(); ++i) {
    const double di = c[i + 1] - c[i];
    if (!(std::abs(di - d) <= kUniformTolerance * d)) {
      core::failInput(where, "{}[{}] - {}[{}] = {} m but {}[1] - {}[0] = {} m: voxel centres must be uniformly "
                             "spaced (to 1e-9 relative); resample the fields onto a uniform grid",
                      label, i + 1, label, i, di, label, label, d);
    }
  }
}

void checkPositive(const std::string& where, const std::string& field, double value, const char* unitAndHint) {
  if (!(std::isfinite(value) && value > 0.0)) {
    core::failInput(where, "{} = {}: must be positive and finite ({})", field, value, unitAndHint);
  }
}

void checkFinite(const std::string& where, const std::string& field, double value, const char* unit) {
  if (!std::isfinite(value)) {
    core::failInput(where, "{} = {}: must be finite (unit: {})", field, value, unit);
  }
}

} // namespace

const std::vector<double>& recordArray(const StormRecord& r, int variable) {
  switch (variable) {
  case kP: return r.p;
  case kU: return r.u;
  case kV: return r.v;
  case kW: return r.w;
  default: return r.alpha;
  }
}

std::vector<double>& recordArray(StormRecord& r, int variable) {
  return const_cast<std::vector<double>&>(recordArray(static_cast<const StormRecord&>(r), variable));
}

/// Unit spellings a reader accepts besides the canonical one written (docs/storm-file.md, "Units").
const std::vector<std::string>& acceptedUnits(const std::string& canonical) {
  static const std::vector<std::string> metre{"m", "metre", "meter", "metres", "meters"};
  static const std::vector<std::string> second{"s", "second", "seconds", "sec"};
  static const std::vector<std::string> pascal{"Pa", "pascal", "pascals"};
  static const std::vector<std::string> velocity{"m s-1", "m/s", "m s^-1", "m.s-1"};
  static const std::vector<std::string> fraction{"1", "", "-", "m3 m-3", "m3/m3"};
  static const std::vector<std::string> none;
  if (canonical == "m") {
    return metre;
  }
  if (canonical == "s") {
    return second;
  }
  if (canonical == "Pa") {
    return pascal;
  }
  if (canonical == "m s-1") {
    return velocity;
  }
  if (canonical == "1") {
    return fraction;
  }
  return none;
}

void validateVariability(const std::string& where, const Variability& v, const Naming& name) {
  if (!v.present) {
    return;
  }
  for (int c = 0; c < kVariabilityClasses; ++c) {
    const auto& fit = v.classes[static_cast<std::size_t>(c)];
    const std::string cls = kVariabilityClassNames[c];
    const std::string code = fmt::format("variability.classes[{}]", cls);
    if (!(std::isfinite(fit.shape) && fit.shape > 0.0)) {
      core::failInput(where, "{} = {}: the Weibull shape k must be positive; refit the {} deviations",
                      name(code + ".shape", fmt::format("weibull_shape[{}]", cls)), fit.shape, cls);
    }
    if (!(std::isfinite(fit.scale) && fit.scale >= 0.0)) {
      core::failInput(where, "{} = {}: the Weibull scale must be >= 0 (0 = no variability in this class)",
                      name(code + ".scale", fmt::format("weibull_scale[{}]", cls)), fit.scale);
    }
    if (!std::isfinite(fit.ksStatistic)) {
      core::failInput(where, "{} = {}: must be finite (a negative value means 'not computed')",
                      name(code + ".ksStatistic", fmt::format("weibull_ks[{}]", cls)), fit.ksStatistic);
    }
    if (fit.samples < 0) {
      core::failInput(where, "{} = {}: the number of fitted deviations must be >= 0 (0 = given, not fitted)",
                      name(code + ".samples", fmt::format("weibull_samples[{}]", cls)), fit.samples);
    }
  }
  for (std::size_t i = 0; i < 2; ++i) {
    const double pa = v.probabilityAbove[i];
    if (!(pa >= 0.0 && pa <= 1.0)) {
      core::failInput(where, "{} = {}: a probability must lie in [0, 1]",
                      name(fmt::format("variability.probabilityAbove[{}]", i),
                           fmt::format("probability_above[{}]", i == 0 ? "crest" : "trough")),
                      pa);
    }
  }
  checkPositive(where, name("variability.normalisationPressure", "normalisation_pressure"), v.normalisationPressure,
                "unit: Pa; rho g a_n, the pressure the deviations were divided by");
  checkPositive(where, name("variability.normalisationElevation", "normalisation_elevation"),
                v.normalisationElevation, "unit: m; the wave amplitude a_n at which P_n was taken");
}

/// The checks shared by the writer (on the header given) and the reader (on the header read).
void validateHeader(const std::string& where, const StormHeader& h, const Naming& name) {
  checkAxis(where, name("header.x", "x"), h.x);
  checkAxis(where, name("header.z", "z"), h.z);
  if (h.samples.size() != h.voxels()) {
    core::failInput(where, "{} has {} values; expected nz * nx = {} * {} = {} ((z, x) order, x fastest)",
                    name("header.samples", "samples"), h.samples.size(), h.nz(), h.nx(), h.voxels());
  }
  for (std::size_t k = 0; k < h.samples.size(); ++k) {
    if (h.samples[k] < 0) {
      core::failInput(where, "{}[{}] = {} at voxel x = {} m, z = {} m: samples per voxel must be >= 0 (0 = no data)",
                      name("header.samples", "samples"), k, h.samples[k], h.x[k % h.nx()], h.z[k / h.nx()]);
    }
  }
  checkPositive(where, name("header.waterDensity", "global attribute water_density"), h.waterDensity,
                "unit: kg/m^3; sea water is about 1025");
  checkPositive(where, name("header.gravity", "global attribute gravity"), h.gravity, "unit: m/s^2; 9.81 on Earth");
  checkPositive(where, name("header.trunkLength", "global attribute trunk_length"), h.trunkLength,
                "unit: m; the length along y of the trunk the fields were averaged over");
  checkFinite(where, name("header.trunkOrigin", "global attribute trunk_origin"), h.trunkOrigin, "m");
  checkFinite(where, name("header.stillWaterLevel", "global attribute still_water_level"), h.stillWaterLevel, "m");
  validateVariability(where, h.variability, name);
}

} // namespace armour::storm::detail
