// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/EnsembleCommands.hpp"

#include "core/TextFile.hpp"
#include "measure/PackAnalysis.hpp"
#include "app/PlacementCheckpoint.hpp"
#include "app/RunCommands.hpp"
#include "app/StopSignals.hpp"
#include "core/AtomicFile.hpp"
#include "core/Error.hpp"
#include "io/SceneOverrides.hpp"
#include "io/SceneReader.hpp"
#include "placement/PlacedScene.hpp"
#include "placement/Placer.hpp"
#include "simulation/CheckpointFile.hpp"
#include "simulation/World.hpp"
#include "storm/StormFile.hpp"

#include <fmt/format.h>
#include <omp.h>

#ifdef ARMOUR_WITH_MPI
#include <mpi.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>


namespace armour::app {
namespace {

namespace fs = std::filesystem;

struct EnsembleOptions {
  std::string file;
  int runs = 16;                   ///< packings (unit: -)
  std::uint64_t firstSeed = 1;     ///< scene seed of packing 0 (unit: -)
  int threads = 0;                 ///< OpenMP threads per rank, 0 = the cores of the node shared by its ranks
  std::string output;
  std::string axis = "nose";
  std::vector<std::string> sets;   ///< --set changes of the placement file
  // Storm realisations (optional).
  std::vector<std::string> storms; ///< storm files, each replayed on every packing
  int realisations = 1;            ///< variability seeds per storm file (unit: -)
  std::uint64_t firstStormSeed = 1; ///< variability seed of realisation 0 (unit: -)
  std::optional<double> duration;  ///< simulated storm time (unit: s); default: to the storm's end
  std::optional<double> timeOffset; ///< storm time at simulation time 0 (unit: s)
  bool plots = false;
  bool restart = false;            ///< continue a stopped ensemble in the same --output
  double checkpointMinutes = 10.0; ///< wall time between a placement's checkpoints (unit: min); 0 = only when stopped
};

/// The command that continues a stopped ensemble (the same options, and --restart).
std::string restartCommand(const EnsembleOptions& o, const fs::path& folder) {
  std::string again = fmt::format("armour ensemble {} --restart --runs {} --first-seed {}", shellWord(o.file), o.runs,
                                  o.firstSeed);
  for (const std::string& storm : o.storms) again += " --storm " + shellWord(storm);
  if (!o.storms.empty())
    again += fmt::format(" --realisations {} --first-storm-seed {}", o.realisations, o.firstStormSeed);
  if (o.duration) again += fmt::format(" --duration {}", *o.duration);
  if (o.timeOffset) again += fmt::format(" --time-offset {}", *o.timeOffset);
  if (o.threads > 0) again += fmt::format(" --threads {}", o.threads);
  again += fmt::format(" --output {} --axis {}", shellWord(folder.string()), shellWord(o.axis));
  for (const std::string& set : o.sets) again += " --set " + shellWord(set);
  if (o.plots) again += " --plots";
  return again;
}

/// Thrown when a stop signal ended a member's placement or storm run: the ensemble stops too.
struct EnsembleStopped : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Thrown when --restart finds a member's record or checkpoint made from other inputs: the whole
/// ensemble is refused (exit 2), no member is recorded as failed and no table is written.
struct RestartRefused : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// ---- Members' records ------------------------------------------------------------------------
// A member's measures are kept in its folder when it ends (measures.csv: "key,value" lines), so that
// a restarted ensemble reads them back instead of running the member again. The fingerprint ties
// them to the member's inputs; the values are written as the shortest text that reads back to the
// same double, so a continued ensemble's tables equal an uninterrupted one's.

struct MemberRecord {
  std::vector<double> values;
  std::string unitPrefix; ///< the packing's unit names' prefix (for its storm runs)
};

void writeRecord(const fs::path& file, const std::string& fingerprint, const std::vector<std::string>& names,
                 const MemberRecord& r) {
  core::writeFileAtomically(file, [&](std::ostream& out) {
    out << "# a member of `armour ensemble` that finished: its measures, read back by --restart\n";
    out << "fingerprint," << fingerprint << "\nunit_prefix," << r.unitPrefix << "\n";
    for (std::size_t k = 0; k < names.size(); ++k) out << names[k] << "," << fmt::format("{}", r.values[k]) << "\n";
  });
}

/// The record of a member that finished before, or nothing when there is none. Throws
/// RestartRefused when it was made from other inputs, or is not whole.
std::optional<MemberRecord> readRecord(const fs::path& file, const std::string& fingerprint,
                                       const std::vector<std::string>& names) {
  std::ifstream in(file);
  if (!in) return std::nullopt;
  std::map<std::string, std::string> fields;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const std::size_t comma = line.find(',');
    if (comma != std::string::npos) fields[line.substr(0, comma)] = line.substr(comma + 1);
  }
  if (fields["fingerprint"] != fingerprint)
    throw RestartRefused(fmt::format("{}: was written by an ensemble of other inputs (another placement file, --set, "
                                     "--axis, storm file or duration: fingerprint {} against {}); continue with the "
                                     "options the ensemble was started with, or start anew without --restart in "
                                     "another --output",
                                     file.string(), fields["fingerprint"], fingerprint));
  MemberRecord r;
  r.unitPrefix = fields["unit_prefix"];
  for (const std::string& name : names) {
    const auto it = fields.find(name);
    char* end = nullptr;
    const double v = it == fields.end() ? 0.0 : std::strtod(it->second.c_str(), &end);
    if (it == fields.end() || end == it->second.c_str() || *end != '\0')
      throw RestartRefused(fmt::format("{}: has no readable value of '{}'; delete the file to run the member again",
                                       file.string(), name));
    r.values.push_back(v);
  }
  return r;
}

/// The fingerprint of a packing: the placement file as the member runs it (with its seed) and the
/// axis its P2 is measured on.
std::string packingFingerprint(const std::string& memberText, const std::string& axis) {
  return simulation::fingerprintOf("packing\n" + memberText + "\naxis " + axis + "\n");
}

/// The fingerprint of a storm member: its packing's, the storm file (path, size and time of its
/// last change), the storm time replayed and the variability seed.
std::string stormFingerprint(const std::string& packing, const EnsembleOptions& o, const std::string& stormFile,
                             std::uint64_t stormSeed) {
  std::error_code ec;
  const auto size = fs::file_size(stormFile, ec);
  const auto changed = fs::last_write_time(stormFile, ec).time_since_epoch().count();
  return simulation::fingerprintOf(fmt::format("storm\n{}\n{}\n{} bytes, changed {}\nduration {}\noffset {}\nseed {}\n",
                                               packing, fs::absolute(stormFile).string(), size, changed,
                                               o.duration ? fmt::format("{}", *o.duration) : "to the end",
                                               o.timeOffset ? fmt::format("{}", *o.timeOffset) : "the scene's", stormSeed));
}

/// The ranks of an MPI job, or one rank without MPI (or when the program was not started by
/// mpirun: Open MPI then runs it as a singleton of size 1).
class Ranks {
public:
  Ranks() {
#ifdef ARMOUR_WITH_MPI
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) {
      MPI_Init(nullptr, nullptr);
      owned_ = true;
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    // Ranks on the same node share its cores.
    MPI_Comm node = MPI_COMM_NULL;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
    MPI_Comm_size(node, &ranksOnNode_);
    MPI_Comm_free(&node);
#endif
  }
  ~Ranks() {
#ifdef ARMOUR_WITH_MPI
    if (owned_) MPI_Finalize();
#endif
  }
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;

  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }
  [[nodiscard]] int ranksOnNode() const { return ranksOnNode_; }

