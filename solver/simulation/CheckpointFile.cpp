// SPDX-License-Identifier: GPL-3.0-or-later
#include "simulation/CheckpointFile.hpp"

#include "core/AtomicFile.hpp"
#include "core/BuildInfo.hpp"
#include "core/Error.hpp"
#include "core/Hash.hpp"
#include "core/ProbeInChild.hpp"

#include <fmt/format.h>
#include <netcdf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace armour::simulation {
namespace {

namespace fs = std::filesystem;
using dynamics::Quat;
using dynamics::Vec3;

constexpr const char* kVersionAttribute = "armour_checkpoint_version";
constexpr const char* kAxesComment = "world frame: x onshore, y along the trunk, z up; vec index 0, 1, 2 = x, y, z";
/// Flag bits of contact_second and contact_key (WorldInternal.hpp): documented in the file for readers.
constexpr const char* kSecondComment =
    "body index of the second body; or 0x80000000 | plane index for a static plane, 0x40000000 | piece index for a "
    "static convex piece";
constexpr const char* kKeyComment =
    "surface sample of the first body (bit 0x80000000 clear) or of the second body (set) | sample index";

// ---------------------------------------------------------------------------------------------
// Hashing
// ---------------------------------------------------------------------------------------------

using core::fnv1a;

/// A mesh file by its content, not its place: "<N bytes, fnv1a64 H>".
std::string fileIdentity(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    core::failInput(file.string(), "cannot read the mesh file to identify the scene for a checkpoint; check that it "
                                   "exists and is readable");
  }
  std::ostringstream bytes;
  bytes << in.rdbuf();
  const std::string content = bytes.str();
  return fmt::format("<{} bytes, fnv1a64 {:016x}>", content.size(), fnv1a(content));
}

/// A storm file by its content, cheaply: its size and a hash of its first and last MiB (storm
/// files run to gigabytes; the header, the time axis and the last records change with any rewrite).
std::string stormIdentity(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    core::failInput(file.string(), "cannot read the storm file to identify the scene for a checkpoint; check that it "
                                   "exists and is readable (hydro.storm.file)");
  }
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::uint64_t>(in.tellg());
  constexpr std::uint64_t kPart = 1u << 20;
  std::string bytes(static_cast<std::size_t>(std::min(size, kPart)), '\0');
  in.seekg(0);
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  std::uint64_t h = fnv1a(bytes);
  if (size > kPart) {
    bytes.assign(static_cast<std::size_t>(std::min(size - kPart, kPart)), '\0');
    in.seekg(static_cast<std::streamoff>(size - bytes.size()));
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    h = fnv1a(bytes, h);
  }
  return fmt::format("<{} bytes, fnv1a64 of the first and last MiB {:016x}>", size, h);
}

