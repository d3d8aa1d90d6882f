// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/VtuFile.hpp"

#include "core/AtomicFile.hpp"
#include "core/Error.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

namespace armour::geometry {

void writeVtu(const TetMesh& mesh, const std::filesystem::path& path) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const auto& v = mesh.vertices[i];
    points->SetPoint(static_cast<vtkIdType>(i), v.x(), v.y(), v.z());
  }
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->Allocate(static_cast<vtkIdType>(mesh.tets.size()));
  vtkNew<vtkDoubleArray> volume;
  volume->SetName("volume");
  volume->SetNumberOfTuples(static_cast<vtkIdType>(mesh.tets.size()));
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& k = mesh.tets[t];
    const vtkIdType ids[4] = {k[0], k[1], k[2], k[3]};
    grid->InsertNextCell(VTK_TETRA, 4, ids);
    volume->SetValue(static_cast<vtkIdType>(t), mesh.volume(t));
  }
  grid->GetCellData()->AddArray(volume);

  const auto tmp = core::temporarySibling(path);
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(tmp.c_str());
  writer->SetInputData(grid);
  writer->SetDataModeToAppended();
  writer->SetCompressorTypeToZLib();
  if (writer->Write() != 1) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    core::failInput(path.string(), "VTK could not write the file; check that the folder exists and is writable");
  }
  core::commitAtomicFile(tmp, path);
}

} // namespace armour::geometry