  /// Element-wise sum over the ranks, into every rank's `values`.
  void sum(std::vector<double>& values) const {
#ifdef ARMOUR_WITH_MPI
    if (size_ > 1)
      MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
#else
    (void)values;
#endif
  }

private:
  int rank_ = 0;
  int size_ = 1;
  int ranksOnNode_ = 1;
  [[maybe_unused]] bool owned_ = false;
};

struct Stat {
  std::string name;
  std::vector<double> values;
  [[nodiscard]] std::vector<double> finite() const {
    std::vector<double> f;
    for (double v : values)
      if (std::isfinite(v)) f.push_back(v);
    return f;
  }
  [[nodiscard]] double mean() const {
    const std::vector<double> f = finite();
    double s = 0.0;
    for (double v : f) s += v;
    return f.empty() ? NAN : s / static_cast<double>(f.size());
  }
  [[nodiscard]] double std() const {
    const std::vector<double> f = finite();
    if (f.size() < 2) return 0.0;
    const double m = mean();
    double s = 0.0;
    for (double v : f) s += (v - m) * (v - m);
    return std::sqrt(s / static_cast<double>(f.size() - 1));
  }
};

/// One member: a packing seed, and (with storms) a storm file and a variability seed. Packing k
/// is placed in member-k/ (placed.yaml, its tables, analysis/); its storm runs in
/// member-k/storm-<file index>-seed-<variability seed>/.
struct Member {
  int packing = 0;
  std::uint64_t seed = 0;
  int storm = -1;               ///< index into the storm files; -1 = placement only
  std::uint64_t stormSeed = 0;
  fs::path folder;              ///< the packing's folder
  fs::path run;                 ///< the storm run's folder (empty without a storm)
};