/// First line where two texts differ, for messages ("" past the end of one of them).
std::pair<std::string, std::string> firstDifference(const std::string& a, const std::string& b) {
  std::istringstream sa(a), sb(b);
  std::string la, lb;
  while (true) {
    const bool hasA = static_cast<bool>(std::getline(sa, la));
    const bool hasB = static_cast<bool>(std::getline(sb, lb));
    if (!hasA && !hasB) {
      return {};
    }
    if (!hasA) la = "(nothing)";
    if (!hasB) lb = "(nothing)";
    if (!hasA || !hasB || la != lb) {
      const auto trim = [](std::string s) {
        s.erase(0, s.find_first_not_of(' '));
        return s;
      };
      return {trim(la), trim(lb)};
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------------

class Writer {
public:
  explicit Writer(const fs::path& path) : path_(path) {}

  void check(int status, const char* what) const {
    if (status != NC_NOERR) {
      core::failInput(path_.string(),
                      "netCDF could not {} of the checkpoint: {}; check that the output folder exists and is "
                      "writable and that the disk is not full",
                      what, nc_strerror(status));
    }
  }
  void text(int ncid, int var, const char* name, const std::string& value) const {
    check(nc_put_att_text(ncid, var, name, value.size(), value.c_str()), "write an attribute");
  }
  void number(int ncid, const char* name, double value) const {
    check(nc_put_att_double(ncid, NC_GLOBAL, name, NC_DOUBLE, 1, &value), "write an attribute");
  }
  void integer(int ncid, const char* name, int value) const {
    check(nc_put_att_int(ncid, NC_GLOBAL, name, NC_INT, 1, &value), "write an attribute");
  }

private:
  fs::path path_;
};

// ---------------------------------------------------------------------------------------------
// Reading
// ---------------------------------------------------------------------------------------------

/// An open checkpoint being read: every error names the file.
class Reader {
public:
  explicit Reader(const fs::path& path) : where_(path.string()) {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      core::failInput(where_, "no checkpoint here: a restart continues from the checkpoint.nc that a run writes into "
                              "its output folder; check --output (or output.folder in the scene), or run without "
                              "--restart to start anew");
    }
    const int status = nc_open(path.c_str(), NC_NOWRITE, &ncid_);
    if (status != NC_NOERR) {
      ncid_ = -1;
      core::failInput(where_, "cannot be read as a netCDF file ({}): it is damaged (cut short?) or not a checkpoint; "
                              "restart from another checkpoint or start the run anew without --restart",
                      nc_strerror(status));
    }
  }
  ~Reader() {
    if (ncid_ >= 0) {
      nc_close(ncid_);
    }
  }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  template <typename... Args>
  [[noreturn]] void fail(fmt::format_string<Args...> format, Args&&... args) const {
    core::failInput(where_, format, std::forward<Args>(args)...);
  }
  [[noreturn]] void damaged(const std::string& item, const std::string& problem) const {
    fail("{}: {}; the file is damaged or was not written by armour: restart from another checkpoint or start the run "
         "anew without --restart",
         item, problem);
  }

  [[nodiscard]] bool hasAttribute(const char* name) const {
    return nc_inq_att(ncid_, NC_GLOBAL, name, nullptr, nullptr) == NC_NOERR;
  }
  std::string text(int var, const char* name) const {
    nc_type type = NC_NAT;
    std::size_t length = 0;
    if (nc_inq_att(ncid_, var, name, &type, &length) != NC_NOERR) {
      damaged(fmt::format("attribute '{}'", name), "missing");
    }
    if (type != NC_CHAR) {
      damaged(fmt::format("attribute '{}'", name), "is not text");
    }
    std::string value(length, '\0');
    if (length > 0 && nc_get_att_text(ncid_, var, name, value.data()) != NC_NOERR) {
      damaged(fmt::format("attribute '{}'", name), "cannot be read");
    }
    return value;
  }
  /// A scalar global attribute of the given type (converted by netCDF only within its type).
  template <typename T>
  T scalar(const char* name, nc_type expected) const {
    nc_type type = NC_NAT;
    std::size_t length = 0;
    if (nc_inq_att(ncid_, NC_GLOBAL, name, &type, &length) != NC_NOERR) {
      damaged(fmt::format("global attribute '{}'", name), "missing");
    }
    if (type != expected || length != 1) {
      damaged(fmt::format("global attribute '{}'", name), "has the wrong type or length");
    }
    T value{};
    if (nc_get_att(ncid_, NC_GLOBAL, name, &value) != NC_NOERR) {
      damaged(fmt::format("global attribute '{}'", name), "cannot be read");
    }
    return value;
  }

  std::size_t dimension(const char* name, int& id) const {
    std::size_t length = 0;
    if (nc_inq_dimid(ncid_, name, &id) != NC_NOERR || nc_inq_dimlen(ncid_, id, &length) != NC_NOERR) {
      damaged(fmt::format("dimension '{}'", name), "missing");
    }
    return length;
  }

  /// Id of variable `name`, checked to have `type` and exactly the dimensions `dims`.
  int variable(const char* name, nc_type type, std::initializer_list<int> dims) const {
    int var = -1;
    if (nc_inq_varid(ncid_, name, &var) != NC_NOERR) {
      damaged(fmt::format("variable '{}'", name), "missing");
    }
    nc_type actual = NC_NAT;
    int ndims = 0;
    std::array<int, NC_MAX_VAR_DIMS> ids{};
    if (nc_inq_var(ncid_, var, nullptr, &actual, &ndims, ids.data(), nullptr) != NC_NOERR) {
      damaged(fmt::format("variable '{}'", name), "cannot be read");
    }
    if (actual != type) {
      damaged(fmt::format("variable '{}'", name), "has another type than armour writes");
    }
    if (ndims != static_cast<int>(dims.size()) || !std::equal(dims.begin(), dims.end(), ids.begin())) {
      damaged(fmt::format("variable '{}'", name), "has other dimensions than armour writes");
    }
    return var;
  }
  /// Read a whole variable into `values` (resized to `count`).
  template <typename T>
  void get(const char* name, int var, std::size_t count, std::vector<T>& values) const {
    values.assign(count, T{});
    if (count == 0) {
      return;
    }
    const int status = nc_get_var(ncid_, var, values.data());
    if (status != NC_NOERR) {
      damaged(fmt::format("variable '{}'", name), fmt::format("cannot be read ({})", nc_strerror(status)));
    }
  }

  [[nodiscard]] int id() const { return ncid_; }

private:
  std::string where_;
  int ncid_ = -1;
};

Vec3 vec3(const std::vector<double>& v, std::size_t i) { return Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]); }

} // namespace

// ---------------------------------------------------------------------------------------------
// Scene identity
// ---------------------------------------------------------------------------------------------

std::string sceneIdentity(const io::Scene& scene) {
  io::Scene s = scene;
  s.name.clear();
  s.sourceName.clear();
  s.baseDir.clear();
  s.description.clear();
  s.warnings.clear();
  s.duration = 0.0;
  s.output = io::OutputSettings{};
  for (io::ShapeSpec& shape : s.shapes) {
    if (shape.source == io::ShapeSource::MeshFile) {
      const std::string id = fileIdentity(shape.meshFile);
      if (shape.name == "mesh:" + shape.meshFile.string()) {
        shape.name = "mesh:" + id; // an inline mesh shape is named by its path
      }
      shape.meshFile = id;
    }
  }
  for (io::StaticMesh& mesh : s.statics.meshes) {
    mesh.file = fileIdentity(mesh.file);
  }
  if (s.hydro.enabled && s.hydro.model == hydro::HydroModel::Storm) {
    s.hydro.storm.file = stormIdentity(s.hydro.storm.file);
  }
  // describeScene with the lines that name the file, the duration and the output block left out.
  std::istringstream in(io::describeScene(s));
  std::string identity = fmt::format("armour scene identity {}\n", kCheckpointFormatVersion);
  bool first = true, inOutput = false;
  for (std::string line; std::getline(in, line);) {
    if (first) { // "scene <name> (from <file>, paths relative to <folder>)"
      first = false;
      continue;
    }
    if (inOutput && line.starts_with(" ")) {
      continue;
    }
    inOutput = line == "output:";
    if (inOutput || line.starts_with("  duration = ")) {
      continue;
    }
    identity += line;
    identity += '\n';
  }
  return identity;
}

