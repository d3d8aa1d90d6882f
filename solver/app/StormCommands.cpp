// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/StormCommands.hpp"

#include "core/Error.hpp"
#include "core/JsonWriter.hpp"
#include "core/Log.hpp"
#include "storm/StormFile.hpp"
#include "storm/StormSynth.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace armour::app {
namespace {

using namespace armour::storm;
using core::jsonNumber;
using core::jsonString;

struct SynthOptions {
  std::string model;
  std::string output;
  SynthSettings settings;
  std::string variability;    ///< "k1,l1,k2,l2,k3,l3,k4,l4"
  std::string probAbove;      ///< "pc,pt"
  double normAmplitude = 0.0; ///< a_n (unit: m); 0 = the wave amplitude
  bool doublePrecision = false;
  int deflate = 1;
};

/// Comma-separated numbers of an option value; exactly `count` of them.
std::vector<double> parseNumbers(const std::string& text, std::size_t count, const char* option, const char* form) {
  std::vector<double> out;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    std::size_t used = 0;
    double value = 0.0;
    bool ok = true;
    try {
      value = std::stod(item, &used);
      ok = item.find_first_not_of(" \t", used) == std::string::npos;
    } catch (const std::exception&) {
      ok = false;
    }
    if (!ok) {
      core::failInput(option, "'{}': '{}' is not a number; give {}", text, item, form);
    }
    out.push_back(value);
  }
  if (out.size() != count || (!text.empty() && text.back() == ',')) {
    core::failInput(option, "'{}' has {} numbers: give {} ({} comma-separated numbers)", text, out.size(), form, count);
  }
  return out;
}

/// Options that only some models use: given to another model they are a mistake, not a no-op.
struct ModelOption {
  const char* option;
  std::vector<SynthModel> models;
  const char* hint;
};

void refuseForeignOptions(const CLI::App& command, SynthModel model) {
  const std::vector<ModelOption> table = {
      {"--height", {SynthModel::Airy, SynthModel::Stokes2}, "the jonswap model takes --hs and --tp"},
      {"--period", {SynthModel::Airy, SynthModel::Stokes2}, "the jonswap model takes --hs and --tp"},
      {"--hs", {SynthModel::Jonswap}, "regular waves (airy, stokes2) take --height and --period"},
      {"--tp", {SynthModel::Jonswap}, "regular waves (airy, stokes2) take --height and --period"},
      {"--gamma", {SynthModel::Jonswap}, ""},
      {"--components", {SynthModel::Jonswap}, ""},
      {"--seed", {SynthModel::Jonswap}, ""},
      {"--f-min", {SynthModel::Jonswap}, ""},
      {"--f-max", {SynthModel::Jonswap}, ""},
      {"--ramp", {SynthModel::Airy, SynthModel::Stokes2, SynthModel::Jonswap}, "still water and a current do not ramp"},
      {"--current-u", {SynthModel::Current}, ""},
      {"--current-w", {SynthModel::Current}, ""},
  };
  for (const ModelOption& entry : table) {
    if (command.count(entry.option) > 0 &&
        std::find(entry.models.begin(), entry.models.end(), model) == entry.models.end()) {
      std::string models;
      for (SynthModel m : entry.models) {
        models += (models.empty() ? "" : ", ") + std::string(synthModelName(m));
      }
      core::failInput(entry.option, "does not apply to the {} model (it is used by: {}){}{}", synthModelName(model),
                      models, *entry.hint ? "; " : "", entry.hint);
    }
  }
}

/// The command line as given, rebuilt from what CLI11 parsed (main() keeps argv to itself): written
/// to the file's provenance so the file can be made again.
std::string commandLine(const CLI::App& command, const std::string& model) {
  auto quote = [](const std::string& s) {
    return s.find_first_of(" \t\"'") == std::string::npos && !s.empty() ? s : fmt::format("'{}'", s);
  };
  std::string line = "armour storm-file synth " + model;
  for (const CLI::Option* option : command.get_options()) {
    if (option->get_positional() || option->count() == 0 || option->get_name() == "--help") {
      continue;
    }
    line += " " + option->get_name();
    if (option->get_type_size() != 0) {
      for (const std::string& value : option->results()) {
        line += " " + quote(value);
      }
    }
  }
  return line;
}

