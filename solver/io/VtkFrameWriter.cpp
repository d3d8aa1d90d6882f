// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/VtkFrameWriter.hpp"

#include "core/AtomicFile.hpp"
#include "core/Error.hpp"
#include "core/Log.hpp"
#include "geometry/VtkSupport.hpp"

#include <fmt/format.h>

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

#include <charconv>
#include <map>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace armour::io {
namespace {

constexpr const char* kBodies = "bodies";
constexpr const char* kContacts = "contacts";

std::string frameName(std::size_t index) { return fmt::format("frame_{:06d}.vtp", index); }

/// Index of "frame_000012.vtp" (or of its temporary sibling "frame_000012.vtp.tmp.<pid>"), or -1.
long frameIndex(const std::string& fileName) {
  static const std::regex pattern(R"(frame_(\d+)\.vtp(\.tmp\.\d+)?)");
  std::smatch m;
  if (!std::regex_match(fileName, m, pattern)) {
    return -1;
  }
  return std::stol(m[1].str());
}

/// Delete frame files numbered `from` or later in `folder` (left-over temporaries too).
void removeFramesFrom(const std::filesystem::path& folder, long from) {
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) {
    return;
  }
  std::size_t removed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const auto name = entry.path().filename().string();
    const long index = frameIndex(name);
    const bool temporary = name.find(".tmp.") != std::string::npos;
    if (index >= 0 && (index >= from || temporary)) {
      std::error_code ignored;
      removed += std::filesystem::remove(entry.path(), ignored) ? 1 : 0;
    }
  }
  if (removed > 0) {
    core::logger("io")->info("{}: removed {} frame files of an earlier run", folder.string(), removed);
  }
}

vtkSmartPointer<vtkDoubleArray> doubleArray(const char* name, int components, vtkIdType tuples) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

vtkSmartPointer<vtkIntArray> intArray(const char* name, vtkIdType tuples) {
  auto a = vtkSmartPointer<vtkIntArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(1);
  a->SetNumberOfTuples(tuples);
  return a;
}

void put3(double* to, const geometry::Vec3& v) {
  to[0] = v.x();
  to[1] = v.y();
  to[2] = v.z();
}

/// The bodies' surfaces in the world with body_id, and with `motion` the motion arrays
/// (displacements from `reference`, which must hold every body then). `vertices`: staging, reused.
vtkSmartPointer<vtkPolyData> surfaces(const std::vector<const BodySnapshot*>& bodies, bool motion,
                                      const std::map<std::int32_t, geometry::Vec3>& reference,
                                      std::vector<geometry::Vec3>& vertices) {
  std::size_t vertexCount = 0, triangleCount = 0;
  for (const BodySnapshot* b : bodies) {
    vertexCount += b->surface->vertexCount();
    triangleCount += b->surface->triangleCount();
  }
  // Geometry: every body's surface moved to the world, p = x + R (s p_body).
  vertices.clear();
  vertices.reserve(vertexCount);
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(static_cast<vtkIdType>(triangleCount + 1));
  connectivity->SetNumberOfTuples(static_cast<vtkIdType>(3 * triangleCount));
  vtkIdType* offset = offsets->GetPointer(0);
  vtkIdType* corner = connectivity->GetPointer(0);
  const auto nv = static_cast<vtkIdType>(vertexCount);
  auto bodyId = intArray("body_id", nv);
  // The motion arrays (not for fixed bodies, whose file is written once).
  const vtkIdType nm = motion ? nv : 0;
  auto velocity = doubleArray("velocity", 3, nm);
  auto speed = doubleArray("speed", 1, nm);
  auto angular = doubleArray("angular_velocity", 3, nm);
  auto contactCount = intArray("contact_count", nm);
  auto maxForce = doubleArray("max_contact_force", 1, nm);
  auto displacement = doubleArray("displacement", 3, nm);
  auto hydroForce = doubleArray("hydro_force", 3, nm);
  vtkIdType triangle = 0;
  *offset++ = 0;
  for (const BodySnapshot* b : bodies) {
    const auto first = static_cast<vtkIdType>(vertices.size());
    const geometry::Mat3 rotation = b->orientation.toRotationMatrix();
    for (const auto& p : b->surface->vertices) {
      vertices.push_back(b->position + rotation * (b->scale * p));
    }
    for (const auto& t : b->surface->triangles) {
      for (const auto c : t) {
        *corner++ = first + c;
      }
      *offset++ = 3 * ++triangle;
    }
    // Point data: per-body values repeated on its vertices. Point rather than cell data because
    // a closed surface has about twice as many triangles as vertices; zlib absorbs the repeats.
    for (auto i = first; i < static_cast<vtkIdType>(vertices.size()); ++i) {
      bodyId->SetValue(i, b->id);
    }
    if (!motion) continue;
    const geometry::Vec3 moved = b->position - reference.at(b->id);
    const double bodySpeed = b->velocity.norm();
    for (auto i = first; i < static_cast<vtkIdType>(vertices.size()); ++i) {
      put3(velocity->GetPointer(3 * i), b->velocity);
      speed->SetValue(i, bodySpeed);
      put3(angular->GetPointer(3 * i), b->angularVelocity);
      contactCount->SetValue(i, b->contactCount);
      maxForce->SetValue(i, b->maxContactForce);
      put3(displacement->GetPointer(3 * i), moved);
      put3(hydroForce->GetPointer(3 * i), b->externalForce);
    }
  }
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(geometry::toVtkPoints(vertices));
  data->SetPolys(polys);
  data->GetPointData()->AddArray(bodyId);
  if (motion) {
    for (vtkDataArray* a : std::initializer_list<vtkDataArray*>{velocity, speed, angular, contactCount, maxForce,
                                                               displacement, hydroForce}) {
      data->GetPointData()->AddArray(a);
    }
  }
  return data;
}

} // namespace

