// The VTK writers (io/vtk_io.hpp): what is written is what VTK's own readers read back, field data
// included; a .pvd lists its steps in order.
#include "io/vtk_io.hpp"

#include <vtkAbstractArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkStructuredGrid.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLStructuredGridReader.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <regex>

#include "io/files.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

fs::path vtkDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("armstudy_vtk_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::vector<std::string> strings(vtkDataObject* data, const char* name) {
  std::vector<std::string> out;
  auto* a = vtkStringArray::SafeDownCast(data->GetFieldData()->GetAbstractArray(name));
  if (!a) return out;
  for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i) out.push_back(a->GetValue(i));
  return out;
}

}  // namespace

TEST_CASE("a .vts keeps its points, point arrays (NaN included) and string field data",
          "[io][vtk]") {
  const fs::path dir = vtkDir("vts");
  io::StructuredGridSet g;
  g.dims = {3, 2, 1};
  std::vector<double> v;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) {
      g.points.emplace_back(0.1 * i, std::sin(0.3 * i), 0.5 + j);
      v.push_back(i == 1 && j == 1 ? std::nan("") : i + 10.0 * j);
    }
  g.point_arrays.push_back({"value", io::ArrayType::Float64, 1, v});
  g.field_data = io::fieldData({"position: m", "value: 1"}, {"value NaN: none"});
  io::writeVts((dir / "g.vts").string(), g);

  vtkNew<vtkXMLStructuredGridReader> r;
  r->SetFileName((dir / "g.vts").c_str());
  r->Update();
  vtkStructuredGrid* out = r->GetOutput();
  REQUIRE(out->GetNumberOfPoints() == 6);
  int dims[3];
  out->GetDimensions(dims);
  CHECK((dims[0] == 3 && dims[1] == 2 && dims[2] == 1));
  vtkDataArray* a = out->GetPointData()->GetArray("value");
  REQUIRE(a);
  for (vtkIdType k = 0; k < 6; ++k) {
    double p[3];
    out->GetPoint(k, p);
    CHECK(p[0] == g.points[k].x());
    CHECK(p[1] == g.points[k].y());
    CHECK(p[2] == g.points[k].z());
    if (std::isnan(v[k]))
      CHECK(std::isnan(a->GetTuple1(k)));
    else
      CHECK(a->GetTuple1(k) == v[k]);
  }
  CHECK(strings(out, "coordinates") == std::vector<std::string>{io::kWorldMetres});
  CHECK(strings(out, "units") == std::vector<std::string>{"position: m", "value: 1"});
  CHECK(strings(out, "legend") == std::vector<std::string>{"value NaN: none"});
}

TEST_CASE(".vti and .vtp carry their field data", "[io][vtk]") {
  const fs::path dir = vtkDir("fields");
  io::ImageGrid img;
  img.dims = {2, 2, 1};
  img.point_arrays.push_back({"status", io::ArrayType::UInt8, 1, {0, 1, 2, 0}});
  img.field_data = io::fieldData({"status: 1"}, {"status 0: a", "status 1: b"}, "parameter plane");
  io::writeVti((dir / "i.vti").string(), img);
  vtkNew<vtkXMLImageDataReader> ri;
  ri->SetFileName((dir / "i.vti").c_str());
  ri->Update();
  CHECK(strings(ri->GetOutput(), "coordinates") == std::vector<std::string>{"parameter plane"});
  CHECK(strings(ri->GetOutput(), "legend").size() == 2);

  io::PolyDataSet poly;
  poly.points = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0)};
  poly.triangles = {{0, 1, 2}};
  poly.field_data = io::fieldData({"position: m"});
  io::writeVtp((dir / "p.vtp").string(), poly);
  vtkNew<vtkXMLPolyDataReader> rp;
  rp->SetFileName((dir / "p.vtp").c_str());
  rp->Update();
  CHECK(rp->GetOutput()->GetNumberOfPolys() == 1);
  CHECK(strings(rp->GetOutput(), "units") == std::vector<std::string>{"position: m"});
  CHECK(strings(rp->GetOutput(), "legend").empty());  // no enumeration, no legend
}

TEST_CASE("a .pvd lists its steps with their times in order", "[io][vtk]") {
  const fs::path dir = vtkDir("pvd");
  io::writePvd((dir / "m.pvd").string(),
               {{0.0, "m/step_000.vtp"}, {0.25, "m/step_001.vtp"}, {1.5, "m/step_002.vtp"}});
  const std::string text = readFileOrThrow((dir / "m.pvd").string());
  CHECK(text.find("type=\"Collection\"") != std::string::npos);
  const std::regex ds("<DataSet timestep=\"([^\"]+)\"[^>]*file=\"([^\"]+)\"");
  std::vector<std::pair<double, std::string>> got;
  for (std::sregex_iterator it(text.begin(), text.end(), ds), end; it != end; ++it)
    got.emplace_back(std::stod((*it)[1].str()), (*it)[2].str());
  REQUIRE(got.size() == 3);
  CHECK(got[0] == std::make_pair(0.0, std::string("m/step_000.vtp")));
  CHECK(got[1] == std::make_pair(0.25, std::string("m/step_001.vtp")));
  CHECK(got[2] == std::make_pair(1.5, std::string("m/step_002.vtp")));
}