void synthesise(SynthOptions& o, const CLI::App& command) {
  SynthSettings& s = o.settings;
  s.model = synthModelFromName(o.model);
  refuseForeignOptions(command, s.model);
  if (!o.variability.empty()) {
    const std::vector<double> v = parseNumbers(o.variability, 8, "--variability",
                                               "k1,l1,k2,l2,k3,l3,k4,l4: Weibull shape and scale of the classes "
                                               "crest_above, crest_below, trough_above, trough_below");
    s.variability.present = true;
    for (std::size_t c = 0; c < kVariabilityClasses; ++c) {
      s.variability.classes[c].shape = v[2 * c];
      s.variability.classes[c].scale = v[2 * c + 1];
    }
    if (!o.probAbove.empty()) {
      const std::vector<double> p = parseNumbers(o.probAbove, 2, "--prob-above",
                                                 "pc,pt: the probability that a sample lies above the mean in "
                                                 "crests and in troughs");
      s.variability.probabilityAbove = {p[0], p[1]};
    }
    s.variability.normalisationElevation = o.normAmplitude;
    if (command.count("--norm-amplitude") > 0 && !(o.normAmplitude > 0.0)) {
      core::failInput("--norm-amplitude", "{} m: the normalisation amplitude a_n must be positive", o.normAmplitude);
    }
  } else if (!o.probAbove.empty() || command.count("--norm-amplitude") > 0) {
    core::failInput(o.probAbove.empty() ? "--norm-amplitude" : "--prob-above",
                    "belongs to a variability model: give --variability k1,l1,k2,l2,k3,l3,k4,l4 too");
  }
  if (o.deflate < 0 || o.deflate > 9) {
    core::failInput("--deflate", "{}: the deflate level is 0 (none) to 9", o.deflate);
  }
  StormWriteOptions write;
  write.doublePrecision = o.doublePrecision;
  write.deflateLevel = o.deflate;
  const std::size_t records = writeSynthStorm(o.output, s, write, commandLine(command, o.model));
  std::cout << fmt::format("{}: {} records\n", o.output, records);
}

std::string describeVariability(const Variability& v) {
  if (!v.present) {
    return "none";
  }
  std::string out = "Weibull";
  for (int c = 0; c < kVariabilityClasses; ++c) {
    const WeibullFit& f = v.classes[static_cast<std::size_t>(c)];
    out += fmt::format("\n  {:<13} shape {:.6g}, scale {:.6g}", kVariabilityClassNames[c], f.shape, f.scale);
    if (f.samples > 0) {
      out += fmt::format(" ({} samples", f.samples);
      out += f.ksStatistic >= 0.0 ? fmt::format(", KS D = {:.4g})", f.ksStatistic) : std::string(")");
    }
  }
  out +=
      fmt::format("\n  P(above the mean): crests {:.6g}, troughs {:.6g}", v.probabilityAbove[0], v.probabilityAbove[1]);
  out += fmt::format("\n  normalisation: P_n = {:.6g} Pa at a_n = {:.6g} m", v.normalisationPressure,
                     v.normalisationElevation);
  if (!v.source.empty()) {
    out += "\n  source: " + v.source;
  }
  return out;
}

struct StormSummary {
  std::size_t dataVoxels = 0;
  double dtMin = 0.0, dtMax = 0.0;   ///< unit: s
  double etaMin = 0.0, etaMax = 0.0; ///< unit: m
};

StormSummary summarise(const StormReader& reader) {
  StormSummary s;
  const StormHeader& h = reader.header();
  s.dataVoxels =
      static_cast<std::size_t>(std::count_if(h.samples.begin(), h.samples.end(), [](auto m) { return m > 0; }));
  const std::vector<double>& t = reader.times();
  s.dtMin = std::numeric_limits<double>::infinity();
  s.dtMax = 0.0;
  for (std::size_t k = 1; k < t.size(); ++k) {
    s.dtMin = std::min(s.dtMin, t[k] - t[k - 1]);
    s.dtMax = std::max(s.dtMax, t[k] - t[k - 1]);
  }
  s.etaMin = std::numeric_limits<double>::infinity();
  s.etaMax = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double* eta = reader.eta(k);
    for (std::size_t i = 0; i < h.nx(); ++i) {
      s.etaMin = std::min(s.etaMin, eta[i]);
      s.etaMax = std::max(s.etaMax, eta[i]);
    }
  }
  return s;
}