void writeCollection(const std::filesystem::path& pvd, const std::vector<CollectionEntry>& entries) {
  core::writeFileAtomically(pvd, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
           "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
           "  <Collection>\n";
    for (const auto& e : entries) {
      // "{}" is the shortest text that reads back to the same double, so resume compares exactly.
      out << fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", e.time, e.file);
    }
    out << "  </Collection>\n"
           "</VTKFile>\n";
  });
}

std::vector<CollectionEntry> readCollection(const std::filesystem::path& pvd) {
  std::ifstream in(pvd);
  if (!in) {
    core::failInput(pvd.string(), "cannot open the collection file; check the path");
  }
  std::ostringstream text;
  text << in.rdbuf();
  const std::string xml = text.str();
  if (xml.find("type=\"Collection\"") == std::string::npos) {
    core::failInput(pvd.string(), "not a VTK collection file (no type=\"Collection\"); move it away or start a new run");
  }
  static const std::regex dataSet(R"(<DataSet\b([^>]*)>)");
  static const std::regex timestep(R"(\btimestep\s*=\s*"([^"]*)\")");
  static const std::regex file(R"(\bfile\s*=\s*"([^"]*)\")");
  std::vector<CollectionEntry> entries;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), dataSet); it != std::sregex_iterator(); ++it) {
    const std::string attributes = (*it)[1].str();
    std::smatch t, f;
    if (!std::regex_search(attributes, t, timestep) || !std::regex_search(attributes, f, file)) {
      core::failInput(pvd.string(), "DataSet {} lacks a timestep or file attribute; the collection is damaged",
                      entries.size());
    }
    CollectionEntry e;
    const std::string value = t[1].str();
    const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), e.time);
    if (ec != std::errc() || end != value.data() + value.size()) {
      core::failInput(pvd.string(), "DataSet {}: timestep \"{}\" is not a number; the collection is damaged",
                      entries.size(), value);
    }
    e.file = f[1].str();
    entries.push_back(std::move(e));
  }
  return entries;
}

VtkFrameWriter::VtkFrameWriter(VtkFrameSettings settings) : settings_(std::move(settings)) {
  std::vector<const char*> folders{kBodies};
  if (settings_.contacts) {
    folders.push_back(kContacts);
  }
  for (const char* sub : folders) {
    std::error_code ec;
    std::filesystem::create_directories(settings_.folder / sub, ec);
    if (ec) {
      core::failInput(settings_.folder.string(), "cannot create the output folder '{}' ({}); choose a writable folder",
                      (settings_.folder / sub).string(), ec.message());
    }
  }
  if (settings_.resumeTime && std::filesystem::exists(collectionPath())) {
    resume(*settings_.resumeTime);
    return;
  }
  if (settings_.resumeTime) {
    core::logger("io")->warn("{}: no collection to resume; starting a new one at t = {} s", collectionPath().string(),
                             *settings_.resumeTime);
  }
  // A fresh run: an earlier run's collections would name files that are about to be replaced.
  std::error_code ignored;
  std::filesystem::remove(collectionPath(), ignored);
  std::filesystem::remove(fixedPath(), ignored);
  std::filesystem::remove(contactCollectionPath(), ignored);
  removeFramesFrom(settings_.folder / kBodies, 0);
  removeFramesFrom(settings_.folder / kContacts, 0);
}