std::string fingerprintOf(const std::string& identity) { return fmt::format("fnv1a64:{:016x}", fnv1a(identity)); }

std::string sceneFingerprint(const io::Scene& scene) { return fingerprintOf(sceneIdentity(scene)); }

// ---------------------------------------------------------------------------------------------
// Write
// ---------------------------------------------------------------------------------------------

namespace {

/// The netCDF ids of a checkpoint's variables (-1: left out).
struct CheckpointVars {
  int position = -1, orientation = -1, velocity = -1, momentum = -1, force = -1, torque = -1;
  int externalForce = -1, externalTorque = -1, sleepLoad = -1;
  std::vector<int> stages; ///< one per load stage
  int cache = -1, motion = -1, rest = -1, count = -1, maxForce = -1, names = -1;
  std::size_t nameLength = 1;
  int first = -1, second = -1, key = -1, stretch = -1, sliding = -1, normalImpulse = -1, tangentImpulse = -1;
  int identity = -1, application = -1;
};

/// The global attributes of a checkpoint (define mode).
void putCheckpointAttributes(const Writer& w, int ncid, const Checkpoint& c) {
  const WorldState& s = c.state;
  w.text(ncid, NC_GLOBAL, "title", "armour checkpoint");
  w.text(ncid, NC_GLOBAL, "comment",
         "Complete dynamic state of an armour run, for `armour run <scene> --restart` (docs/output-files.md, "
         "docs/user-guide.md). Units: time, last_vtk_time and last_series_time in s; energy_minimum, external_work "
         "and energy_peak in J. Shapes, materials and static geometry come from the scene, identified by "
         "scene_fingerprint.");
  w.integer(ncid, kVersionAttribute, kCheckpointFormatVersion);
  w.text(ncid, NC_GLOBAL, "armour_build", core::buildInfo());
  w.text(ncid, NC_GLOBAL, "scene_fingerprint", c.sceneFingerprint);
  w.number(ncid, "time", s.time);
  const unsigned long long steps = s.steps;
  w.check(nc_put_att_ulonglong(ncid, NC_GLOBAL, "steps", NC_UINT64, 1, &steps), "write an attribute");
  w.integer(ncid, "forces_ready", s.forcesReady ? 1 : 0);
  w.number(ncid, "energy_minimum", s.energyMinimum);
  w.number(ncid, "external_work", s.externalWork);
  w.number(ncid, "energy_peak", s.energyPeak);
  w.integer(ncid, "energy_started", s.energyStarted ? 1 : 0);
  w.number(ncid, "last_vtk_time", c.outputs.lastVtkTime);
  w.number(ncid, "last_series_time", c.outputs.lastSeriesTime);
  if (!c.stopReason.empty()) {
    w.text(ncid, NC_GLOBAL, "stop_reason", c.stopReason);
  }
}

/// The dimensions and variables of a checkpoint, with their attributes (define mode).
CheckpointVars defineCheckpointVars(const Writer& w, int ncid, const Checkpoint& c) {
  const WorldState& s = c.state;
  const std::size_t n = s.bodies.size();
  const std::size_t m = s.contacts.size();
  CheckpointVars v;
  // A dimension of length 0 is unlimited in netCDF: a state without contacts keeps a valid file.
  int bodyDim = -1, contactDim = -1, vecDim = -1, quatDim = -1;
  w.check(nc_def_dim(ncid, "body", n, &bodyDim), "define the body dimension");
  w.check(nc_def_dim(ncid, "contact", m, &contactDim), "define the contact dimension");
  w.check(nc_def_dim(ncid, "vec", 3, &vecDim), "define the vec dimension");
  w.check(nc_def_dim(ncid, "quat", 4, &quatDim), "define the quat dimension");

  const auto define = [&](const char* name, nc_type type, std::initializer_list<int> dims, const char* units,
                          const std::string& longName) {
    int var = -1;
    const std::vector<int> ids(dims);
    w.check(nc_def_var(ncid, name, type, static_cast<int>(ids.size()), ids.data(), &var), "define a variable");
    if (units != nullptr) {
      w.text(ncid, var, "units", units);
    }
    w.text(ncid, var, "long_name", longName);
    return var;
  };
  v.position = define("position", NC_DOUBLE, {bodyDim, vecDim}, "m", "centre of mass position");
  v.orientation = define("orientation", NC_DOUBLE, {bodyDim, quatDim}, "1",
                                 "orientation quaternion (w, x, y, z), principal body frame to world");
  v.velocity = define("velocity", NC_DOUBLE, {bodyDim, vecDim}, "m s-1", "centre of mass velocity");
  v.momentum = define("angular_momentum", NC_DOUBLE, {bodyDim, vecDim}, "kg m2 s-1",
                              "angular momentum about the centre of mass, world frame");
  v.force = define("force", NC_DOUBLE, {bodyDim, vecDim}, "N",
                           "force of the last force evaluation (contacts and external loads; gravity excluded)");
  v.torque = define("torque", NC_DOUBLE, {bodyDim, vecDim}, "N m",
                            "torque about the centre of mass of the last force evaluation, world frame");
  v.externalForce = define("external_force", NC_DOUBLE, {bodyDim, vecDim}, "N",
                                   "load stages' force of the last force evaluation (hydrodynamics)");
  v.externalTorque = define("external_torque", NC_DOUBLE, {bodyDim, vecDim}, "N m",
                                    "load stages' torque about the centre of mass, last force evaluation");
  v.sleepLoad = define("sleep_load", NC_DOUBLE, {bodyDim, vecDim}, "N",
                               "load stages' force when the body fell asleep (wake logic)");
  // Each load stage's own state (held loads, update times) as a flat array named after the stage.
  std::vector<int> stageVars;
  for (std::size_t k = 0; k < s.loadStages.size(); ++k) {
    int dim = -1;
    const std::string dimName = fmt::format("load_stage_{}_length", k);
    w.check(nc_def_dim(ncid, dimName.c_str(), std::max<std::size_t>(1, s.loadStages[k].second.size()), &dim),
            "define a load stage dimension");
    const std::string varName = fmt::format("load_stage_{}", k);
    v.stages.push_back(define(varName.c_str(), NC_DOUBLE, {dim}, nullptr, "state of a load stage"));
    w.text(ncid, v.stages.back(), "stage_name", s.loadStages[k].first);
    const auto used = static_cast<unsigned long long>(s.loadStages[k].second.size());
    w.check(nc_put_att_ulonglong(ncid, v.stages.back(), "used_length", NC_UINT64, 1, &used), "write an attribute");
  }
  // The constraint solver's reused manifolds (flat; absent when empty).
  if (!s.manifoldCache.empty()) {
    int dim = -1;
    w.check(nc_def_dim(ncid, "manifold_cache_length", s.manifoldCache.size(), &dim), "define a dimension");
    v.cache = define("manifold_cache", NC_DOUBLE, {dim}, nullptr,
                      "constraint solver: reused contact patches per pair (World::saveManifoldCache)");
  }
  for (int var : {v.position, v.velocity, v.momentum, v.force, v.torque, v.externalForce, v.externalTorque, v.sleepLoad}) {
    w.text(ncid, var, "comment", kAxesComment);
  }
  v.motion = define("motion_type", NC_UBYTE, {bodyDim}, "1", "motion type");
  const std::array<unsigned char, 3> flags{0, 1, 2};
  w.check(nc_put_att_uchar(ncid, v.motion, "flag_values", NC_UBYTE, flags.size(), flags.data()), "write an attribute");
  w.text(ncid, v.motion, "flag_meanings", "static dynamic sleeping");
  v.rest = define("rest_time", NC_DOUBLE, {bodyDim}, "s", "time at rest so far (sleep logic)");
  v.count = define("contact_count", NC_INT, {bodyDim}, "1", "engaged contact points, last force evaluation");
  v.maxForce = define("max_contact_force", NC_DOUBLE, {bodyDim}, "N",
                              "largest contact point force, last force evaluation");
  if (!c.bodyNames.empty()) {
    for (const auto& name : c.bodyNames) {
      v.nameLength = std::max(v.nameLength, name.size());
    }
    int strDim = -1;
    w.check(nc_def_dim(ncid, "name_strlen", v.nameLength, &strDim), "define the name_strlen dimension");
    v.names = define("body_name", NC_CHAR, {bodyDim, strDim}, nullptr, "body name (for reading; not used on restart)");
  }
  v.first = define("contact_first", NC_UINT, {contactDim}, "1", "friction spring: index of the first body");
  v.second = define("contact_second", NC_UINT, {contactDim}, "1", "friction spring: the other side");
  w.text(ncid, v.second, "comment", kSecondComment);
  // levelset: the surface sample; fdem: contactor element << 16 | target element, or the surface
  // face index against static geometry.
  v.key = define("contact_key", NC_UINT, {contactDim}, "1", "friction spring: surface sample or element pair");
  w.text(ncid, v.key, "comment", kKeyComment);
  v.stretch = define("contact_stretch", NC_DOUBLE, {contactDim, vecDim}, "m",
                             "friction spring: tangential stretch, world frame");
  v.sliding =
      define("contact_sliding", NC_UBYTE, {contactDim}, "1", "friction spring: sliding (1) or stuck (0)");
  // The constraint solver's warm start (contact.solver: constraint); zero under the penalty solver.
  v.normalImpulse = define("contact_normal_impulse", NC_DOUBLE, {contactDim}, "N s",
                                   "constraint solver: normal impulse per substep (warm start)");
  v.tangentImpulse = define("contact_tangent_impulse", NC_DOUBLE, {contactDim, vecDim}, "N s",
                                    "constraint solver: friction impulse per substep, world frame (warm start)");
  // Optional texts: a char variable over its own length dimension, left out when empty.
  const auto defineText = [&](const char* name, const char* dimName, const std::string& text, const char* longName) {
    if (text.empty()) return -1;
    int dim = -1;
    w.check(nc_def_dim(ncid, dimName, text.size(), &dim), "define a dimension");
    return define(name, NC_CHAR, {dim}, nullptr, longName);
  };
  v.identity = defineText("scene_identity", "identity_length", c.sceneIdentity,
                                  "the resolved scene that scene_fingerprint hashes (duration and output settings "
                                  "left out)");
  v.application = defineText("application_state", "application_state_length", c.applicationState,
                                     "the command's own state around the World (armour place: placement progress; "
                                     "a placed state: the contact model its contacts belong to)");
  return v;
}

/// The values of a checkpoint's variables (data mode).
void putCheckpointVars(const Writer& w, int ncid, const CheckpointVars& v, const Checkpoint& c) {
  const WorldState& s = c.state;
  const std::size_t n = s.bodies.size();
  const std::size_t m = s.contacts.size();
  const auto put = [&](int var, const auto& values) {
    if (!values.empty()) {
      w.check(nc_put_var(ncid, var, values.data()), "write a variable");
    }
  };
  if (n > 0) {
    std::vector<double> buffer(4 * n);
    const auto putVec = [&](int var, Vec3 BodyState::*member) {
      buffer.resize(3 * n);
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3& v = s.bodies[i].*member;
        std::copy(v.data(), v.data() + 3, buffer.begin() + static_cast<std::ptrdiff_t>(3 * i));
      }
      put(var, buffer);
    };
    putVec(v.position, &BodyState::position);
    putVec(v.velocity, &BodyState::velocity);
    putVec(v.momentum, &BodyState::angularMomentum);
    putVec(v.force, &BodyState::force);
    putVec(v.torque, &BodyState::torque);
    putVec(v.externalForce, &BodyState::externalForce);
    putVec(v.externalTorque, &BodyState::externalTorque);
    putVec(v.sleepLoad, &BodyState::sleepLoad);
    buffer.resize(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& q = s.bodies[i].orientation;
      buffer[4 * i] = q.w();
      buffer[4 * i + 1] = q.x();
      buffer[4 * i + 2] = q.y();
      buffer[4 * i + 3] = q.z();
    }
    put(v.orientation, buffer);
    std::vector<unsigned char> motions(n);
    std::vector<double> rests(n), forces(n);
    std::vector<int> counts(n);
    for (std::size_t i = 0; i < n; ++i) {
      motions[i] = static_cast<unsigned char>(s.bodies[i].motion);
      rests[i] = s.bodies[i].restTime;
      counts[i] = s.bodies[i].contactCount;
      forces[i] = s.bodies[i].maxContactForce;
    }
    put(v.motion, motions);
    put(v.rest, rests);
    put(v.count, counts);
    put(v.maxForce, forces);
    if (v.names >= 0) {
      std::vector<char> text(n * v.nameLength, '\0');
      for (std::size_t i = 0; i < n; ++i) {
        std::copy(c.bodyNames[i].begin(), c.bodyNames[i].end(),
                  text.begin() + static_cast<std::ptrdiff_t>(i * v.nameLength));
      }
      put(v.names, text);
    }
  }
  if (v.cache >= 0) {
    put(v.cache, s.manifoldCache);
  }
  for (std::size_t k = 0; k < s.loadStages.size(); ++k) {
    std::vector<double> values = s.loadStages[k].second;
    values.resize(std::max<std::size_t>(1, values.size()), 0.0);
    put(v.stages[k], values);
  }
  if (m > 0) {
    std::vector<unsigned> firsts(m), seconds(m), keys(m);
    std::vector<double> stretches(3 * m);
    std::vector<unsigned char> slides(m);
    std::vector<double> normals(m), tangents(3 * m);
    for (std::size_t k = 0; k < m; ++k) {
      const ContactPointState& p = s.contacts[k];
      normals[k] = p.normalImpulse;
      std::copy(p.tangentImpulse.data(), p.tangentImpulse.data() + 3,
                tangents.begin() + static_cast<std::ptrdiff_t>(3 * k));
      firsts[k] = p.first;
      seconds[k] = p.second;
      keys[k] = p.key;
      std::copy(p.stretch.data(), p.stretch.data() + 3, stretches.begin() + static_cast<std::ptrdiff_t>(3 * k));
      slides[k] = p.sliding ? 1 : 0;
    }
    // The unlimited dimension (m = 0) is never written to, so nc_put_var's whole-variable
    // shape is the fixed length m here.
    put(v.first, firsts);
    put(v.second, seconds);
    put(v.key, keys);
    put(v.stretch, stretches);
    put(v.sliding, slides);
    put(v.normalImpulse, normals);
    put(v.tangentImpulse, tangents);
  }
  if (v.identity >= 0) {
    put(v.identity, c.sceneIdentity);
  }
  if (v.application >= 0) {
    put(v.application, c.applicationState);
  }
}

} // namespace

