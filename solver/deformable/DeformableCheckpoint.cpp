// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/DeformableCheckpoint.hpp"

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

} // namespace

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
  if (version != 1 && version != kDeformableCheckpointVersion) {
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
  body.restore(state, file);
}

} // namespace armour::deformable