/// The interval as "0.05 s", or "0.049..0.051 s" when the records are not evenly spaced (to 1e-9).
std::string describeStep(const StormSummary& s) {
  if (s.dtMax - s.dtMin <= 1e-9 * s.dtMax) {
    return fmt::format("{:.6g} s", s.dtMax);
  }
  return fmt::format("{:.6g}..{:.6g} s (uneven)", s.dtMin, s.dtMax);
}

void checkStorm(const std::string& path) {
  const StormReader reader(path);
  reader.validateAllRecords();
  const StormHeader& h = reader.header();
  const std::vector<double>& t = reader.times();
  const StormSummary s = summarise(reader);
  std::cout << fmt::format("{}: valid storm file ({} records, t = {:.6g}..{:.6g} s, dt = {}, {} x {} voxels of "
                           "{:.6g} x {:.6g} m, {} with data, variability: {})\n",
                           path, t.size(), t.front(), t.back(), describeStep(s), h.nx(), h.nz(), h.dx(), h.dz(),
                           s.dataVoxels, h.variability.present ? "Weibull" : "none");
}

void printInfoJson(const StormReader& reader, const StormSummary& s) {
  const StormHeader& h = reader.header();
  const std::vector<double>& t = reader.times();
  const Variability& v = h.variability;
  const Provenance& p = h.provenance;
  std::string out = "{\n";
  out += fmt::format("  \"file\": {},\n", jsonString(reader.path()));
  out += fmt::format("  \"nx\": {}, \"nz\": {}, \"data_voxels\": {},\n", h.nx(), h.nz(), s.dataVoxels);
  out += fmt::format("  \"x\": [{}, {}], \"z\": [{}, {}], \"dx\": {}, \"dz\": {},\n", jsonNumber(h.x.front()),
                     jsonNumber(h.x.back()), jsonNumber(h.z.front()), jsonNumber(h.z.back()), jsonNumber(h.dx()),
                     jsonNumber(h.dz()));
  out += fmt::format("  \"records\": {}, \"time\": [{}, {}], \"dt\": [{}, {}],\n", t.size(), jsonNumber(t.front()),
                     jsonNumber(t.back()), jsonNumber(s.dtMin), jsonNumber(s.dtMax));
  out += fmt::format("  \"still_water_level\": {}, \"water_density\": {}, \"gravity\": {},\n",
                     jsonNumber(h.stillWaterLevel), jsonNumber(h.waterDensity), jsonNumber(h.gravity));
  out += fmt::format("  \"trunk_origin\": {}, \"trunk_length\": {}, \"uniform_along_y\": {}, \"velocity_y\": {},\n",
                     jsonNumber(h.trunkOrigin), jsonNumber(h.trunkLength), h.uniformAlongY ? "true" : "false",
                     h.hasVelocityY ? "true" : "false");
  out += fmt::format("  \"eta\": [{}, {}],\n", jsonNumber(s.etaMin), jsonNumber(s.etaMax));
  if (!v.present) {
    out += "  \"variability\": null,\n";
  } else {
    out += "  \"variability\": {\n    \"classes\": {";
    for (int c = 0; c < kVariabilityClasses; ++c) {
      const WeibullFit& f = v.classes[static_cast<std::size_t>(c)];
      out += fmt::format("{}\n      \"{}\": {{\"shape\": {}, \"scale\": {}, \"ks\": {}, \"samples\": {}}}",
                         c ? "," : "", kVariabilityClassNames[c], jsonNumber(f.shape), jsonNumber(f.scale),
                         f.ksStatistic >= 0.0 ? jsonNumber(f.ksStatistic) : "null", f.samples);
    }
    out += fmt::format("\n    }},\n    \"probability_above\": [{}, {}],\n", jsonNumber(v.probabilityAbove[0]),
                       jsonNumber(v.probabilityAbove[1]));
    out += fmt::format("    \"normalisation_pressure\": {}, \"normalisation_elevation\": {},\n",
                       jsonNumber(v.normalisationPressure), jsonNumber(v.normalisationElevation));
    out += fmt::format("    \"source\": {}\n  }},\n", jsonString(v.source));
  }
  out += fmt::format("  \"provenance\": {{\"title\": {}, \"source_case\": {}, \"openfoam_version\": {}, \"software\": "
                     "{}, \"command\": {}, \"comment\": {}}}\n",
                     jsonString(p.title), jsonString(p.sourceCase), jsonString(p.openfoamVersion),
                     jsonString(p.software), jsonString(p.command), jsonString(p.comment));
  out += "}\n";
  std::cout << out;
}