void writeCheckpoint(const fs::path& path, const Checkpoint& c) {
  const std::size_t n = c.state.bodies.size();
  if (!c.bodyNames.empty() && c.bodyNames.size() != n) {
    throw std::logic_error(fmt::format("writeCheckpoint: {} body names for {} bodies", c.bodyNames.size(), n));
  }
  const Writer w(path);
  const fs::path tmp = core::temporarySibling(path);
  int ncid = -1;
  try {
    w.check(nc_create(tmp.c_str(), NC_NETCDF4 | NC_CLOBBER, &ncid), "create the file");
    putCheckpointAttributes(w, ncid, c);
    const CheckpointVars vars = defineCheckpointVars(w, ncid, c);
    w.check(nc_enddef(ncid), "finish the header");
    putCheckpointVars(w, ncid, vars, c);
    const int status = nc_close(ncid);
    ncid = -1;
    w.check(status, "finish");
    core::commitAtomicFile(tmp, path);
  } catch (...) {
    if (ncid >= 0) {
      nc_close(ncid);
    }
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

// ---------------------------------------------------------------------------------------------
// Read
// ---------------------------------------------------------------------------------------------

namespace {

/// The global attributes: format version, build, fingerprint, stop reason, time, steps, the energy
/// monitor and the output schedule, refused when not finite.
void readCheckpointGlobals(const Reader& r, Checkpoint& c) {
  if (!r.hasAttribute(kVersionAttribute)) {
    r.fail("is a netCDF file but not an armour checkpoint (no global attribute '{}'); give the checkpoint.nc that "
           "armour run wrote into the run's output folder",
           kVersionAttribute);
  }
  c.formatVersion = r.scalar<int>(kVersionAttribute, NC_INT);
  c.build = r.hasAttribute("armour_build") ? r.text(NC_GLOBAL, "armour_build") : std::string("an unknown armour");
  if (c.formatVersion != kCheckpointFormatVersion) {
    r.fail("{} = {}: this armour reads checkpoint version {} only (the file was written by {}); restart with the "
           "armour that wrote it, or start the run anew without --restart",
           kVersionAttribute, c.formatVersion, kCheckpointFormatVersion, c.build);
  }
  c.sceneFingerprint = r.text(NC_GLOBAL, "scene_fingerprint");
  if (r.hasAttribute("stop_reason")) {
    c.stopReason = r.text(NC_GLOBAL, "stop_reason");
  }

  WorldState& s = c.state;
  s.time = r.scalar<double>("time", NC_DOUBLE);
  s.steps = r.scalar<unsigned long long>("steps", NC_UINT64);
  s.forcesReady = r.scalar<int>("forces_ready", NC_INT) != 0;
  s.energyMinimum = r.scalar<double>("energy_minimum", NC_DOUBLE);
  s.externalWork = r.scalar<double>("external_work", NC_DOUBLE);
  s.energyPeak = r.scalar<double>("energy_peak", NC_DOUBLE);
  s.energyStarted = r.scalar<int>("energy_started", NC_INT) != 0;
  c.outputs.lastVtkTime = r.scalar<double>("last_vtk_time", NC_DOUBLE);
  c.outputs.lastSeriesTime = r.scalar<double>("last_series_time", NC_DOUBLE);
  for (const auto& [name, value] : {std::pair<const char*, double>{"time", s.time},
                                    {"energy_minimum", s.energyMinimum},
                                    {"external_work", s.externalWork},
                                    {"energy_peak", s.energyPeak},
                                    {"last_vtk_time", c.outputs.lastVtkTime},
                                    {"last_series_time", c.outputs.lastSeriesTime}}) {
    if (!std::isfinite(value)) {
      r.fail("global attribute '{}' = {} is not finite: the checkpoint holds a state that had blown up (e.g. "
             "checkpoint_at_error.nc); restart from an earlier checkpoint.nc or start the run anew",
             name, value);
    }
  }

}

/// Each load stage's own state and the constraint solver's reused manifolds (both optional).
void readLoadStages(const Reader& r, WorldState& s) {
  int unused = -1;
  for (std::size_t k = 0;; ++k) {
    const std::string varName = fmt::format("load_stage_{}", k);
    if (nc_inq_varid(r.id(), varName.c_str(), &unused) != NC_NOERR) {
      break;
    }
    int dim = -1;
    const std::size_t length = r.dimension(fmt::format("load_stage_{}_length", k).c_str(), dim);
    std::vector<double> values;
    const int var = r.variable(varName.c_str(), NC_DOUBLE, {dim});
    r.get(varName.c_str(), var, length, values);
    std::size_t nameLength = 0;
    unsigned long long used = 0;
    if (nc_inq_attlen(r.id(), var, "stage_name", &nameLength) != NC_NOERR ||
        nc_get_att_ulonglong(r.id(), var, "used_length", &used) != NC_NOERR || used > length) {
      r.damaged(fmt::format("variable '{}'", varName), "lacks a valid stage_name or used_length attribute");
    }
    std::string name(nameLength, '\0');
    nc_get_att_text(r.id(), var, "stage_name", name.data());
    values.resize(used);
    s.loadStages.emplace_back(name, std::move(values));
  }
  if (nc_inq_varid(r.id(), "manifold_cache", &unused) == NC_NOERR) {
    int dim = -1;
    const std::size_t length = r.dimension("manifold_cache_length", dim);
    r.get("manifold_cache", r.variable("manifold_cache", NC_DOUBLE, {dim}), length, s.manifoldCache);
  }
}

/// The bodies' state and names (dims: body, vec, quat), refused when not finite or not a rotation.
void readCheckpointBodies(const Reader& r, Checkpoint& c, const std::array<int, 3>& dims, std::size_t n) {
  const auto [bodyDim, vecDim, quatDim] = dims;
  WorldState& s = c.state;
  int unused = -1;
  std::vector<double> positions, orientations, velocities, momenta, forces, torques, rests, maxForces;
  std::vector<unsigned char> motions;
  std::vector<int> counts;
  r.get("position", r.variable("position", NC_DOUBLE, {bodyDim, vecDim}), 3 * n, positions);
  r.get("orientation", r.variable("orientation", NC_DOUBLE, {bodyDim, quatDim}), 4 * n, orientations);
  r.get("velocity", r.variable("velocity", NC_DOUBLE, {bodyDim, vecDim}), 3 * n, velocities);
  r.get("angular_momentum", r.variable("angular_momentum", NC_DOUBLE, {bodyDim, vecDim}), 3 * n, momenta);
  r.get("force", r.variable("force", NC_DOUBLE, {bodyDim, vecDim}), 3 * n, forces);
  r.get("torque", r.variable("torque", NC_DOUBLE, {bodyDim, vecDim}), 3 * n, torques);
  r.get("motion_type", r.variable("motion_type", NC_UBYTE, {bodyDim}), n, motions);
  r.get("rest_time", r.variable("rest_time", NC_DOUBLE, {bodyDim}), n, rests);
  r.get("contact_count", r.variable("contact_count", NC_INT, {bodyDim}), n, counts);
  r.get("max_contact_force", r.variable("max_contact_force", NC_DOUBLE, {bodyDim}), n, maxForces);
  // Load-stage data: absent in checkpoints of runs without load stages (zero then).
  std::vector<double> externalForces(3 * n, 0.0), externalTorques(3 * n, 0.0), sleepLoads(3 * n, 0.0);
  if (nc_inq_varid(r.id(), "external_force", &unused) == NC_NOERR) {
    r.get("external_force", r.variable("external_force", NC_DOUBLE, {bodyDim, vecDim}), 3 * n, externalForces);
    r.get("external_torque", r.variable("external_torque", NC_DOUBLE, {bodyDim, vecDim}), 3 * n, externalTorques);
    r.get("sleep_load", r.variable("sleep_load", NC_DOUBLE, {bodyDim, vecDim}), 3 * n, sleepLoads);
  }
  if (nc_inq_varid(r.id(), "body_name", &unused) == NC_NOERR) {
    int strDim = -1;
    const std::size_t length = r.dimension("name_strlen", strDim);
    std::vector<char> text;
    r.get("body_name", r.variable("body_name", NC_CHAR, {bodyDim, strDim}), n * length, text);
    for (std::size_t i = 0; i < n; ++i) {
      const char* start = text.data() + i * length;
      c.bodyNames.emplace_back(start, std::find(start, start + length, '\0'));
    }
  }

  const auto bodyName = [&](std::size_t i) {
    return i < c.bodyNames.size() && !c.bodyNames[i].empty() ? fmt::format("body '{}' (index {})", c.bodyNames[i], i)
                                                               : fmt::format("body #{}", i);
  };
  const auto requireFinite = [&](const char* variable, std::size_t i, bool finite) {
    if (!finite) {
      r.fail("variable '{}' of {} is not finite: the checkpoint holds a state that had blown up (e.g. "
             "checkpoint_at_error.nc); restart from an earlier checkpoint.nc or start the run anew",
             variable, bodyName(i));
    }
  };
  s.bodies.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    BodyState& b = s.bodies[i];
    if (motions[i] > static_cast<unsigned char>(dynamics::MotionType::Sleeping)) {
      r.damaged(fmt::format("variable 'motion_type' of {}", bodyName(i)),
                fmt::format("is {}, not 0 (static), 1 (dynamic) or 2 (sleeping)", motions[i]));
    }
    b.motion = static_cast<dynamics::MotionType>(motions[i]);
    b.position = vec3(positions, i);
    const double* q = &orientations[4 * i];
    b.orientation = Quat(q[0], q[1], q[2], q[3]); // (w, x, y, z)
    b.velocity = vec3(velocities, i);
    b.angularMomentum = vec3(momenta, i);
    b.force = vec3(forces, i);
    b.torque = vec3(torques, i);
    b.restTime = rests[i];
    b.contactCount = counts[i];
    b.maxContactForce = maxForces[i];
    b.externalForce = vec3(externalForces, i);
    b.externalTorque = vec3(externalTorques, i);
    b.sleepLoad = vec3(sleepLoads, i);
    requireFinite("position", i, b.position.allFinite());
    requireFinite("orientation", i, b.orientation.coeffs().allFinite());
    requireFinite("velocity", i, b.velocity.allFinite());
    requireFinite("angular_momentum", i, b.angularMomentum.allFinite());
    requireFinite("force", i, b.force.allFinite());
    requireFinite("torque", i, b.torque.allFinite());
    requireFinite("rest_time", i, std::isfinite(b.restTime));
    requireFinite("max_contact_force", i, std::isfinite(b.maxContactForce));
    // The integrator keeps quaternions unit to round-off; anything else was not written by it.
    if (std::abs(b.orientation.norm() - 1.0) > 1e-9) {
      r.damaged(fmt::format("variable 'orientation' of {}", bodyName(i)),
                fmt::format("has norm {}, not a rotation", b.orientation.norm()));
    }
  }

}

/// The friction springs and warm starts of the contacts (dims: contact, vec), each naming a body.
void readCheckpointContacts(const Reader& r, WorldState& s, const std::array<int, 2>& dims, std::size_t n,
                            std::size_t m) {
  const auto [contactDim, vecDim] = dims;
  std::vector<unsigned> firsts, seconds, keys;
  std::vector<double> stretches;
  std::vector<unsigned char> slides;
  r.get("contact_first", r.variable("contact_first", NC_UINT, {contactDim}), m, firsts);
  r.get("contact_second", r.variable("contact_second", NC_UINT, {contactDim}), m, seconds);
  r.get("contact_key", r.variable("contact_key", NC_UINT, {contactDim}), m, keys);
  r.get("contact_stretch", r.variable("contact_stretch", NC_DOUBLE, {contactDim, vecDim}), 3 * m, stretches);
  r.get("contact_sliding", r.variable("contact_sliding", NC_UBYTE, {contactDim}), m, slides);
  // Checkpoints written before the constraint solver have no impulses: zero (no warm start).
  std::vector<double> normalImpulses(m, 0.0), tangentImpulses(3 * m, 0.0);
  int unusedImpulse = -1;
  if (nc_inq_varid(r.id(), "contact_normal_impulse", &unusedImpulse) == NC_NOERR) {
    r.get("contact_normal_impulse", r.variable("contact_normal_impulse", NC_DOUBLE, {contactDim}), m, normalImpulses);
    r.get("contact_tangent_impulse", r.variable("contact_tangent_impulse", NC_DOUBLE, {contactDim, vecDim}), 3 * m,
          tangentImpulses);
  }
  s.contacts.resize(m);
  for (std::size_t k = 0; k < m; ++k) {
    ContactPointState& p = s.contacts[k];
    p.first = firsts[k];
    p.second = seconds[k];
    p.key = keys[k];
    p.stretch = vec3(stretches, k);
    p.sliding = slides[k] != 0;
    p.normalImpulse = normalImpulses[k];
    p.tangentImpulse = vec3(tangentImpulses, k);
    if (!p.stretch.allFinite() || !std::isfinite(p.normalImpulse) || !p.tangentImpulse.allFinite()) {
      r.fail("variable 'contact_stretch' or an impulse of contact {} (body {}) is not finite: the checkpoint holds a state that had "
             "blown up; restart from an earlier checkpoint.nc or start the run anew",
             k, p.first);
    }
    if (p.first >= n) {
      r.damaged(fmt::format("variable 'contact_first' of contact {}", k),
                fmt::format("names body {}, but there are {} bodies", p.first, n));
    }
  }
}

} // namespace

Checkpoint readCheckpoint(const fs::path& path, const CheckpointExpectation& expect) {
  // A damaged file can crash libhdf5 inside nc_open: read it whole in a child first (one fork per
  // restart; core/ProbeInChild.hpp). In the child this call reads it without a second probe.
  core::probeInChild(path.string(), {"checkpoint", "restart from another checkpoint, or start the run anew without "
                                                   "--restart"},
                     [&] { (void)readCheckpoint(path, expect); });
  const Reader r(path);
  Checkpoint c;
  readCheckpointGlobals(r, c);
  int bodyDim = -1, contactDim = -1, vecDim = -1, quatDim = -1;
  const std::size_t n = r.dimension("body", bodyDim);
  const std::size_t m = r.dimension("contact", contactDim);
  if (const std::size_t v = r.dimension("vec", vecDim); v != 3) {
    r.damaged("dimension 'vec'", fmt::format("is {}, expected 3", v));
  }
  if (const std::size_t q = r.dimension("quat", quatDim); q != 4) {
    r.damaged("dimension 'quat'", fmt::format("is {}, expected 4", q));
  }

  // The scene first: a changed scene explains any mismatch that follows.
  int unused = -1;
  // Optional texts: absent = "".
  const auto readText = [&](const char* name, const char* dimName) {
    std::string out;
    if (nc_inq_varid(r.id(), name, &unused) != NC_NOERR) return out;
    int dim = -1;
    const std::size_t length = r.dimension(dimName, dim);
    std::vector<char> text;
    r.get(name, r.variable(name, NC_CHAR, {dim}), length, text);
    out.assign(text.begin(), text.end());
    return out;
  };
  c.sceneIdentity = readText("scene_identity", "identity_length");
  c.applicationState = readText("application_state", "application_state_length");
  if (!expect.sceneFingerprint.empty() && expect.sceneFingerprint != c.sceneFingerprint) {
    std::string change = "(the checkpoint does not hold the scene text, so the change cannot be named)";
    if (!c.sceneIdentity.empty() && !expect.sceneIdentity.empty()) {
      const auto [was, is] = firstDifference(c.sceneIdentity, expect.sceneIdentity);
      change = fmt::format("first difference: the run had '{}', the scene now has '{}'", was, is);
    }
    r.fail("scene_fingerprint {} does not match the scene ({}): the scene changed since the run started; {}. A "
           "restart may change the duration and the output settings only: undo the change, or start a new run "
           "without --restart (into another output folder to keep this one)",
           c.sceneFingerprint, expect.sceneFingerprint, change);
  }
  if (expect.bodies > 0 && n != expect.bodies) {
    r.fail("dimension 'body' = {}: the checkpoint holds {} bodies but the scene builds {}; restart with the scene "
           "the run was started with, or start a new run without --restart",
           n, n, expect.bodies);
  }

  readCheckpointBodies(r, c, {bodyDim, vecDim, quatDim}, n);
  readLoadStages(r, c.state);
  readCheckpointContacts(r, c.state, {contactDim, vecDim}, n, m);
  return c;
}

} // namespace armour::simulation
