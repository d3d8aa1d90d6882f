// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/VtuFile.hpp"

#include "geometry/VtkSupport.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

namespace armour::geometry {

void writeVtu(const TetMesh& mesh, const std::filesystem::path& path) {
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(toVtkPoints(mesh.vertices));
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
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writeVtkXmlAtomically(*writer, grid, path);
}

} // namespace armour::geometry
