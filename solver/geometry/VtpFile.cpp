// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/VtpFile.hpp"

#include "core/Error.hpp"
#include "core/ProbeInChild.hpp"
#include "geometry/VtkSupport.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

#include <exception>
#include <stdexcept>
#include <fstream>
#include <string>

namespace armour::geometry {
namespace {

/// VTK 9.1 believes NumberOfComponents: a corrupt one (e.g. "2147483647") makes vtkXMLReader
/// spin for minutes naming components, a negative one throws. A surface mesh's arrays have 1 to
/// 9 components, so refuse others before VTK sees them (found by tests/fuzz).
void checkComponentCounts(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string text(64 * 1024, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  text = text.substr(0, text.find("<AppendedData")); // the XML part only
  const std::string key = "NumberOfComponents=\"";
  for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + 1)) {
    const std::size_t begin = at + key.size();
    const std::string value = text.substr(begin, text.find('"', begin) - begin);
    if (value.size() != 1 || value[0] < '1' || value[0] > '9') {
      core::failInput(path.string(), "NumberOfComponents=\"{}\": expected 1 to 9 (3 for points); the file is "
                      "corrupt, re-export it from ParaView", value.substr(0, 40));
    }
  }
}

} // namespace

TriangleMesh readVtp(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) {
    core::failInput(path.string(), "cannot open the mesh file; check the path");
  }
  checkComponentCounts(path);
  // VTK 9.1 crashes (SIGSEGV in vtkXMLDataParser::ReadBlock) on damaged compressed appended data,
  // or allocates tens of GB for a corrupt size (tests/fuzz/upstream): read it in a child first.
  // 30 s is mine: a unit's mesh file reads in well under a second.
  core::probeInChild(path.string(),
                     {"mesh file", "re-export it from ParaView or `armour shape export`", "VTK",
                      "open it in ParaView, or check its XML header with `head -c 2000`"},
                     [&] {
                       VtkMessageCapture quiet;
                       vtkNew<vtkXMLPolyDataReader> probe;
                       probe->SetFileName(path.c_str());
                       probe->Update();
                     },
                     30);
  VtkMessageCapture messages;
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  try {
    reader->Update();
  } catch (const std::exception& e) {
    // VTK believes the sizes in the XML: NumberOfComponents="-1e308" throws std::length_error
    // and a huge NumberOfPoints std::bad_alloc out of Update() (found by tests/fuzz).
    core::failInput(path.string(),
                    "not a readable VTK XML PolyData file: VTK failed with '{}' (a corrupt size or count in the "
                    "XML?); re-export it from ParaView",
                    e.what());
  }
  vtkPolyData* data = reader->GetOutput();
  if (!messages.text().empty() || data == nullptr) {
    core::failInput(path.string(), "not a readable VTK XML PolyData file; re-export it from ParaView. VTK said: {}",
                    messages.text());
  }
  TriangleMesh mesh;
  const vtkIdType np = data->GetNumberOfPoints();
  mesh.vertices.reserve(static_cast<std::size_t>(np));
  for (vtkIdType i = 0; i < np; ++i) {
    double p[3];
    data->GetPoint(i, p);
    mesh.vertices.emplace_back(p[0], p[1], p[2]);
  }
  const auto addPolygon = [&](vtkIdType n, const vtkIdType* ids) {
    for (vtkIdType k = 1; k + 1 < n; ++k) {
      mesh.triangles.push_back({static_cast<std::int32_t>(ids[0]), static_cast<std::int32_t>(ids[k]),
                                static_cast<std::int32_t>(ids[k + 1])});
    }
  };
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  vtkCellArray* polys = data->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
    addPolygon(n, ids);
  }
  vtkCellArray* strips = data->GetStrips();
  for (strips->InitTraversal(); strips->GetNextCell(n, ids);) {
    // A strip (p0, p1, p2, p3, ...) holds triangles (p_k, p_k+1, p_k+2), alternate ones reversed.
    for (vtkIdType k = 0; k + 2 < n; ++k) {
      const auto a = static_cast<std::int32_t>(ids[k]);
      const auto b = static_cast<std::int32_t>(ids[k + 1]);
      const auto c = static_cast<std::int32_t>(ids[k + 2]);
      mesh.triangles.push_back(k % 2 == 0 ? Triangle{a, b, c} : Triangle{b, a, c});
    }
  }
  if (mesh.triangles.empty()) {
    core::failInput(path.string(), "the .vtp holds no polygons; export the surface (Extract Surface in ParaView)");
  }
  return mesh;
}

void writeVtp(const TriangleMesh& mesh, const std::filesystem::path& path) { writeVtp(mesh, path, {}); }

void writeVtp(const TriangleMesh& mesh, const std::filesystem::path& path, const std::vector<CellArray>& cells) {
  vtkNew<vtkCellArray> polys;
  for (const auto& f : mesh.triangles) {
    const vtkIdType ids[3] = {f[0], f[1], f[2]};
    polys->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> data;
  data->SetPoints(toVtkPoints(mesh.vertices));
  data->SetPolys(polys);
  for (const CellArray& c : cells) {
    if (c.values.size() != mesh.triangles.size())
      throw std::invalid_argument("writeVtp: cell array '" + c.name + "' has not one value per triangle");
    vtkNew<vtkDoubleArray> array;
    array->SetName(c.name.c_str());
    array->SetNumberOfValues(static_cast<vtkIdType>(c.values.size()));
    for (std::size_t i = 0; i < c.values.size(); ++i) array->SetValue(static_cast<vtkIdType>(i), c.values[i]);
    data->GetCellData()->AddArray(array);
  }
  vtkNew<vtkXMLPolyDataWriter> writer;
  writeVtkXmlAtomically(*writer, data, path);
}

} // namespace armour::geometry