/// The placement a rank did last, reused by its next member on the same packing.
struct PlacedPacking {
  int packing = -1;
  std::vector<double> values;
  std::string unitPrefix;
};

/// The measures of a member, in the order of measureNames.
const std::vector<std::string>& placementMeasures() {
  static const std::vector<std::string> names{
      "delta_rms_m",      "delta_rms_horizontal_m", "p2_mean_director",    "p2_q_tensor",
      "packing_density",  "layer_thickness_m",      "porosity",            "coordination_number",
      "max_displacement_dn", "mean_contact_number",   "units_touching_underlayer", "stacked_units"};
  return names;
}
const std::vector<std::string>& stormMeasures() {
  static const std::vector<std::string> names{
      "storm_moved_0.2dn",     "storm_moved_0.5dn",    "storm_moved_1dn",         "storm_rocking_units",
      "storm_max_displacement_dn", "storm_mean_displacement_dn", "storm_delta_rms_m", "storm_total_displacement_m",
      "storm_p2_q_tensor_after"};
  return names;
}

/// The placement file as member `m` runs it: the --set changes and its seed. The seed drives the
/// height field, the jitter, the orientations and the rocks, unless the file fixes their own.
std::string memberText(const EnsembleOptions& o, const std::string& text, const Member& m) {
  std::vector<std::string> sets = o.sets;
  sets.push_back(fmt::format("seed={}", m.seed));
  return io::applyOverridesToText(text, sets, o.file);
}

