// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StormSynth.hpp
/// Analytic storm files (`armour storm-file synth`): still water, a uniform current, a linear
/// (Airy) or Stokes second-order regular wave, or a linear JONSWAP irregular sea, sampled at the
/// voxel centres of a storm-file grid (docs/theory.md, "Analytic storms").
///
/// The generator makes records one at a time, so a long storm never needs more than one record in
/// memory. Kinematics above the still water level in a crest use Wheeler stretching for the linear
/// models (Airy, JONSWAP) and direct evaluation of the second-order expansion for Stokes 2.
/// Pressure is gauge (0 at and above the free surface) and total: hydrostatic + dynamic.
///
/// Conventions: x onshore (the waves travel towards +x), z up; the seabed is flat at
/// z = stillWaterLevel - depth; a regular wave has its crest at x = 0 at t = 0.

#include "storm/StormFile.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace armour::storm {

enum class SynthModel { Still, Current, Airy, Stokes2, Jonswap };

/// "still", "current", "airy", "stokes2", "jonswap". Throws core::InputError listing the valid names.
SynthModel synthModelFromName(const std::string& name);
const char* synthModelName(SynthModel model);

/// What to synthesise. Option names in the comments are those of `armour storm-file synth`, used in
/// error messages so the user can find the value to change.
struct SynthSettings {
  SynthModel model = SynthModel::Still;

  // Grid (the voxel centres are half a voxel inside the box; a side that is not a whole number of
  // voxels is extended to the next whole voxel).
  double xMin = 0.0;   ///< --x-min: left edge of the grid (unit: m)
  double xMax = 20.0;  ///< --x-max: right edge of the grid (unit: m)
  double zMin = 0.0;   ///< --z-min: bottom edge of the grid (unit: m)
  double zMax = 15.0;  ///< --z-max: top edge of the grid (unit: m)
  double voxel = 0.25; ///< --voxel: square voxel side (unit: m)

  // Water.
  double stillWaterLevel = 10.0; ///< --swl: z of the still water surface (unit: m)
  double depth = 10.0;           ///< --depth: still water depth; the seabed is at swl - depth (unit: m)
  double density = 1025.0;       ///< --density: rho (unit: kg/m^3)
  double gravity = 9.81;         ///< --gravity: |g| (unit: m/s^2)

  // Time axis: records at t = 0, dt, 2 dt, ... up to duration.
  double duration = 20.0; ///< --duration (unit: s)
  double dt = 0.05;       ///< --dt: record interval (unit: s)

  // Current model.
  double currentU = 0.0; ///< --current-u: uniform x velocity (unit: m/s)
  double currentW = 0.0; ///< --current-w: uniform z velocity (unit: m/s)

  // Regular waves (airy, stokes2).
  double height = 1.0; ///< --height: wave height H, crest to trough (unit: m)
  double period = 8.0; ///< --period: wave period T (unit: s)

  // JONSWAP sea.
  double hs = 1.0;          ///< --hs: significant wave height Hm0 = 4 sqrt(m0) (unit: m)
  double tp = 8.0;          ///< --tp: spectral peak period (unit: s)
  double gamma = 3.3;       ///< --gamma: peak enhancement factor (unit: -)
  double sigmaBelow = 0.07; ///< spectral width parameter for f <= fp (unit: -)
  double sigmaAbove = 0.09; ///< spectral width parameter for f > fp (unit: -)
  int components = 256;     ///< --components: number of wave components (unit: -)
  double fMinFactor = 0.5;  ///< --f-min: lowest component band edge / fp (unit: -)
  double fMaxFactor = 3.0;  ///< --f-max: highest component band edge / fp (unit: -)
  std::uint64_t seed = 1;   ///< --seed: random phases (std::mt19937_64) (unit: -)

  /// --ramp: cosine ramp-up of the wave amplitude from 0 at t = 0 (unit: s); < 0 = two wave
  /// periods (T or Tp) so the storm starts from rest.
  double rampTime = -1.0;

  // Trunk (the extrusion of the 2D slice along y).
  double trunkOrigin = 0.0;  ///< --trunk-origin: y of the start of the trunk (unit: m)
  double trunkLength = 20.0; ///< --trunk-length: trunk length along y (unit: m)
  /// --uniform-along-y: the analytic fields hold at every y, so the solver loads units anywhere
  /// along the trunk; off, only units within [trunkOrigin, trunkOrigin + trunkLength] (unit: -).
  bool uniformAlongY = false;

  /// --variability etc.: written to the header as given (present = false: none). A zero
  /// normalisationElevation is replaced by the wave amplitude a_n = H/2 (Hs/2) and the pressure by
  /// rho g a_n.
  Variability variability;

  std::string title;   ///< provenance title ("" = made from the model and its parameters)
  std::string comment; ///< provenance comment ("" = how the kinematics were computed)
};

