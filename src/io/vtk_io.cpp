#include "io/vtk_io.hpp"

#include <vtkCellArray.h>
#include <vtkDataSet.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkStructuredGrid.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLStructuredGridWriter.h>

#include <sstream>

#include "common/errors.hpp"
#include "common/format.hpp"
#include "io/files.hpp"

namespace armstudy::io {

namespace {

// VTK's type code of each ArrayType, in the enum's order (io/vtk_io.hpp).
int vtkTypeOf(ArrayType type) {
  static constexpr int kCodes[] = {VTK_DOUBLE, VTK_FLOAT, VTK_INT, VTK_UNSIGNED_CHAR};
  return kCodes[static_cast<int>(type)];
}

vtkSmartPointer<vtkDataArray> makeArray(const NamedArray& a, long tuples) {
  ARMSTUDY_CHECK(a.components >= 1, "array '" + a.name + "' needs at least one component");
  ARMSTUDY_CHECK(static_cast<long>(a.values.size()) == tuples * a.components,
                 "array '" + a.name + "' has the wrong number of values");
  vtkSmartPointer<vtkDataArray> arr;
  arr.TakeReference(vtkDataArray::CreateDataArray(vtkTypeOf(a.type)));
  arr->SetName(a.name.c_str());
  arr->SetNumberOfComponents(a.components);
  arr->SetNumberOfTuples(tuples);
  for (long t = 0; t < tuples; ++t)
    for (int c = 0; c < a.components; ++c)
      arr->SetComponent(t, c, a.values[static_cast<std::size_t>(t * a.components + c)]);
  return arr;
}

void addFieldData(vtkDataSet* data, const std::vector<FieldStrings>& fields) {
  for (const FieldStrings& f : fields) {
    vtkNew<vtkStringArray> a;
    a->SetName(f.name.c_str());
    a->SetNumberOfValues(static_cast<vtkIdType>(f.values.size()));
    for (std::size_t i = 0; i < f.values.size(); ++i)
      a->SetValue(static_cast<vtkIdType>(i), f.values[i]);
    data->GetFieldData()->AddArray(a);
  }
}

vtkSmartPointer<vtkPoints> makePoints(const std::vector<Eigen::Vector3d>& p) {
  auto pts = vtkSmartPointer<vtkPoints>::New();
  pts->SetDataTypeToDouble();
  pts->SetNumberOfPoints(static_cast<vtkIdType>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i)
    pts->SetPoint(static_cast<vtkIdType>(i), p[i].x(), p[i].y(), p[i].z());
  return pts;
}

template <class Writer>
void writeAtomic(Writer* w, const std::string& path) {
  w->SetDataModeToAppended();
  w->SetCompressorTypeToZLib();
  w->WriteToOutputStringOn();
  if (w->Write() != 1) throw InputError(path, 0, "", "VTK writer failed");
  writeFileAtomic(path, w->GetOutputString());
}

}  // namespace

std::vector<FieldStrings> fieldData(std::vector<std::string> units, std::vector<std::string> legend,
                                    std::string coordinates) {
  std::vector<FieldStrings> f{{"coordinates", {std::move(coordinates)}},
                              {"units", std::move(units)}};
  if (!legend.empty()) f.push_back({"legend", std::move(legend)});
  return f;
}

void writeVti(const std::string& path, const ImageGrid& g) {
  vtkNew<vtkImageData> img;
  img->SetDimensions(g.dims[0], g.dims[1], g.dims[2]);
  img->SetOrigin(g.origin[0], g.origin[1], g.origin[2]);
  img->SetSpacing(g.spacing[0], g.spacing[1], g.spacing[2]);
  for (const NamedArray& a : g.point_arrays)
    img->GetPointData()->AddArray(makeArray(a, g.points()));
  addFieldData(img, g.field_data);
  vtkNew<vtkXMLImageDataWriter> w;
  w->SetInputData(img);
  writeAtomic(w.GetPointer(), path);
}

void writeVtp(const std::string& path, const PolyDataSet& p) {
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(makePoints(p.points));
  const long n = static_cast<long>(p.points.size());
  auto checkIndex = [n](int i) {
    ARMSTUDY_CHECK(i >= 0 && i < n, "poly data cell index out of range");
  };
  if (p.vertices) {
    vtkNew<vtkCellArray> verts;
    for (vtkIdType i = 0; i < n; ++i) verts->InsertNextCell(1, &i);
    poly->SetVerts(verts);
  }
  if (!p.lines.empty()) {
    vtkNew<vtkCellArray> lines;
    for (const auto& l : p.lines) {
      lines->InsertNextCell(static_cast<int>(l.size()));
      for (int i : l) {
        checkIndex(i);
        lines->InsertCellPoint(i);
      }
    }
    poly->SetLines(lines);
  }
  if (!p.triangles.empty()) {
    vtkNew<vtkCellArray> polys;
    for (const auto& t : p.triangles) {
      vtkIdType ids[3] = {t[0], t[1], t[2]};
      for (int i : t) checkIndex(i);
      polys->InsertNextCell(3, ids);
    }
    poly->SetPolys(polys);
  }
  for (const NamedArray& a : p.point_arrays) poly->GetPointData()->AddArray(makeArray(a, n));
  if (!p.active_tensors.empty()) {
    ARMSTUDY_CHECK(poly->GetPointData()->GetArray(p.active_tensors.c_str()),
                   "active tensors '" + p.active_tensors + "' is not a point array");
    poly->GetPointData()->SetActiveTensors(p.active_tensors.c_str());
  }
  addFieldData(poly, p.field_data);
  vtkNew<vtkXMLPolyDataWriter> w;
  w->SetInputData(poly);
  writeAtomic(w.GetPointer(), path);
}

void writeVts(const std::string& path, const StructuredGridSet& g) {
  const long n = static_cast<long>(g.dims[0]) * g.dims[1] * g.dims[2];
  ARMSTUDY_CHECK(static_cast<long>(g.points.size()) == n,
                 "structured grid: points do not match its dimensions");
  vtkNew<vtkStructuredGrid> grid;
  grid->SetDimensions(g.dims[0], g.dims[1], g.dims[2]);
  grid->SetPoints(makePoints(g.points));
  for (const NamedArray& a : g.point_arrays) grid->GetPointData()->AddArray(makeArray(a, n));
  addFieldData(grid, g.field_data);
  vtkNew<vtkXMLStructuredGridWriter> w;
  w->SetInputData(grid);
  writeAtomic(w.GetPointer(), path);
}

void writePvd(const std::string& path, const std::vector<PvdStep>& steps) {
  std::ostringstream s;
  s << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
       "byte_order=\"LittleEndian\">\n"
    << "  <Collection>\n";
  for (const PvdStep& st : steps) {
    s << "    <DataSet timestep=\"" << formatG(st.time, 9) << "\" group=\"\" part=\"0\" file=\""
      << st.file << "\"/>\n";
  }
  s << "  </Collection>\n</VTKFile>\n";
  writeFileAtomic(path, s.str());
}

}  // namespace armstudy::io