/// Place the member's packing and measure it; the placed scene is member/placed.yaml. The placement
/// checkpoints into member/place-checkpoint.nc (every --checkpoint-minutes, and when stopped by a
/// signal: then EnsembleStopped), and with --restart continues from it; the caller removes it once
/// the member's record is written.
std::vector<double> placeMember(const EnsembleOptions& o, const std::string& text, const fs::path& source,
                                const Member& m, std::string& unitPrefix, const StopSignals& signals) {
  const io::Scene scene = io::parseScene(text, source.parent_path(), source.filename().string());
  if (!scene.placement.enabled) core::failInput(o.file, "no placement: block; `armour ensemble` places each member");
  fs::create_directories(m.folder);
  PlacementCheckpoint checkpoint(scene, text, m.folder / "place-checkpoint.nc");
  std::optional<placement::PlacementProgress> resume;
  if (o.restart && fs::exists(checkpoint.path())) {
    try {
      resume = checkpoint.read();
    } catch (const core::InputError& e) {
      throw RestartRefused(e.what());
    }
    std::cout << fmt::format("  continuing its placement from {} ({} units placed)\n", checkpoint.path().string(),
                             resume->unitsDone)
              << std::flush;
  }
  placement::PlaceOptions options;
  if (resume) options.resume = &*resume;
  options.safePoint = checkpoint.safePoint(signals, o.checkpointMinutes);
  placement::PlacementResult placed;
  try {
    placed = placement::place(scene, {}, options);
  } catch (const placement::PlacementStopped&) {
    throw EnsembleStopped(fmt::format("while placing packing seed {} (its checkpoint: {})", m.seed,
                                      checkpoint.path().string()));
  }
  placement::writePlacementOutputs(text, placed, m.folder / "placed.yaml", m.folder);
  // Displacements from where each unit was released (seed 001 test 3: the crane positions).
  measure::PoseMap release;
  for (const auto& u : placed.units) release[u.name] = {u.gridPoint, u.releaseOrientation};
  measure::AnalyseSettings settings;
  settings.unitPrefix = unitPrefix = scene.placement.namePrefix + "_";
  settings.axis = o.axis;
  const measure::PackReport report = measure::analysePack(placed.scene, settings, nullptr, &release);
  measure::writePackReport(report, m.folder / "analysis");
  return {report.displacement->deltaRms,
          report.displacement->deltaRmsHorizontal,
          report.p2Mean.p2,
          report.p2Q.p2,
          placed.summary.packingDensity > 0.0 ? placed.summary.packingDensity : report.packingHull.phi,
          placed.summary.layerThickness,
          placed.summary.porosity,
          report.contacts.coordinationNumber,
          report.displacement->maxDn,
          report.contacts.meanContactNumber,
          static_cast<double>(report.touchingUnderlayer),
          static_cast<double>(report.stackedUnits)};
}

/// Replay the member's storm on its placed scene and measure the damage (from the placed poses).
std::vector<double> stormMember(const EnsembleOptions& o, const Member& m, int threads, const std::string& unitPrefix,
                                const StopSignals& signals) {
  const fs::path placedScene = m.folder / "placed.yaml";
  RunRequest run;
  run.scene = placedScene.string();
  run.stormFile = o.storms[static_cast<std::size_t>(m.storm)];
  run.output = m.run.string();
  run.threads = threads;
  run.timeOffset = o.timeOffset;
  if (o.duration) {
    run.duration = *o.duration;
    run.durationGiven = true;
  }
  run.variabilitySeed = m.stormSeed;
  // A run that failed left a checkpoint of its failed step, which cannot be continued: run it anew.
  run.restart = o.restart && fs::exists(m.run / "checkpoint.nc") && !fs::exists(m.run / "error.txt");
  std::error_code ec;
  fs::remove(m.run / "error.txt", ec);
  if (run.restart) std::cout << fmt::format("  continuing its storm run from {}\n", (m.run / "checkpoint.nc").string()) << std::flush;
  measure::PoseMap after;
  try {
    after = runScene(run);
  } catch (const core::InputError& e) {
    // The scene was read before: what a restarted run refuses is its checkpoint (another scene).
    if (run.restart) throw RestartRefused(e.what());
    throw;
  } catch (const CLI::RuntimeError&) {
    if (signals.received() != 0)
      throw EnsembleStopped(fmt::format("in the storm run {} (its checkpoint: {})", m.run.string(),
                                        (m.run / "checkpoint.nc").string()));
    throw;
  }
  const io::Scene scene = io::readScene(placedScene);
  const measure::PoseMap before = measure::posesOf(scene);
  measure::AnalyseSettings settings;
  settings.unitPrefix = unitPrefix;
  settings.axis = o.axis;
  settings.stateName = (m.run / "final_state.csv").string();
  const measure::PackReport report = measure::analysePack(scene, settings, &after, &before);
  measure::writePackReport(report, m.run / "analysis");
  const analysis::PackDisplacement& d = *report.displacement;
  const auto count = [&](double threshold) {
    for (std::size_t k = 0; k < d.thresholdsDn.size(); ++k)
      if (std::abs(d.thresholdsDn[k] - threshold) < 1e-12) return static_cast<double>(d.movedCounts[k]);
    return std::numeric_limits<double>::quiet_NaN();
  };
  return {count(0.2),    count(0.5), count(1.0), static_cast<double>(d.rockingCount), d.maxDn, d.meanDn,
          d.deltaRms, d.total,     report.p2Q.p2};
}