/// Solve the linear dispersion relation omega^2 = g k tanh(k h) for the wave number k (unit: 1/m)
/// by Newton's method from the Fenton & McKee (1990) explicit approximation, to a relative
/// change below 1e-12. @pre omega > 0, depth > 0, gravity > 0.
double waveNumber(double omega, double depth, double gravity);

/// One linear wave component: eta = amplitude cos(k x - omega t + phase).
struct WaveComponent {
  double amplitude = 0.0;  ///< unit: m
  double waveNumber = 0.0; ///< k (unit: 1/m)
  double omega = 0.0;      ///< angular frequency (unit: rad/s)
  double phase = 0.0;      ///< unit: rad
};

/// The components of a JONSWAP sea (Hasselmann et al. 1973), equal frequency bins between
/// fMinFactor fp and fMaxFactor fp, amplitudes sqrt(2 S(f) df) scaled so that 4 sqrt(sum a^2/2) = Hs
/// exactly, phases uniform in [0, 2 pi) from std::mt19937_64(seed). Validates the JONSWAP settings.
std::vector<WaveComponent> jonswapComponents(const SynthSettings& settings);

/// The JONSWAP spectral shape without its scale: f^-5 exp(-1.25 (fp/f)^4) gamma^r (unit: s^5).
double jonswapShape(double f, double fp, double gamma, double sigmaBelow, double sigmaAbove);

/// Flow at one point (values as stored in a storm record).
struct SynthFlow {
  double p = 0.0;     ///< total gauge pressure (unit: Pa)
  double u = 0.0;     ///< unit: m/s
  double w = 0.0;     ///< unit: m/s
  double alpha = 0.0; ///< 1 below the free surface, 0 above (a point, not a voxel) (unit: -)
};

/// A synthetic storm: validated settings, the header, and the records on demand.
class StormSynth {
public:
  /// Validate the settings (throws core::InputError naming the option, the value and the limit)
  /// and build the header. `command` is recorded as the provenance command line.
  explicit StormSynth(const SynthSettings& settings, const std::string& command = "");

  const SynthSettings& settings() const { return settings_; }
  const StormHeader& header() const { return header_; }

  std::size_t recordCount() const { return records_; }
  double recordTime(std::size_t k) const { return static_cast<double>(k) * settings_.dt; }

  /// The record at time t (unit: s): every voxel of the header's grid.
  StormRecord record(double t) const;
  /// Same, reusing `out`'s storage.
  void record(double t, StormRecord& out) const;

  /// Free-surface elevation above the still water level at (x, t) (unit: m).
  double elevation(double x, double t) const;
  /// The flow at a point (x, z) at time t, with the same formulas as the records.
  SynthFlow flowAt(double x, double z, double t) const;

  /// Linear components (Airy: one, JONSWAP: settings.components; none otherwise).
  const std::vector<WaveComponent>& components() const { return components_; }
  /// Ramp-up time in use (unit: s).
  double rampTime() const { return ramp_; }
  /// Amplitude factor of the ramp at time t, 0..1 (unit: -).
  double ramp(double t) const;
  /// Stokes 2: amplitude of the second harmonic of eta at full amplitude (unit: m); 0 otherwise.
  double secondHarmonicAmplitude() const { return a2_; }

private:
  /// Flow in one column of `count` points z0, z0 + dz, ... at x (the linear models); the
  /// elevation of the column is `eta`. Writes p, u, w at stride `stride` from the pointers.
  void linearColumn(double x, double t, double eta, double z0, double dz, std::size_t count, double* p, double* u,
                    double* w, std::size_t stride) const;
  SynthFlow stokesPoint(double x, double z, double t, double eta) const;
  void validate();
  /// The grid, water and record settings (part of validate()).
  void validateGrid();
  /// The wave model's settings; sets the wave members and the ramp. Returns the wave amplitude
  /// a_n for the variability's normalisation (unit: m; 0 without waves).
  double validateWave();
  /// The variability model, normalised by `amplitude` when it gives none (unit: m).
  void validateVariability(double amplitude);
  void buildHeader(const std::string& command);

  SynthSettings settings_;
  StormHeader header_;
  std::size_t records_ = 0;
  std::vector<WaveComponent> components_;
  double ramp_ = 0.0;
  double seabed_ = 0.0; ///< z of the seabed (unit: m)
  // Stokes 2 coefficients (full amplitude).
  double k_ = 0.0, omega_ = 0.0, a_ = 0.0, a2_ = 0.0;
};

/// Generate the storm record by record and write it with StormWriter (atomically: "<path>.partial"
/// renamed when complete). Returns the number of records written.
std::size_t writeSynthStorm(const std::string& path, const SynthSettings& settings, const StormWriteOptions& options,
                            const std::string& command);

/// The Stokes second-order validity ratio: amplitude of the second harmonic of eta over the first
/// (a2 / a) for a wave of height H, wave number k on depth h (unit: -). Above 1/4 the second
/// harmonic makes a secondary crest in the trough: the expansion no longer describes the wave.
double stokesSecondOrderRatio(double height, double waveNumber, double depth);

} // namespace armour::storm