void printInfo(const std::string& path, bool json) {
  const StormReader reader(path);
  const StormSummary s = summarise(reader);
  if (json) {
    printInfoJson(reader, s);
    return;
  }
  const StormHeader& h = reader.header();
  const std::vector<double>& t = reader.times();
  const Provenance& p = h.provenance;
  auto line = [](const char* key, const std::string& value) {
    std::cout << fmt::format("{:<16} {}\n", std::string(key) + ":", value);
  };
  line("file", path);
  line("grid", fmt::format("{} x {} voxels (nx x nz) of {:.6g} x {:.6g} m, {} with data", h.nx(), h.nz(), h.dx(),
                           h.dz(), s.dataVoxels));
  line("x centres", fmt::format("{:.6g} .. {:.6g} m", h.x.front(), h.x.back()));
  line("z centres", fmt::format("{:.6g} .. {:.6g} m", h.z.front(), h.z.back()));
  line("records", fmt::format("{}, t = {:.6g} .. {:.6g} s, dt = {}", t.size(), t.front(), t.back(), describeStep(s)));
  line("still water", fmt::format("z = {:.6g} m", h.stillWaterLevel));
  line("eta", fmt::format("{:.6g} .. {:.6g} m above the still water level", s.etaMin, s.etaMax));
  line("water", fmt::format("density {:.6g} kg/m^3, gravity {:.6g} m/s^2", h.waterDensity, h.gravity));
  line("trunk", fmt::format("y = {:.6g} .. {:.6g} m (length {:.6g} m){}", h.trunkOrigin, h.trunkOrigin + h.trunkLength,
                            h.trunkLength,
                            h.uniformAlongY ? "; uniform along y: the fields hold at every y (a 2D tank), loads apply "
                                              "to units at any y"
                                            : "; loads apply only to units on it"));
  line("velocity y", h.hasVelocityY ? "yes" : "no (v = 0)");
  line("variability", describeVariability(h.variability));
  line("title", p.title);
  line("source", p.sourceCase);
  if (!p.openfoamVersion.empty()) {
    line("OpenFOAM", p.openfoamVersion);
  }
  line("software", p.software);
  line("command", p.command);
  if (!p.comment.empty()) {
    line("comment", p.comment);
  }
}

} // namespace