void VtkFrameWriter::resume(double time) {
  const auto keepUpTo = [time](std::vector<CollectionEntry> all) {
    std::size_t keep = 0;
    while (keep < all.size() && all[keep].time <= time && (keep == 0 || all[keep].time > all[keep - 1].time)) {
      ++keep;
    }
    all.resize(keep);
    return all;
  };
  const auto all = readCollection(collectionPath());
  entries_ = keepUpTo(all);
  nextIndex_ = entries_.size();
  if (!entries_.empty()) {
    const long last = frameIndex(std::filesystem::path(entries_.back().file).filename().string());
    if (last >= 0) {
      nextIndex_ = static_cast<std::size_t>(last) + 1;
    }
  }
  if (settings_.contacts && std::filesystem::exists(contactCollectionPath())) {
    contactEntries_ = keepUpTo(readCollection(contactCollectionPath()));
  }
  // Collections first, then the files they no longer name: the folder stays consistent throughout.
  writeCollection(collectionPath(), entries_);
  if (settings_.contacts) {
    writeCollection(contactCollectionPath(), contactEntries_);
  } else {
    std::error_code ignored;
    std::filesystem::remove(contactCollectionPath(), ignored);
  }
  removeFramesFrom(settings_.folder / kBodies, static_cast<long>(nextIndex_));
  removeFramesFrom(settings_.folder / kContacts, settings_.contacts ? static_cast<long>(nextIndex_) : 0);
  core::logger("io")->info("{}: resuming at t = {} s: keeping {} of {} frames", collectionPath().string(), time,
                           entries_.size(), all.size());

  // The displacement reference travels in every frame's field data; take it from the last kept one.
  if (entries_.empty()) {
    return;
  }
  const auto last = settings_.folder / entries_.back().file;
  geometry::VtkMessageCapture messages;
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(last.c_str());
  reader->Update();
  vtkPolyData* data = reader->GetOutput();
  if (!messages.text().empty() || data == nullptr) {
    core::failInput(last.string(), "cannot read the last kept frame to resume from it; VTK said: {}", messages.text());
  }
  vtkDataArray* ids = data->GetFieldData()->GetArray("reference_body_id");
  vtkDataArray* positions = data->GetFieldData()->GetArray("reference_position");
  if (ids == nullptr || positions == nullptr || positions->GetNumberOfComponents() != 3 ||
      positions->GetNumberOfTuples() != ids->GetNumberOfTuples()) {
    core::logger("io")->warn("{}: no displacement reference in the frame; displacements will be measured from the "
                             "first position written after the restart",
                             last.string());
    return;
  }
  for (vtkIdType i = 0; i < ids->GetNumberOfTuples(); ++i) {
    const double* p = positions->GetTuple3(i);
    reference_[static_cast<std::int32_t>(ids->GetTuple1(i))] = geometry::Vec3(p[0], p[1], p[2]);
  }
}

void VtkFrameWriter::setReferencePosition(std::int32_t id, const geometry::Vec3& position) {
  reference_[id] = position;
}

void VtkFrameWriter::writeFixed(const std::vector<const BodySnapshot*>& fixed) {
  std::vector<std::int32_t> ids;
  for (const BodySnapshot* b : fixed) ids.push_back(b->id);
  if (fixedWritten_ && ids == fixedIds_) {
    return;
  }
  const auto path = fixedPath();
  if (fixed.empty()) {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
  } else {
    vtkSmartPointer<vtkPolyData> data = surfaces(fixed, false, reference_, vertices_);
    vtkNew<vtkXMLPolyDataWriter> writer;
    geometry::writeVtkXmlAtomically(*writer, data, path);
  }
  fixedIds_ = std::move(ids);
  fixedWritten_ = true;
}

