// SPDX-License-Identifier: GPL-3.0-or-later
#include "storm/StormSynth.hpp"

#include "core/BuildInfo.hpp"
#include "core/Error.hpp"
#include "core/Log.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

namespace armour::storm {
namespace {

constexpr double kPi = std::numbers::pi;

/// Depth-limited breaking on a flat bed: H/h = 0.78 (McCowan 1894).
constexpr double kBreakingDepthRatio = 0.78;
/// Steepness-limited breaking: H/L = tanh(kh) / 7 (Miche 1944; 1/7 in deep water, Michell 1893).
constexpr double kBreakingSteepness = 1.0 / 7.0;
/// A sea state on a flat bed carries Hs up to about 0.6 h before its largest waves (about 1.3 Hs
/// and more) all break at 0.78 h; a linear superposition does not break, so refuse it instead.
constexpr double kSeaStateDepthRatio = 0.6;
/// Stokes 2: above a2/a = 1/4 the second harmonic puts a secondary crest in the trough.
constexpr double kStokesRatioLimit = 0.25;

/// Uniform in [0, 1) from the top 53 bits: the same on every platform, unlike
/// std::uniform_real_distribution whose algorithm is left to the implementation.
double uniform01(std::mt19937_64& generator) { return static_cast<double>(generator() >> 11) * 0x1.0p-53; }

/// Cells of a grid side [lo, hi] of voxel size `voxel`: a partial last cell counts as a whole one.
std::size_t cellCount(double lo, double hi, double voxel) {
  return static_cast<std::size_t>(std::ceil((hi - lo) / voxel - 1e-9));
}

std::string modelSummary(const SynthSettings& s) {
  switch (s.model) {
  case SynthModel::Still:
    return fmt::format("still swl={:g} m h={:g} m", s.stillWaterLevel, s.depth);
  case SynthModel::Current:
    return fmt::format("current u={:g} m/s w={:g} m/s swl={:g} m h={:g} m", s.currentU, s.currentW, s.stillWaterLevel,
                       s.depth);
  case SynthModel::Airy:
  case SynthModel::Stokes2:
    return fmt::format("{} H={:g} m T={:g} s h={:g} m swl={:g} m", synthModelName(s.model), s.height, s.period, s.depth,
                       s.stillWaterLevel);
  case SynthModel::Jonswap:
    return fmt::format("jonswap Hs={:g} m Tp={:g} s gamma={:g} N={} seed={} h={:g} m swl={:g} m", s.hs, s.tp, s.gamma,
                       s.components, s.seed, s.depth, s.stillWaterLevel);
  }
  return "unknown";
}

} // namespace

SynthModel synthModelFromName(const std::string& name) {
  for (SynthModel m :
       {SynthModel::Still, SynthModel::Current, SynthModel::Airy, SynthModel::Stokes2, SynthModel::Jonswap}) {
    if (name == synthModelName(m)) {
      return m;
    }
  }
  core::failInput("storm-file synth", "unknown model '{}': use one of still, current, airy, stokes2, jonswap", name);
}

const char* synthModelName(SynthModel model) {
  switch (model) {
  case SynthModel::Still:
    return "still";
  case SynthModel::Current:
    return "current";
  case SynthModel::Airy:
    return "airy";
  case SynthModel::Stokes2:
    return "stokes2";
  case SynthModel::Jonswap:
    return "jonswap";
  }
  return "unknown";
}

double waveNumber(double omega, double depth, double gravity) {
  if (!(omega > 0.0) || !(depth > 0.0) || !(gravity > 0.0)) {
    throw std::invalid_argument(
        fmt::format("waveNumber: omega = {}, depth = {}, gravity = {} must be positive", omega, depth, gravity));
  }
  // Dimensionless form y tanh y = x0 with y = k h, x0 = omega^2 h / g: well scaled from shallow
  // (y ~ sqrt(x0)) to deep water (y ~ x0).
  const double x0 = omega * omega * depth / gravity;
  double y = x0 * std::pow(1.0 / std::tanh(std::pow(x0, 0.75)), 2.0 / 3.0); // Fenton & McKee (1990), 0.1 %
  for (int iteration = 0; iteration < 50; ++iteration) {
    const double th = std::tanh(y);
    const double f = y * th - x0;
    const double df = th + y * (1.0 - th * th);
    const double step = f / df;
    y -= step;
    if (std::abs(step) <= 1e-12 * y) {
      return y / depth;
    }
  }
  throw std::runtime_error(fmt::format("waveNumber: Newton did not converge for omega = {}, depth = {}", omega, depth));
}

double stokesSecondOrderRatio(double height, double waveNumber, double depth) {
  // (k H / 8) cosh(kh) (2 + cosh 2kh) / sinh^3(kh), written with t = exp(-2kh) so deep water does
  // not overflow: (k H / 4) (1 + t) (1 + 4t + t^2) / (1 - t)^3.
  const double t = std::exp(-2.0 * waveNumber * depth);
  return 0.25 * waveNumber * height * (1.0 + t) * (1.0 + 4.0 * t + t * t) / ((1.0 - t) * (1.0 - t) * (1.0 - t));
}

double jonswapShape(double f, double fp, double gamma, double sigmaBelow, double sigmaAbove) {
  const double sigma = f <= fp ? sigmaBelow : sigmaAbove;
  const double r = std::exp(-(f / fp - 1.0) * (f / fp - 1.0) / (2.0 * sigma * sigma));
  const double ratio = fp / f;
  return std::pow(f, -5.0) * std::exp(-1.25 * ratio * ratio * ratio * ratio) * std::pow(gamma, r);
}

std::vector<WaveComponent> jonswapComponents(const SynthSettings& s) {
  if (!(s.hs > 0.0) || !std::isfinite(s.hs)) {
    core::failInput("--hs", "{} m: the significant wave height must be positive", s.hs);
  }
  if (!(s.tp > 0.0) || !std::isfinite(s.tp)) {
    core::failInput("--tp", "{} s: the peak period must be positive", s.tp);
  }
  if (!(s.gamma >= 1.0 && s.gamma <= 20.0)) {
    core::failInput("--gamma",
                    "{}: the peak enhancement factor must be between 1 (Pierson-Moskowitz) and 20 "
                    "(3.3 is the JONSWAP mean)",
                    s.gamma);
  }
  if (!(s.sigmaBelow > 0.0) || !(s.sigmaAbove > 0.0)) {
    core::failInput("jonswap", "sigma = {}, {}: the spectral width parameters must be positive (0.07, 0.09)",
                    s.sigmaBelow, s.sigmaAbove);
  }
  if (s.components < 1 || s.components > 100000) {
    core::failInput("--components",
                    "{}: give between 1 and 100000 wave components (256 resolves a JONSWAP "
                    "spectrum well)",
                    s.components);
  }
  if (!(s.fMinFactor > 0.0) || !(s.fMaxFactor > s.fMinFactor)) {
    core::failInput("--f-min/--f-max", "{} and {} x fp: the band needs 0 < f-min < f-max (defaults 0.5 and 3)",
                    s.fMinFactor, s.fMaxFactor);
  }
  const double fp = 1.0 / s.tp;
  const double fMin = s.fMinFactor * fp;
  const double df = (s.fMaxFactor - s.fMinFactor) * fp / s.components;
  std::vector<WaveComponent> out(static_cast<std::size_t>(s.components));
  std::vector<double> shape(out.size());
  double m0Shape = 0.0;
  for (std::size_t n = 0; n < out.size(); ++n) {
    const double f = fMin + (static_cast<double>(n) + 0.5) * df;
    shape[n] = jonswapShape(f, fp, s.gamma, s.sigmaBelow, s.sigmaAbove);
    m0Shape += shape[n] * df;
  }
  // Scale the discretised spectrum so that the generated sea has Hm0 = 4 sqrt(m0) = Hs exactly
  // (instead of Goda's approximate alpha, which is within a few per cent).
  const double scale = s.hs * s.hs / 16.0 / m0Shape;
  std::mt19937_64 generator(s.seed);
  for (std::size_t n = 0; n < out.size(); ++n) {
    const double f = fMin + (static_cast<double>(n) + 0.5) * df;
    WaveComponent& c = out[n];
    c.amplitude = std::sqrt(2.0 * scale * shape[n] * df);
    c.omega = 2.0 * kPi * f;
    c.waveNumber = waveNumber(c.omega, s.depth, s.gravity);
    c.phase = 2.0 * kPi * uniform01(generator);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// StormSynth
// ---------------------------------------------------------------------------------------------

StormSynth::StormSynth(const SynthSettings& settings, const std::string& command) : settings_(settings) {
  validate();
  buildHeader(command);
}

namespace {

void requirePositive(double value, const char* option, const char* what, const char* unit) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    core::failInput(option, "{} {}: {} must be positive and finite", value, unit, what);
  }
}

void requireFiniteOption(double value, const char* option, const char* unit) {
  if (!std::isfinite(value)) {
    core::failInput(option, "{} {}: give a finite number", value, unit);
  }
}

} // namespace

void StormSynth::validate() {
  validateGrid();
  const double amplitude = validateWave();
  validateVariability(amplitude);
  const SynthSettings& s = settings_;
  auto log = core::logger("storm");
  if (ramp_ > s.duration) {
    log->warn("the ramp-up ({} s) is longer than the storm ({} s): the waves never reach full height", ramp_,
              s.duration);
  }
  records_ = static_cast<std::size_t>(std::floor(s.duration / s.dt + 1e-9)) + 1;
}

void StormSynth::validateGrid() {
  SynthSettings& s = settings_;
  for (auto [value, option] :
       {std::pair{s.xMin, "--x-min"}, std::pair{s.xMax, "--x-max"}, std::pair{s.zMin, "--z-min"},
        std::pair{s.zMax, "--z-max"}, std::pair{s.stillWaterLevel, "--swl"}, std::pair{s.trunkOrigin, "--trunk-origin"},
        std::pair{s.currentU, "--current-u"}, std::pair{s.currentW, "--current-w"}}) {
    requireFiniteOption(value, option, "m");
  }
  if (!(s.xMin < s.xMax)) {
    core::failInput("--x-min", "{} m is not below --x-max = {} m: give x-min < x-max", s.xMin, s.xMax);
  }
  if (!(s.zMin < s.zMax)) {
    core::failInput("--z-min", "{} m is not below --z-max = {} m: give z-min < z-max", s.zMin, s.zMax);
  }
  requirePositive(s.voxel, "--voxel", "the voxel size", "m");
  if (cellCount(s.xMin, s.xMax, s.voxel) < 2 || cellCount(s.zMin, s.zMax, s.voxel) < 2) {
    core::failInput("--voxel",
                    "{} m leaves fewer than 2 voxels across x {}..{} m or z {}..{} m: use a smaller "
                    "voxel or a larger grid",
                    s.voxel, s.xMin, s.xMax, s.zMin, s.zMax);
  }
  const double voxels =
      static_cast<double>(cellCount(s.xMin, s.xMax, s.voxel)) * static_cast<double>(cellCount(s.zMin, s.zMax, s.voxel));
  if (voxels > 1e8) {
    core::failInput("--voxel", "{} m gives {:.3g} voxels: more than 1e8; use a larger voxel or a smaller grid", s.voxel,
                    voxels);
  }
  requirePositive(s.depth, "--depth", "the still water depth", "m");
  requirePositive(s.density, "--density", "the water density", "kg/m^3");
  requirePositive(s.gravity, "--gravity", "gravity", "m/s^2");
  requirePositive(s.dt, "--dt", "the record interval", "s");
  requirePositive(s.duration, "--duration", "the storm duration", "s");
  requirePositive(s.trunkLength, "--trunk-length", "the trunk length", "m");
  if (s.duration < s.dt * (1.0 - 1e-9)) {
    core::failInput("--duration", "{} s is shorter than --dt = {} s: a storm needs at least two records", s.duration,
                    s.dt);
  }
  seabed_ = s.stillWaterLevel - s.depth;
  if (!(seabed_ < s.zMax)) {
    core::failInput("--depth",
                    "{} m puts the seabed at z = {} m, above the grid top --z-max = {} m: no voxel "
                    "holds water",
                    s.depth, seabed_, s.zMax);
  }
  if (s.model != SynthModel::Current && (s.currentU != 0.0 || s.currentW != 0.0)) {
    core::failInput("--current-u",
                    "a current ({}, {} m/s) applies to the current model only: waves on a current "
                    "would need the Doppler-shifted dispersion relation, which synth does not model; "
                    "drop --current-u and --current-w for a wave, or use the current model alone",
                    s.currentU, s.currentW);
  }
  if (!std::isfinite(s.rampTime)) {
    core::failInput("--ramp", "{} s: give a finite ramp time (negative = two wave periods)", s.rampTime);
  }
}

double StormSynth::validateWave() {
  SynthSettings& s = settings_;
  auto log = core::logger("storm");
  double amplitude = 0.0; // wave amplitude a_n for the variability normalisation (unit: m)
  switch (s.model) {
  case SynthModel::Still:
  case SynthModel::Current:
    ramp_ = 0.0;
    break;
  case SynthModel::Airy:
  case SynthModel::Stokes2: {
    requirePositive(s.height, "--height", "the wave height", "m");
    requirePositive(s.period, "--period", "the wave period", "s");
    omega_ = 2.0 * kPi / s.period;
    k_ = waveNumber(omega_, s.depth, s.gravity);
    a_ = 0.5 * s.height;
    const double length = 2.0 * kPi / k_;
    if (s.height > kBreakingDepthRatio * s.depth) {
      core::failInput("--height",
                      "{} m on --depth {} m: H/h = {:.3f} exceeds {}, the depth-limited breaking "
                      "height (McCowan): the wave would break; use --height <= {:.4g} m or a larger "
                      "depth",
                      s.height, s.depth, s.height / s.depth, kBreakingDepthRatio, kBreakingDepthRatio * s.depth);
    }
    const double steepnessLimit = kBreakingSteepness * std::tanh(k_ * s.depth);
    if (s.height / length > steepnessLimit) {
      core::failInput("--height",
                      "{} m with --period {} s (L = {:.4g} m): H/L = {:.4f} exceeds the breaking "
                      "steepness tanh(kh)/7 = {:.4f} (Miche): use --height <= {:.4g} m or a longer "
                      "period",
                      s.height, s.period, length, s.height / length, steepnessLimit, steepnessLimit * length);
    }
    if (s.model == SynthModel::Stokes2) {
      const double ratio = stokesSecondOrderRatio(s.height, k_, s.depth);
      const double ursell = s.height * length * length / (s.depth * s.depth * s.depth);
      if (ratio > kStokesRatioLimit) {
        core::failInput("--height",
                        "{} m with --period {} s on --depth {} m: the second harmonic of Stokes "
                        "second-order theory is {:.3f} of the first (limit {}: above it the trough "
                        "gets a secondary crest; Ursell number H L^2/h^3 = {:.3g}); use a smaller "
                        "--height, a shorter --period or a larger --depth, or the airy model",
                        s.height, s.period, s.depth, ratio, kStokesRatioLimit, ursell);
      }
      a2_ = ratio * a_;
    }
    components_ = {WaveComponent{a_, k_, omega_, 0.0}};
    ramp_ = s.rampTime >= 0.0 ? s.rampTime : 2.0 * s.period;
    amplitude = a_;
    const double crest = s.stillWaterLevel + a_ + a2_;
    if (crest > s.zMax) {
      log->warn("the wave crest reaches z = {:.4g} m, above the grid top --z-max = {} m: the file holds the flow "
                "up to the grid top only",
                crest, s.zMax);
    }
    break;
  }
  case SynthModel::Jonswap: {
    components_ = jonswapComponents(s);
    const double kp = waveNumber(2.0 * kPi / s.tp, s.depth, s.gravity);
    const double lp = 2.0 * kPi / kp;
    if (s.hs > kSeaStateDepthRatio * s.depth) {
      core::failInput("--hs",
                      "{} m on --depth {} m: Hs/h = {:.3f} exceeds {}: the largest waves of the sea "
                      "state would break (H/h = 0.78) and a linear sea cannot break; use --hs <= {:.4g} m",
                      s.hs, s.depth, s.hs / s.depth, kSeaStateDepthRatio, kSeaStateDepthRatio * s.depth);
    }
    const double steepnessLimit = kBreakingSteepness * std::tanh(kp * s.depth);
    if (s.hs / lp > steepnessLimit) {
      core::failInput("--hs",
                      "{} m with --tp {} s (Lp = {:.4g} m): Hs/Lp = {:.4f} exceeds the breaking steepness "
                      "tanh(kh)/7 = {:.4f}; use --hs <= {:.4g} m or a longer --tp",
                      s.hs, s.tp, lp, s.hs / lp, steepnessLimit, steepnessLimit * lp);
    }
    ramp_ = s.rampTime >= 0.0 ? s.rampTime : 2.0 * s.tp;
    amplitude = 0.5 * s.hs;
    break;
  }
  }
  return amplitude;
}

void StormSynth::validateVariability(double amplitude) {
  SynthSettings& s = settings_;
  Variability& v = s.variability;
  if (v.present) {
    for (int c = 0; c < kVariabilityClasses; ++c) {
      const WeibullFit& fit = v.classes[static_cast<std::size_t>(c)];
      if (!(fit.shape > 0.0) || !std::isfinite(fit.shape) || !(fit.scale >= 0.0) || !std::isfinite(fit.scale)) {
        core::failInput("--variability",
                        "class {} ({}): shape {} and scale {}: a Weibull fit needs shape > 0 and "
                        "scale >= 0",
                        c + 1, kVariabilityClassNames[c], fit.shape, fit.scale);
      }
    }
    for (double probability : v.probabilityAbove) {
      if (!(probability >= 0.0 && probability <= 1.0)) {
        core::failInput("--prob-above", "{}: a probability must be within [0, 1]", probability);
      }
    }
    if (v.normalisationElevation == 0.0) {
      if (amplitude <= 0.0) {
        core::failInput("--norm-amplitude",
                        "the {} model has no wave amplitude: give the normalisation amplitude "
                        "a_n (m) of the variability model",
                        synthModelName(s.model));
      }
      v.normalisationElevation = amplitude;
    }
    if (!(v.normalisationElevation > 0.0) || !std::isfinite(v.normalisationElevation)) {
      core::failInput("--norm-amplitude", "{} m: the normalisation amplitude must be positive",
                      v.normalisationElevation);
    }
    if (v.normalisationPressure == 0.0) {
      v.normalisationPressure = s.density * s.gravity * v.normalisationElevation;
    }
    if (v.source.empty()) {
      v.source = "given to armour storm-file synth";
    }
  }
}

void StormSynth::buildHeader(const std::string& command) {
  const SynthSettings& s = settings_;
  StormHeader& h = header_;
  const std::size_t nx = cellCount(s.xMin, s.xMax, s.voxel);
  const std::size_t nz = cellCount(s.zMin, s.zMax, s.voxel);
  if (s.xMin + static_cast<double>(nx) * s.voxel > s.xMax + 1e-9 * s.voxel ||
      s.zMin + static_cast<double>(nz) * s.voxel > s.zMax + 1e-9 * s.voxel) {
    core::logger("storm")->info("the grid is extended to whole voxels: x {}..{} m, z {}..{} m", s.xMin,
                                s.xMin + static_cast<double>(nx) * s.voxel, s.zMin,
                                s.zMin + static_cast<double>(nz) * s.voxel);
  }
  h.x.resize(nx);
  h.z.resize(nz);
  for (std::size_t i = 0; i < nx; ++i) {
    h.x[i] = s.xMin + (static_cast<double>(i) + 0.5) * s.voxel;
  }
  for (std::size_t j = 0; j < nz; ++j) {
    h.z[j] = s.zMin + (static_cast<double>(j) + 0.5) * s.voxel;
  }
  h.trunkOrigin = s.trunkOrigin;
  h.trunkLength = s.trunkLength;
  h.uniformAlongY = s.uniformAlongY;
  h.stillWaterLevel = s.stillWaterLevel;
  h.waterDensity = s.density;
  h.gravity = s.gravity;
  h.hasVelocityY = false;
  h.samples.assign(nx * nz, 1);
  // Voxels whose centre lies in the seabed hold no data (solid).
  for (std::size_t j = 0; j < nz; ++j) {
    if (h.z[j] < seabed_) {
      std::fill_n(h.samples.begin() + static_cast<std::ptrdiff_t>(j * nx), nx, 0);
    }
  }
  h.variability = s.variability;
  Provenance& p = h.provenance;
  p.sourceCase = "synthetic: " + modelSummary(s);
  p.title = s.title.empty() ? "Synthetic storm: " + modelSummary(s) : s.title;
  p.software = core::buildInfo();
  p.command = command;
  if (!s.comment.empty()) {
    p.comment = s.comment;
  } else {
    switch (s.model) {
    case SynthModel::Still:
    case SynthModel::Current:
      p.comment = "hydrostatic pressure rho g (swl - z); uniform velocity";
      break;
    case SynthModel::Airy:
      p.comment = fmt::format("linear wave theory with Wheeler stretching; cosine ramp-up over {:g} s; crest at "
                              "x = 0, t = 0",
                              ramp_);
      break;
    case SynthModel::Jonswap:
      p.comment = fmt::format("linear superposition of {} components with random phases (seed {}), Wheeler "
                              "stretching; cosine ramp-up over {:g} s",
                              components_.size(), s.seed, ramp_);
      break;
    case SynthModel::Stokes2:
      p.comment = fmt::format("Stokes second-order theory evaluated up to the free surface; cosine ramp-up over "
                              "{:g} s; crest at x = 0, t = 0",
                              ramp_);
      break;
    }
  }
}

double StormSynth::ramp(double t) const {
  if (ramp_ <= 0.0 || t >= ramp_) {
    return 1.0;
  }
  if (t <= 0.0) {
    return 0.0;
  }
  return 0.5 * (1.0 - std::cos(kPi * t / ramp_));
}

double StormSynth::elevation(double x, double t) const {
  const double r = ramp(t);
  switch (settings_.model) {
  case SynthModel::Still:
  case SynthModel::Current:
    return 0.0;
  case SynthModel::Stokes2: {
    const double theta = k_ * x - omega_ * t;
    return r * a_ * std::cos(theta) + r * r * a2_ * std::cos(2.0 * theta);
  }
  case SynthModel::Airy:
  case SynthModel::Jonswap:
    break;
  }
  double eta = 0.0;
  for (const WaveComponent& c : components_) {
    eta += c.amplitude * std::cos(c.waveNumber * x - c.omega * t + c.phase);
  }
  return r * eta;
}

void StormSynth::linearColumn(double x, double t, double eta, double z0, double dz, std::size_t count, double* p,
                              double* u, double* w, std::size_t stride) const {
  if (count == 0) {
    return;
  }
  const double h = settings_.depth;
  const double r = ramp(t);
  if (!(h + eta > 0.05 * h)) {
    core::failInput(settings_.model == SynthModel::Jonswap ? "--hs" : "--height",
                    "at x = {} m, t = {} s the trough (eta = {:.4g} m) nearly reaches the seabed on --depth {} m: "
                    "the sea is too high for its depth; lower the wave height or deepen the water",
                    x, t, eta, h);
  }
  // Wheeler stretching: the wet column seabed..swl+eta is mapped onto seabed..swl, where linear
  // theory holds, by s' = (z - zb) h / (h + eta); at the free surface s' = h exactly.
  const double q = h / (h + eta);
  std::vector<double> sumP(count, 0.0), sumU(count, 0.0), sumW(count, 0.0), e(count);
  for (const WaveComponent& c : components_) {
    const double k = c.waveNumber;
    const double theta = k * x - c.omega * t + c.phase;
    const double cosT = std::cos(theta), sinT = std::sin(theta);
    // The hyperbolic profiles as exponentials relative to the surface so deep-water components
    // neither overflow nor lose precision: with E = exp(k (s' - h)), F = exp(-k (s' + h)),
    // t2 = exp(-2 k h): cosh(k s')/sinh(kh) = (E + F)/(1 - t2), sinh(k s')/sinh(kh) = (E - F)/(1 - t2),
    // cosh(k s')/cosh(kh) = (E + F)/(1 + t2).
    const double t2 = std::exp(-2.0 * k * h);
    const double amplitude = r * c.amplitude;
    const double cu = amplitude * c.omega * cosT / (1.0 - t2);
    const double cw = amplitude * c.omega * sinT / (1.0 - t2);
    const double cp = amplitude * cosT / (1.0 + t2);
    // Along the column s' grows by dz q per point: E and F are geometric sequences. Each is run in
    // the direction in which it decreases, so an underflow to 0 is the right answer, not a seed
    // that would stay 0 while the true value grows.
    const double ratio = std::exp(-k * dz * q);
    const double sBottom = (z0 - seabed_) * q;
    const double sTop = (z0 + static_cast<double>(count - 1) * dz - seabed_) * q;
    double value = std::exp(k * (sTop - h));
    for (std::size_t j = count; j-- > 0;) {
      e[j] = value;
      value *= ratio;
    }
    value = std::exp(-k * (sBottom + h));
    for (std::size_t j = 0; j < count; ++j) {
      const double f = value;
      value *= ratio;
      sumU[j] += cu * (e[j] + f);
      sumW[j] += cw * (e[j] - f);
      sumP[j] += cp * (e[j] + f);
    }
  }
  const double rhoG = settings_.density * settings_.gravity;
  for (std::size_t j = 0; j < count; ++j) {
    const double zeta = z0 + static_cast<double>(j) * dz - settings_.stillWaterLevel;
    // p = rho g (sum a Kp(s') cos - zeta): at the surface Kp = 1 and sum a cos = eta, so p = 0.
    p[j * stride] = std::max(0.0, rhoG * (sumP[j] - zeta));
    u[j * stride] = sumU[j];
    w[j * stride] = sumW[j];
  }
}

SynthFlow StormSynth::stokesPoint(double x, double z, double t, double eta) const {
  // Stokes second-order theory as Dean & Dalrymple (1991) write it, with s = z - zb,
  // zeta = z - swl, and the hyperbolic ratios as exponentials (E1 = exp(k zeta),
  // G1 = exp(-k (s + h)), t = exp(-2 k h)) so deep water does not overflow.
  const double h = settings_.depth;
  const double r = ramp(t);
  const double a = r * a_;
  const double k = k_;
  const double omega = omega_;
  const double theta = k * x - omega * t;
  const double zeta = std::min(z, settings_.stillWaterLevel + eta) - settings_.stillWaterLevel;
  const double s = zeta + h;
  const double e1 = std::exp(k * zeta);
  const double g1 = std::exp(-k * (s + h));
  const double tt = std::exp(-2.0 * k * h);
  const double sum2 = e1 * e1 + g1 * g1;
  const double diff2 = e1 * e1 - g1 * g1;
  const double oneMinus = 1.0 - tt;
  const double oneMinus4 = oneMinus * oneMinus * oneMinus * oneMinus;
  const double c1 = std::cos(theta), s1 = std::sin(theta);
  const double c2 = std::cos(2.0 * theta), s2 = std::sin(2.0 * theta);
  SynthFlow flow;
  // First order.
  flow.u = a * omega * (e1 + g1) / oneMinus * c1;
  flow.w = a * omega * (e1 - g1) / oneMinus * s1;
  double dynamic = a * (e1 + g1) / (1.0 + tt) * c1;
  // Second order: (3/4) omega k a^2 cosh(2ks)/sinh^4(kh) = 6 omega k a^2 t (E1^2 + G1^2) / (1 - t)^4.
  const double second = 6.0 * omega * k * a * a * tt / oneMinus4;
  flow.u += second * sum2 * c2;
  flow.w += second * diff2 * s2;
  // (3/2) k a^2 / sinh(2kh) [cosh(2ks)/sinh^2(kh) - 1/3] cos 2 theta
  //   - (1/2) k a^2 / sinh(2kh) [cosh(2ks) - 1]
  const double oneMinusSq = 1.0 - tt * tt;
  dynamic +=
      1.5 * k * a * a * (4.0 * tt * sum2 / (oneMinusSq * oneMinus * oneMinus) - 2.0 * tt / (3.0 * oneMinusSq)) * c2;
  dynamic -= 0.5 * k * a * a * (sum2 - 2.0 * tt) / oneMinusSq;
  const double rhoG = settings_.density * settings_.gravity;
  if (z < settings_.stillWaterLevel + eta) {
    flow.p = std::max(0.0, rhoG * (dynamic - zeta));
    flow.alpha = 1.0;
  }
  return flow;
}

SynthFlow StormSynth::flowAt(double x, double z, double t) const {
  SynthFlow flow;
  if (z < seabed_) {
    return flow;
  }
  const double eta = elevation(x, t);
  const double surface = settings_.stillWaterLevel + eta;
  const double rhoG = settings_.density * settings_.gravity;
  switch (settings_.model) {
  case SynthModel::Still:
  case SynthModel::Current:
    flow.u = settings_.model == SynthModel::Current ? settings_.currentU : 0.0;
    flow.w = settings_.model == SynthModel::Current ? settings_.currentW : 0.0;
    if (z < surface) {
      flow.p = rhoG * (surface - z);
      flow.alpha = 1.0;
    }
    return flow;
  case SynthModel::Stokes2:
    return stokesPoint(x, z, t, eta);
  case SynthModel::Airy:
  case SynthModel::Jonswap:
    break;
  }
  // Above the surface the velocity is held at its free-surface value (s' = h) and p = 0.
  linearColumn(x, t, eta, std::min(z, surface), 1.0, 1, &flow.p, &flow.u, &flow.w, 1);
  if (z < surface) {
    flow.alpha = 1.0;
  } else {
    flow.p = 0.0;
  }
  return flow;
}

StormRecord StormSynth::record(double t) const {
  StormRecord out;
  record(t, out);
  return out;
}

void StormSynth::record(double t, StormRecord& out) const {
  const StormHeader& h = header_;
  const std::size_t nx = h.nx(), nz = h.nz();
  const double dz = settings_.voxel;
  out.time = t;
  out.p.assign(nx * nz, 0.0);
  out.u.assign(nx * nz, 0.0);
  out.w.assign(nx * nz, 0.0);
  out.alpha.assign(nx * nz, 0.0);
  out.v.clear();
  out.eta.resize(nx);
  // First voxel with data (centre at or above the seabed).
  const std::size_t jBed = static_cast<std::size_t>(std::lower_bound(h.z.begin(), h.z.end(), seabed_) - h.z.begin());
  for (std::size_t i = 0; i < nx; ++i) {
    const double eta = elevation(h.x[i], t);
    out.eta[i] = eta;
    const double surface = settings_.stillWaterLevel + eta;
    // Wet voxel centres: jBed <= j < jTop (centre below the free surface).
    const std::size_t jTop =
        std::max(jBed, static_cast<std::size_t>(std::lower_bound(h.z.begin(), h.z.end(), surface) - h.z.begin()));
    for (std::size_t j = jBed; j < nz; ++j) {
      // The part of the voxel's height below the free surface.
      out.alpha[j * nx + i] = std::clamp((surface - (h.z[j] - 0.5 * dz)) / dz, 0.0, 1.0);
    }
    switch (settings_.model) {
    case SynthModel::Still:
    case SynthModel::Current: {
      const double rhoG = settings_.density * settings_.gravity;
      const bool current = settings_.model == SynthModel::Current;
      for (std::size_t j = jBed; j < nz; ++j) {
        const std::size_t v = j * nx + i;
        out.p[v] = j < jTop ? rhoG * (surface - h.z[j]) : 0.0;
        out.u[v] = current ? settings_.currentU : 0.0;
        out.w[v] = current ? settings_.currentW : 0.0;
      }
      break;
    }
    case SynthModel::Stokes2:
      for (std::size_t j = jBed; j < nz; ++j) {
        const std::size_t v = j * nx + i;
        const SynthFlow flow = stokesPoint(h.x[i], h.z[j], t, eta);
        out.p[v] = j < jTop ? flow.p : 0.0;
        out.u[v] = flow.u;
        out.w[v] = flow.w;
      }
      break;
    case SynthModel::Airy:
    case SynthModel::Jonswap: {
      if (jTop > jBed) {
        linearColumn(h.x[i], t, eta, h.z[jBed], dz, jTop - jBed, &out.p[jBed * nx + i], &out.u[jBed * nx + i],
                     &out.w[jBed * nx + i], nx);
      }
      if (jTop < nz) {
        // Air: p = 0, velocity held at its free-surface value so interpolation between a wet and a
        // dry voxel centre does not drag the surface velocity towards zero (alpha marks the air).
        double pSurface = 0.0, uSurface = 0.0, wSurface = 0.0;
        linearColumn(h.x[i], t, eta, surface, dz, 1, &pSurface, &uSurface, &wSurface, 1);
        for (std::size_t j = jTop; j < nz; ++j) {
          out.u[j * nx + i] = uSurface;
          out.w[j * nx + i] = wSurface;
        }
      }
      break;
    }
    }
  }
}

std::size_t writeSynthStorm(const std::string& path, const SynthSettings& settings, const StormWriteOptions& options,
                            const std::string& command) {
  const StormSynth synth(settings, command);
  auto log = core::logger("storm");
  const StormHeader& header = synth.header();
  log->info("synthesising {}: {} x {} voxels, {} records at {} s ({})", path, header.nx(), header.nz(),
            synth.recordCount(), settings.dt, header.provenance.sourceCase);
  StormWriter writer(path, header, options);
  StormRecord record;
  for (std::size_t k = 0; k < synth.recordCount(); ++k) {
    synth.record(synth.recordTime(k), record);
    writer.append(record);
  }
  writer.finish();
  log->info("wrote {} ({} records, t = 0..{} s)", path, synth.recordCount(), synth.recordTime(synth.recordCount() - 1));
  return synth.recordCount();
}

} // namespace armour::storm