void addStormCommands(CLI::App& app, const GlobalOptions& /*global*/) {
  CLI::App* storm = app.add_subcommand("storm-file", "storm files (docs/storm-file.md): analytic storms, validation, "
                                                     "summary");
  storm->require_subcommand(1);

  auto o = std::make_shared<SynthOptions>();
  SynthSettings& s = o->settings;
  CLI::App* synth = storm->add_subcommand("synth", "write an analytic storm file: still water, a uniform current, a "
                                                   "linear (Airy) or Stokes second-order wave, or a JONSWAP sea");
  synth->add_option("model", o->model, "still, current, airy, stokes2 or jonswap")->required();
  synth->add_option("-o,--out", o->output, "storm file to write (.nc); written as <out>.partial, then renamed")
      ->required();
  synth->add_option("--x-min", s.xMin, "left edge of the grid (m)")->capture_default_str()->group("Grid");
  synth->add_option("--x-max", s.xMax, "right edge of the grid (m)")->capture_default_str()->group("Grid");
  synth->add_option("--z-min", s.zMin, "bottom edge of the grid (m)")->capture_default_str()->group("Grid");
  synth->add_option("--z-max", s.zMax, "top edge of the grid (m)")->capture_default_str()->group("Grid");
  synth->add_option("--voxel", s.voxel, "square voxel side (m)")->capture_default_str()->group("Grid");
  synth->add_option("--trunk-origin", s.trunkOrigin, "y of the start of the trunk (m)")
      ->capture_default_str()
      ->group("Grid");
  synth->add_option("--trunk-length", s.trunkLength, "trunk length along y (m)")->capture_default_str()->group("Grid");
  synth
      ->add_flag("--uniform-along-y", s.uniformAlongY,
                 "the fields hold at every y (uniform_along_y = 1): the solver loads units at any y, not only on the "
                 "trunk section")
      ->group("Grid");
  synth->add_option("--swl", s.stillWaterLevel, "z of the still water level (m)")
      ->capture_default_str()
      ->group("Water");
  synth->add_option("--depth", s.depth, "still water depth; the seabed is flat at swl - depth (m)")
      ->capture_default_str()
      ->group("Water");
  synth->add_option("--density", s.density, "water density (kg/m^3)")->capture_default_str()->group("Water");
  synth->add_option("--gravity", s.gravity, "gravitational acceleration (m/s^2)")
      ->capture_default_str()
      ->group("Water");
  synth->add_option("--duration", s.duration, "storm duration (s)")->capture_default_str()->group("Time");
  synth->add_option("--dt", s.dt, "record interval (s)")->capture_default_str()->group("Time");
  synth->add_option("--ramp", s.rampTime, "cosine ramp-up of the waves from rest (s); default: 2 wave periods")
      ->group("Time");
  synth->add_option("--current-u", s.currentU, "current model: x velocity (m/s)")->group("Current");
  synth->add_option("--current-w", s.currentW, "current model: z velocity (m/s)")->group("Current");
  synth->add_option("--height", s.height, "airy, stokes2: wave height H, crest to trough (m)")
      ->capture_default_str()
      ->group("Regular wave");
  synth->add_option("--period", s.period, "airy, stokes2: wave period T (s)")
      ->capture_default_str()
      ->group("Regular wave");
  synth->add_option("--hs", s.hs, "jonswap: significant wave height Hm0 (m)")->capture_default_str()->group("JONSWAP");
  synth->add_option("--tp", s.tp, "jonswap: spectral peak period (s)")->capture_default_str()->group("JONSWAP");
  synth->add_option("--gamma", s.gamma, "jonswap: peak enhancement factor (-)")
      ->capture_default_str()
      ->group("JONSWAP");
  synth->add_option("--components", s.components, "jonswap: number of wave components (-)")
      ->capture_default_str()
      ->group("JONSWAP");
  synth->add_option("--f-min", s.fMinFactor, "jonswap: lowest frequency, as a multiple of fp (-)")
      ->capture_default_str()
      ->group("JONSWAP");
  synth->add_option("--f-max", s.fMaxFactor, "jonswap: highest frequency, as a multiple of fp (-)")
      ->capture_default_str()
      ->group("JONSWAP");
  synth->add_option("--seed", s.seed, "jonswap: seed of the random phases (-)")
      ->capture_default_str()
      ->group("JONSWAP");
  synth
      ->add_option("--variability", o->variability,
                   "Weibull variability model 'k1,l1,k2,l2,k3,l3,k4,l4': shape k and scale l (-) of the classes "
                   "crest_above, crest_below, trough_above, trough_below (default: none)")
      ->group("Variability");
  synth
      ->add_option("--prob-above", o->probAbove,
                   "'pc,pt': probability that a sample lies above the mean in crests and troughs (-), default 0.5,0.5")
      ->group("Variability");
  synth
      ->add_option("--norm-amplitude", o->normAmplitude,
                   "normalisation amplitude a_n (m); P_n = rho g a_n (default: a_n = H/2 or Hs/2)")
      ->group("Variability");
  synth->add_option("--title", s.title, "provenance title (default: the model and its parameters)")->group("Output");
  synth->add_option("--comment", s.comment, "provenance comment")->group("Output");
  synth->add_flag("--double", o->doublePrecision, "store p, u, w, alpha, eta as double instead of float")
      ->group("Output");
  synth->add_option("--deflate", o->deflate, "deflate level 0 (none) to 9")->capture_default_str()->group("Output");
  synth->callback([o, synth] { synthesise(*o, *synth); });

  auto checkPath = std::make_shared<std::string>();
  CLI::App* check = storm->add_subcommand("check", "read every record of a storm file and validate it (exit 2 with "
                                                   "the problem if it is not valid)");
  check->add_option("file", *checkPath, "storm file (.nc)")->required();
  check->callback([checkPath] { checkStorm(*checkPath); });

  auto info = std::make_shared<std::pair<std::string, bool>>("", false);
  CLI::App* infoCmd = storm->add_subcommand("info", "grid, time axis, water, trunk, variability model and provenance "
                                                    "of a storm file");
  infoCmd->add_option("file", info->first, "storm file (.nc)")->required();
  infoCmd->add_flag("--json", info->second, "print as JSON");
  infoCmd->callback([info] { printInfo(info->first, info->second); });
}

} // namespace armour::app