void VtkFrameWriter::write(const BodyFrame& frame, std::span<const ContactPoint> contacts) {
  if (!entries_.empty() && !(frame.time > entries_.back().time)) {
    throw std::logic_error(
        fmt::format("VtkFrameWriter::write: time {} s does not follow {} s", frame.time, entries_.back().time));
  }
  // The displacement reference (kept in every frame's field data) holds the moving bodies only.
  std::vector<const BodySnapshot*> moving, fixed;
  for (const auto& b : frame.bodies) {
    if (!b.fixed) reference_.try_emplace(b.id, b.position);
    if (b.surface != nullptr) (b.fixed ? fixed : moving).push_back(&b);
  }
  // Fixed bodies (an underlayer's thousands of rocks) go once into their own file, not into every
  // frame: it is rewritten only if the set of fixed bodies changes.
  writeFixed(fixed);
  vtkSmartPointer<vtkPolyData> data = surfaces(moving, true, reference_, vertices_);

  // Field data: the time (ParaView shows "TimeValue" when one file is opened on its own) and the
  // displacement reference of every body seen so far, so that a resumed run measures from t = 0.
  auto timeValue = doubleArray("TimeValue", 1, 1);
  timeValue->SetValue(0, frame.time);
  const auto nr = static_cast<vtkIdType>(reference_.size());
  auto referenceId = intArray("reference_body_id", nr);
  auto referencePosition = doubleArray("reference_position", 3, nr);
  vtkIdType r = 0;
  for (const auto& [id, position] : reference_) {
    referenceId->SetValue(r, id);
    put3(referencePosition->GetPointer(3 * r), position);
    ++r;
  }
  data->GetFieldData()->AddArray(timeValue);
  data->GetFieldData()->AddArray(referenceId);
  data->GetFieldData()->AddArray(referencePosition);

  const std::string name = frameName(nextIndex_);
  {
    vtkNew<vtkXMLPolyDataWriter> writer;
    geometry::writeVtkXmlAtomically(*writer, data, settings_.folder / kBodies / name);
  }

  if (settings_.contacts) {
    const auto nc = static_cast<vtkIdType>(contacts.size());
    std::vector<geometry::Vec3> points;
    points.reserve(contacts.size());
    vtkNew<vtkIdTypeArray> vertexOffsets, vertexIds;
    vertexOffsets->SetNumberOfTuples(nc + 1);
    vertexIds->SetNumberOfTuples(nc);
    auto force = doubleArray("force", 3, nc);
    auto normalForce = doubleArray("normal_force", 1, nc);
    auto forceMagnitude = doubleArray("force_magnitude", 1, nc);
    auto bodyA = intArray("body_a", nc);
    auto bodyB = intArray("body_b", nc);
    vertexOffsets->SetValue(0, 0);
    for (vtkIdType i = 0; i < nc; ++i) {
      const auto& c = contacts[static_cast<std::size_t>(i)];
      points.push_back(c.position);
      vertexIds->SetValue(i, i);
      vertexOffsets->SetValue(i + 1, i + 1);
      put3(force->GetPointer(3 * i), c.force);
      normalForce->SetValue(i, c.normalForce);
      forceMagnitude->SetValue(i, c.force.norm());
      bodyA->SetValue(i, c.bodyA);
      bodyB->SetValue(i, c.bodyB);
    }
    // One vertex cell per point: without cells ParaView draws nothing.
    vtkNew<vtkCellArray> verts;
    verts->SetData(vertexOffsets, vertexIds);
    vtkNew<vtkPolyData> contactData;
    contactData->SetPoints(geometry::toVtkPoints(points));
    contactData->SetVerts(verts);
    for (vtkDataArray* a : std::initializer_list<vtkDataArray*>{force, normalForce, forceMagnitude, bodyA, bodyB}) {
      contactData->GetPointData()->AddArray(a);
    }
    contactData->GetPointData()->SetActiveVectors("force");
    auto contactTime = doubleArray("TimeValue", 1, 1);
    contactTime->SetValue(0, frame.time);
    contactData->GetFieldData()->AddArray(contactTime);
    vtkNew<vtkXMLPolyDataWriter> writer;
    geometry::writeVtkXmlAtomically(*writer, contactData, settings_.folder / kContacts / name);
  }

  // Collections last, each after the file it adds, so they never name a file that is not there.
  // On failure the lists drop the entry again, so the writer's state matches the files on disk.
  const auto append = [&](std::vector<CollectionEntry>& list, const char* sub, const std::filesystem::path& pvd) {
    list.push_back({frame.time, std::string(sub) + "/" + name});
    try {
      writeCollection(pvd, list);
    } catch (...) {
      list.pop_back();
      throw;
    }
  };
  append(entries_, kBodies, collectionPath());
  if (settings_.contacts) {
    append(contactEntries_, kContacts, contactCollectionPath());
  }
  ++nextIndex_;
}

} // namespace armour::io