void writeError(const fs::path& folder, const std::string& message) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  core::writeFileAtomically(folder / "error.txt", [&](std::ostream& out) { out << message << "\n"; });
}

/// Member m's packing: its measures and its units' name prefix, read from its record (--restart)
/// or placed now and recorded.
MemberRecord packingOf(const EnsembleOptions& o, const std::string& text, const fs::path& source, const Member& m,
                       const StopSignals& signals, std::string& fingerprint) {
  const std::string placementText = memberText(o, text, m);
  fingerprint = packingFingerprint(placementText, o.axis);
  const fs::path file = m.folder / "measures.csv";
  if (o.restart) {
    if (std::optional<MemberRecord> r = readRecord(file, fingerprint, placementMeasures())) {
      std::cout << fmt::format("  packing seed {}: placed before ({})\n", m.seed, file.string()) << std::flush;
      return *r;
    }
  }
  if (signals.received() != 0) throw EnsembleStopped(fmt::format("before placing packing seed {}", m.seed));
  std::error_code ec;
  fs::remove(m.folder / "error.txt", ec);
  MemberRecord r;
  r.values = placeMember(o, placementText, source, m, r.unitPrefix, signals);
  writeRecord(file, fingerprint, placementMeasures(), r);
  fs::remove(m.folder / "place-checkpoint.nc", ec); // the record is the result now (a kill before it continues from here)
  return r;
}

/// Member m's storm measures, read from its record (--restart) or run now and recorded.
std::vector<double> stormOf(const EnsembleOptions& o, const Member& m, int threads, const MemberRecord& packing,
                            const std::string& packingFingerprint, const StopSignals& signals) {
  const std::string& file = o.storms[static_cast<std::size_t>(m.storm)];
  const std::string fingerprint = stormFingerprint(packingFingerprint, o, file, m.stormSeed);
  const fs::path record = m.run / "measures.csv";
  if (o.restart) {
    if (std::optional<MemberRecord> r = readRecord(record, fingerprint, stormMeasures())) {
      std::cout << fmt::format("  stormed before ({})\n", record.string()) << std::flush;
      return r->values;
    }
  }
  if (signals.received() != 0) throw EnsembleStopped(fmt::format("before the storm run {}", m.run.string()));
  std::vector<double> values = stormMember(o, m, threads, packing.unitPrefix, signals);
  writeRecord(record, fingerprint, stormMeasures(), {values, packing.unitPrefix});
  return values;
}

