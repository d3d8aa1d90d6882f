// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/DeformableCheckpoint.hpp"
#include "core/Hash.hpp"
#include <fmt/format.h>
#include <sstream>

#include "core/AtomicFile.hpp"
#include "core/Error.hpp"

#include <cstring>
#include <fstream>

namespace armour::deformable {
namespace {

constexpr char kMagic[8] = {'A', 'R', 'M', 'D', 'E', 'F', '0', '1'};

template <typename T>
void put(std::ostream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <typename T>
T get(std::istream& in, const std::string& file, const char* what) {
  T value{};
  in.read(reinterpret_cast<char*>(&value), sizeof(T));
  if (!in) {
    core::failInput(file, "the file ends before {}: it is truncated; use an earlier checkpoint", what);
  }
  return value;
}

void putVectors(std::ostream& out, const std::vector<Vec3>& values) {
  out.write(reinterpret_cast<const char*>(values.data()), static_cast<std::streamsize>(values.size() * sizeof(Vec3)));
}

std::vector<Vec3> getVectors(std::istream& in, std::size_t count, const std::string& file, const char* what) {
  std::vector<Vec3> values(count);
  in.read(reinterpret_cast<char*>(values.data()), static_cast<std::streamsize>(count * sizeof(Vec3)));
  if (!in) {
    core::failInput(file, "the file ends inside the {}: it is truncated; use an earlier checkpoint", what);
  }
  for (std::size_t n = 0; n < count; ++n) {
    if (!values[n].allFinite()) {
      core::failInput(file, "{} of node {} is not finite: the checkpoint holds a failed state; use an earlier one",
                      what, n);
    }
  }
  return values;
}

/// The first line where two identity texts differ, as "'then' then, 'now' now".
std::string firstDifference(const std::string& then, const std::string& now) {
  std::istringstream a(then), b(now);
  std::string la, lb;
  while (true) {
    const bool ha = static_cast<bool>(std::getline(a, la));
    const bool hb = static_cast<bool>(std::getline(b, lb));
    if (!ha && !hb) return "";
    if (!ha) la = "(nothing)";
    if (!hb) lb = "(nothing)";
    if (la != lb) return fmt::format("'{}' then, '{}' now", la, lb);
  }
}

} // namespace

std::string setupIdentity(const DeformableBody& body) {
  const DeformableMesh& mesh = body.mesh();
  std::uint64_t h = core::fnv1a(std::string_view(reinterpret_cast<const char*>(mesh.nodes.data()),
                                                 mesh.nodes.size() * sizeof(Vec3)));
  h = core::fnv1a(std::string_view(reinterpret_cast<const char*>(mesh.connectivity.data()),
                                   mesh.connectivity.size() * sizeof(mesh.connectivity[0])),
                  h);
  const DeformableSettings& s = body.settings();
  std::string out = fmt::format("mesh = {} nodes, {} elements of {} nodes, fnv1a64 {:016x}\n", mesh.nodeCount(),
                                mesh.elementCount(), mesh.nodesPerElement(), h);
  out += fmt::format("material.density = {} kg/m^3\nmaterial.young_modulus = {} Pa\nmaterial.poisson_ratio = {}\n"
                     "material.viscosity = {} Pa s\n",
                     s.material.density, s.material.youngModulus, s.material.poissonRatio, s.material.viscosity);
  out += fmt::format("gravity = [{}, {}, {}] m/s^2\nf_bar = {}\nmass_damping = {} 1/s\nstep_safety = {}\n"
                     "mass_scaling = {}\n",
                     s.gravity.x(), s.gravity.y(), s.gravity.z(), s.fBar, s.massDamping, s.stepSafety, s.massScaling);
  for (std::size_t k = 0; k < s.halfSpaces.size(); ++k) {
    const auto& hs = s.halfSpaces[k];
    out += fmt::format("half_spaces[{}] = point [{}, {}, {}] m, normal [{}, {}, {}]\n", k, hs.point.x(), hs.point.y(),
                       hs.point.z(), hs.normal.x(), hs.normal.y(), hs.normal.z());
  }
  out += fmt::format("contact.gradient = {} Pa/m\ncontact.friction = {}\ncontact.friction_stiffness_ratio = {}\n"
                     "contact.rigid = {}\ncontact.bodies = {}\ncontact.penalty = {} Pa\ncontact.damping = {}\n",
                     s.contactGradient, s.friction, s.frictionStiffnessRatio, s.rigidContact, s.bodyContact,
                     s.contactPenalty, s.contactDamping);
  if (s.bodyFriction > 0.0) out += fmt::format("contact.body_friction = {}\n", s.bodyFriction); // absent: the text of older files
  // The rigid bodies (a restart among others is another setup): pose (of a fixed one), scale,
  // level-set grid.
  for (std::size_t k = 0; k < body.obstacles().size(); ++k) {
    const RigidObstacle& o = body.obstacles()[k];
    const auto& q = o.orientation;
    out += o.moving ? fmt::format("rigid[{}] = moving, scale {}", k, o.scale)
                    : fmt::format("rigid[{}] = position [{}, {}, {}] m, orientation [{}, {}, {}, {}], scale {}", k,
                                  o.position.x(), o.position.y(), o.position.z(), q.w(), q.x(), q.y(), q.z(), o.scale);
    if (o.levelSet != nullptr)
      out += fmt::format(", level set cell {} m from [{}, {}, {}]", o.levelSet->cellSize(), o.levelSet->origin().x(),
                         o.levelSet->origin().y(), o.levelSet->origin().z());
    out += '\n';
  }
  return out;
}

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles for the binary layout");

void writeDeformableCheckpoint(const DeformableBody& body, const std::filesystem::path& path) {
  const auto& s = body.state();
  core::writeFileAtomically(
      path,
      [&](std::ostream& out) {
        out.write(kMagic, sizeof(kMagic));
        put(out, kDeformableCheckpointVersion);
        put(out, static_cast<std::uint32_t>(body.mesh().nodesPerElement()));
        put(out, static_cast<std::uint64_t>(body.nodeCount()));
        put(out, static_cast<std::uint64_t>(body.mesh().elementCount()));
        put(out, s.steps);
        put(out, s.time);
        put(out, static_cast<std::uint8_t>(s.accelerationsReady ? 1 : 0));
        putVectors(out, s.positions);
        putVectors(out, s.velocities);
        putVectors(out, s.accelerations);
        // Version 2: the friction anchors (HalfSpaceFriction.hpp), count 0 without friction.
        put(out, static_cast<std::uint64_t>(s.frictionAnchors.size()));
        putVectors(out, s.frictionAnchors);
        out.write(reinterpret_cast<const char*>(s.frictionActive.data()),
                  static_cast<std::streamsize>(s.frictionActive.size()));
        // Version 3: the setup it belongs to (setupIdentity), so that a restart with another is refused.
        const std::string identity = setupIdentity(body);
        put(out, static_cast<std::uint64_t>(identity.size()));
        out.write(identity.data(), static_cast<std::streamsize>(identity.size()));
        // Version 4: the body friction anchors (BodyFriction.hpp), count 0 without body friction.
        put(out, static_cast<std::uint64_t>(s.bodyFrictionTets.size()));
        out.write(reinterpret_cast<const char*>(s.bodyFrictionTets.data()),
                  static_cast<std::streamsize>(s.bodyFrictionTets.size() * sizeof(std::int32_t)));
        out.write(reinterpret_cast<const char*>(s.bodyFrictionWeights.data()),
                  static_cast<std::streamsize>(s.bodyFrictionWeights.size() * sizeof(std::array<double, 4>)));
      },
      true);
}

void readDeformableCheckpoint(const std::filesystem::path& path, DeformableBody& body) {
  const std::string file = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    core::failInput(file, "cannot open the checkpoint; check the path");
  }
  char magic[8] = {};
  in.read(magic, sizeof(magic));
  if (!in || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0) {
    core::failInput(file, "not a deformable-body checkpoint (no ARMDEF01 header); give the file the run wrote");
  }
  const auto version = get<std::uint32_t>(in, file, "the version");
  if (version < 1 || version > kDeformableCheckpointVersion) {
    core::failInput(file, "format version {}, this build reads 1 to {}; restart with the armour build that wrote it",
                    version, kDeformableCheckpointVersion);
  }
  const auto nen = get<std::uint32_t>(in, file, "the element order");
  const auto nodes = get<std::uint64_t>(in, file, "the node count");
  const auto elements = get<std::uint64_t>(in, file, "the element count");
  if (nen != static_cast<std::uint32_t>(body.mesh().nodesPerElement()) || nodes != body.nodeCount() ||
      elements != body.mesh().elementCount()) {
    core::failInput(file,
                    "written for {} nodes, {} elements of {} nodes; this body has {}, {} of {}: restart with the mesh "
                    "and element order of the run that wrote it",
                    nodes, elements, nen, body.nodeCount(), body.mesh().elementCount(), body.mesh().nodesPerElement());
  }
  DeformableState state;
  state.steps = get<std::uint64_t>(in, file, "the step count");
  state.time = get<double>(in, file, "the time");
  state.accelerationsReady = get<std::uint8_t>(in, file, "the flags") != 0;
  state.positions = getVectors(in, nodes, file, "positions");
  state.velocities = getVectors(in, nodes, file, "velocities");
  state.accelerations = getVectors(in, nodes, file, "accelerations");
  if (version >= 2) {
    const auto anchors = get<std::uint64_t>(in, file, "the friction anchor count");
    if (anchors != body.state().frictionAnchors.size()) {
      core::failInput(file, "holds {} friction anchors, this body {}: it was written with other friction settings "
                            "(friction, half-spaces); restart with those", anchors, body.state().frictionAnchors.size());
    }
    state.frictionAnchors = getVectors(in, anchors, file, "friction anchors");
    state.frictionActive.resize(anchors);
    in.read(reinterpret_cast<char*>(state.frictionActive.data()), static_cast<std::streamsize>(anchors));
    if (!in) {
      core::failInput(file, "the file ends inside the friction flags: it is truncated; use an earlier checkpoint");
    }
  }
  if (version >= 3) {
    const auto length = get<std::uint64_t>(in, file, "the setup's length");
    if (length > (std::uint64_t{1} << 24)) {
      core::failInput(file, "the setup text claims {} bytes: the file is damaged; use an earlier checkpoint", length);
    }
    std::string identity(length, '\0');
    in.read(identity.data(), static_cast<std::streamsize>(length));
    if (!in) {
      core::failInput(file, "the file ends inside the setup text: it is truncated; use an earlier checkpoint");
    }
    const std::string now = setupIdentity(body);
    if (identity != now) {
      core::failInput(file, "was written for another setup: {}. Restart with the scene that wrote it, or run again "
                            "without --restart",
                      firstDifference(identity, now));
    }
  }
  if (version >= 4) {
    const auto anchors = get<std::uint64_t>(in, file, "the body friction anchor count");
    if (anchors != body.state().bodyFrictionTets.size()) {
      core::failInput(file, "holds {} body friction anchors, this body {}: it was written with another "
                            "contact.body_friction; restart with that", anchors, body.state().bodyFrictionTets.size());
    }
    state.bodyFrictionTets.resize(anchors);
    state.bodyFrictionWeights.resize(anchors);
    in.read(reinterpret_cast<char*>(state.bodyFrictionTets.data()),
            static_cast<std::streamsize>(anchors * sizeof(std::int32_t)));
    in.read(reinterpret_cast<char*>(state.bodyFrictionWeights.data()),
            static_cast<std::streamsize>(anchors * sizeof(std::array<double, 4>)));
    if (!in) {
      core::failInput(file, "the file ends inside the body friction anchors: it is truncated; use an earlier checkpoint");
    }
  } else {
    state.bodyFrictionTets = body.state().bodyFrictionTets; // older files: no body friction (the size check above)
    state.bodyFrictionWeights = body.state().bodyFrictionWeights;
  }
  body.restore(state, file);
}

} // namespace armour::deformable