/// This rank's members [first, last): each one's row of `table` gets its measures and its status
/// (1 done, 0 failed). A member that fails (its dynamics stopped: the run wrote its state and log)
/// is recorded and the others go on: its row is empty and its error.txt says why. The other ranks
/// must reach the gathering after this, so no member's failure may end the loop; a stop signal
/// does (EnsembleStopped), as it reaches every rank of mpirun.
void runMembers(const EnsembleOptions& o, const std::string& text, const fs::path& source,
                const std::vector<Member>& members, std::size_t first, std::size_t last, int threads, int rank,
                const StopSignals& signals, std::vector<double>& table, std::size_t width) {
  int placedPacking = -1; // the packing this rank holds, reused by its next member on the same packing
  MemberRecord packing;
  std::string fingerprint;
  for (std::size_t i = first; i < last; ++i) {
    const Member& m = members[i];
    std::cout << fmt::format("[rank {}] member {}/{}: packing seed {}{}\n", rank, i + 1, members.size(), m.seed,
                             m.storm >= 0 ? fmt::format(", storm {} variability seed {}",
                                                        o.storms[static_cast<std::size_t>(m.storm)], m.stormSeed)
                                          : std::string())
              << std::flush;
    double* row = &table[i * width];
    try {
      if (placedPacking != m.packing) {
        placedPacking = -1; // until this placement succeeds
        packing = packingOf(o, text, source, m, signals, fingerprint);
        placedPacking = m.packing;
      }
      std::vector<double> values = packing.values;
      if (m.storm >= 0) {
        const std::vector<double> damage = stormOf(o, m, threads, packing, fingerprint, signals);
        values.insert(values.end(), damage.begin(), damage.end());
      }
      std::copy(values.begin(), values.end(), row);
      row[width - 1] = 1.0;
    } catch (const EnsembleStopped&) {
      throw;
    } catch (const RestartRefused&) {
      throw;
    } catch (const std::exception& e) {
      const std::string message = fmt::format("member {} (packing seed {}) failed: {} (see its folder's logs)", i,
                                              m.seed, e.what());
      std::cerr << message << "\n";
      writeError(m.run.empty() ? m.folder : m.run, message);
      for (std::size_t c = 0; c + 1 < width; ++c) row[c] = std::numeric_limits<double>::quiet_NaN();
    }
  }
}

void ensemble(const EnsembleOptions& o) {
  const Ranks ranks;
  const StopSignals signals;
  if (o.runs < 1) core::failInput("--runs", "{}: give at least one member", o.runs);
  if (o.realisations < 1) core::failInput("--realisations", "{}: give at least one per storm file", o.realisations);
  if (o.threads < 0) core::failInput("--threads", "{}: give a positive number of threads, or 0", o.threads);
  if (!o.storms.empty() && o.realisations > 1)
    for (const std::string& file : o.storms)
      if (!storm::StormReader(file).header().variability.present)
        core::failInput(file, "carries no variability model, so its --realisations {} would all be the same storm; "
                              "give --realisations 1, or a storm file written with variability (foam-proxy fits "
                              "one; armour storm-file synth --variability)",
                        o.realisations);
  // Threads per rank: what was asked, else the node's cores shared by the ranks on it.
  const int hardware = static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  const int threads = o.threads > 0 ? o.threads : std::max(1, hardware / ranks.ranksOnNode());
  omp_set_num_threads(threads);

  const std::string text = core::readTextFile(o.file, "the placement file");
  const fs::path source = fs::absolute(o.file);
  const fs::path folder = o.output.empty() ? source.parent_path() / (source.stem().string() + "-ensemble")
                                           : fs::absolute(o.output);
  // The file is read and checked by every rank before any work: a bad file stops all of them.
  (void)io::parseScene(io::applyOverridesToText(text, o.sets, o.file), source.parent_path(),
                       source.filename().string());
  if (!(o.checkpointMinutes >= 0.0) || !std::isfinite(o.checkpointMinutes))
    core::failInput("--checkpoint-minutes", "{}: give the wall time between checkpoints in minutes (>= 0; 0 = only "
                                            "when stopped by SIGINT or SIGTERM)", o.checkpointMinutes);
  if (o.restart && !fs::is_directory(folder))
    core::failInput(folder.string(), "does not exist, so there is no ensemble to continue; start it without --restart "
                                     "(or give the --output of the stopped one)");
  fs::create_directories(folder);

  std::vector<Member> members;
  const int storms = o.storms.empty() ? 0 : static_cast<int>(o.storms.size());
  for (int k = 0; k < o.runs; ++k) {
    const std::uint64_t seed = o.firstSeed + static_cast<std::uint64_t>(k);
    if (storms == 0) {
      members.push_back({k, seed, -1, 0, folder / fmt::format("member-{:03d}", k), {}});
      continue;
    }
    for (int s = 0; s < storms; ++s)
      for (int r = 0; r < o.realisations; ++r) {
        const std::uint64_t stormSeed = o.firstStormSeed + static_cast<std::uint64_t>(r);
        const fs::path packing = folder / fmt::format("member-{:03d}", k);
        members.push_back({k, seed, s, stormSeed, packing, packing / fmt::format("storm-{}-seed-{}", s, stormSeed)});
      }
  }
  std::vector<std::string> names = placementMeasures();
  if (storms > 0) names.insert(names.end(), stormMeasures().begin(), stormMeasures().end());
  const std::size_t width = names.size() + 1; // + a status column: 1 done, 0 failed
  std::vector<double> table(members.size() * width, 0.0);
  if (ranks.rank() == 0)
    std::cout << fmt::format("ensemble: {} members ({} packings{}) on {} rank{}, {} thread{} each\n", members.size(),
                             o.runs,
                             storms ? fmt::format(" x {} storm file{} x {} realisation{}", storms, storms > 1 ? "s" : "",
                                                  o.realisations, o.realisations > 1 ? "s" : "")
                                    : std::string(),
                             ranks.size(), ranks.size() > 1 ? "s" : "", threads, threads > 1 ? "s" : "")
              << std::flush;
  // Blocks of consecutive members per rank: the storm runs of one packing mostly fall to one rank,
  // which places the packing once.
  const std::size_t ranksCount = static_cast<std::size_t>(ranks.size()), rank = static_cast<std::size_t>(ranks.rank());
  const std::size_t first = members.size() * rank / ranksCount, last = members.size() * (rank + 1) / ranksCount;
  try {
    runMembers(o, text, source, members, first, last, threads, ranks.rank(), signals, table, width);
  } catch (const EnsembleStopped& e) {
    std::cerr << fmt::format("{}: stopped by {} {}; the members that finished are recorded in their folders\n"
                             "continue with: {}\n",
                             o.file, signalName(signals.received()), e.what(), restartCommand(o, folder));
    throw CLI::RuntimeError(kExitStopped);
  } catch (const RestartRefused& e) {
    core::failInput("--restart", "{}", e.what());
  }
  ranks.sum(table); // each row is filled by exactly one rank, zeros elsewhere
  if (ranks.rank() != 0) return;

  std::vector<Stat> stats;
  for (const std::string& n : names) stats.push_back({n, {}});
  std::string rows = "member,packing,packing_seed,storm,storm_seed";
  for (const std::string& n : names) rows += "," + n;
  rows += ",status\n";
  std::size_t failed = 0;
  for (std::size_t i = 0; i < members.size(); ++i) {
    const Member& m = members[i];
    const double* row = &table[i * width];
    const bool done = row[width - 1] > 0.5;
    failed += done ? 0 : 1;
    rows += fmt::format("{},{},{},{},{}", i, m.packing, m.seed, m.storm >= 0 ? o.storms[static_cast<std::size_t>(m.storm)] : "",
                        m.storm >= 0 ? std::to_string(m.stormSeed) : "");
    for (std::size_t c = 0; c + 1 < width; ++c) {
      rows += fmt::format(",{}", done ? row[c] : std::numeric_limits<double>::quiet_NaN());
      if (done) stats[c].values.push_back(row[c]);
    }
    rows += done ? ",done\n" : ",failed\n";
  }
  std::string summary = fmt::format("ensemble of {} members of {} (packing seeds {}..{}{}), mean +- standard deviation"
                                   " over the {} members that finished:\n",
                                   members.size(), o.file, o.firstSeed,
                                   o.firstSeed + static_cast<std::uint64_t>(o.runs) - 1,
                                   storms ? fmt::format("; variability seeds {}..{}", o.firstStormSeed,
                                                        o.firstStormSeed + static_cast<std::uint64_t>(o.realisations) - 1)
                                          : std::string(),
                                   members.size() - failed);
  std::string json = fmt::format("{{\n  \"members\": {},\n  \"failed\": {},\n  \"ranks\": {},\n", members.size(), failed,
                                 ranks.size());
  for (std::size_t s = 0; s < stats.size(); ++s) {
    summary += fmt::format("  {:<28} {:.4g} +- {:.2g}\n", stats[s].name, stats[s].mean(), stats[s].std());
    json += fmt::format("  \"{}\": {{\"mean\": {}, \"std\": {}}}{}\n", stats[s].name, stats[s].mean(), stats[s].std(),
                        s + 1 < stats.size() ? "," : "");
  }
  json += "}\n";
  core::writeFileAtomically(folder / "ensemble.csv", [&](std::ostream& out) { out << rows; });
  core::writeFileAtomically(folder / "ensemble.txt", [&](std::ostream& out) { out << summary; });
  core::writeFileAtomically(folder / "ensemble.json", [&](std::ostream& out) { out << json; });
  std::cout << summary << fmt::format("tables: {}/ensemble.csv, ensemble.json; packings in member-*/{}\n", folder.string(),
                                     storms ? ", their storm runs in member-*/storm-*/" : "");
  if (o.plots) runUtility("plot_ensemble.py", {(folder / "ensemble.csv").string()}, "plots");
  if (failed > 0) {
    std::cerr << fmt::format("error: {} of {} members failed; their error.txt says why\n", failed, members.size());
    throw CLI::RuntimeError(3);
  }
}

} // namespace

void addEnsembleCommands(CLI::App& app, const GlobalOptions& /*global*/) {
  auto e = std::make_shared<EnsembleOptions>();
  auto* cmd = app.add_subcommand("ensemble", "place N packings of a placement file (seeds S..S+N-1) and, with --storm, "
                                             "replay storm realisations on each; mean +- std of the pack and damage "
                                             "measures (seed 001 Table 1); runs under mpirun -np N");
  cmd->add_option("file", e->file, "scene file with a placement: block")->required()->check(CLI::ExistingFile);
  cmd->add_option("--runs", e->runs, "packings")->capture_default_str();
  cmd->add_option("--first-seed", e->firstSeed, "scene seed of the first packing")->capture_default_str();
  cmd->add_option("--storm", e->storms, "storm file replayed on every packing (repeatable: one realisation each)")
      ->take_all()
      ->allow_extra_args(false)
      ->check(CLI::ExistingFile);
  cmd->add_option("--realisations", e->realisations, "variability seeds per storm file (seed 000's Weibull draws)")
      ->capture_default_str();
  cmd->add_option("--first-storm-seed", e->firstStormSeed, "variability seed of the first realisation")
      ->capture_default_str();
  cmd->add_option("--duration", e->duration, "simulated storm time (s); default: to the storm's end");
  cmd->add_option("--time-offset", e->timeOffset, "storm time at simulation time 0 (s)");
  cmd->add_option("--threads", e->threads, "OpenMP threads per rank (0 = the node's cores shared by its ranks)")
      ->capture_default_str();
  cmd->add_option("--output", e->output, "output folder (default: <file stem>-ensemble beside the file)");
  cmd->add_option("--axis", e->axis, "unit axis for P2")->capture_default_str();
  addSetOption(*cmd, e->sets);
  cmd->add_flag("--plots", e->plots, "also draw the spread plot (utilities/plot_ensemble.py, matplotlib)");
  cmd->add_flag("--restart", e->restart,
                "continue a stopped ensemble in its --output folder: members that finished are read back from "
                "their measures.csv, a placement continues from its place-checkpoint.nc, a storm run from its "
                "checkpoint.nc");
  cmd->add_option("--checkpoint-minutes", e->checkpointMinutes,
                  "wall time between a placement's checkpoints (min); 0 = only when stopped by SIGINT or SIGTERM")
      ->capture_default_str();
  cmd->callback([e] { ensemble(*e); });
}

} // namespace armour::app
