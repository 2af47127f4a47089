// ParaView: every spatial file of a small study (reach grid with obstacles, dexterity map,
// tracked line) parses with VTK's readers, carries its field data, and lies in world metres so
// that maps, robot and obstacles overlay; scene.py lists them and ParaView's Python renders
// the scene offscreen.
#include <unistd.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkStringArray.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLStructuredGridReader.h>

#include <array>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "io/files.hpp"
#include "io/vtk_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

constexpr double kStemX = 0.225, kStemY = 0.7, kRadius = 0.15;  // the study's [dexterity] circle
constexpr double kSceneBox_m = 3.0;  // every world file within this of the robot base (metres)
constexpr double kGeometryTolerance = 1e-9;
constexpr double kMinDrawnShare = 0.05;  // of the screenshot's pixels that show something

const char* kStudy = R"(
[study]
name = "scene"
[[design]]
file = "DESIGN"
[[obstacle]]
name = "stem"
type = "capsule"
points = [["0.225 m", "0.7 m", "0 m"], ["0.225 m", "0.7 m", "2 m"]]
radius = "12 mm"
[[obstacle]]
name = "fruit"
type = "sphere"
points = [["-0.2 m", "0.66 m", "1.25 m"]]
radius = "45 mm"
[reach]
task_space = "position"
self_collision = true
[[reach.grid]]
name = "wall"
x = { from = "-0.4 m", to = "0.4 m", step = "0.2 m" }
y = "0.6 m"
z = { from = "0.8 m", to = "1.2 m", step = "0.2 m" }
[dexterity]
stem_x = "0.225 m"
stem_y = "0.7 m"
radius = "0.15 m"
gamma = { min = "-60 deg", max = "60 deg", step = "30 deg" }
z = { min = "0.9 m", max = "1.2 m", step = "0.1 m" }
ellipsoids = true
[[tracking]]
name = "line"
design = "final_prototype_7dof"
q0 = [0, 0.2, 0.3, 1.2, 0, 0.6, 0]
delta = ["0.1 m", 0, 0]
duration = 0.5
rate = 200
)";

std::vector<std::string> strings(vtkDataObject* d, const char* name) {
  std::vector<std::string> out;
  if (auto* a = vtkStringArray::SafeDownCast(d->GetFieldData()->GetAbstractArray(name)))
    for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i) out.push_back(a->GetValue(i));
  return out;
}

// Reads a .vti, .vts or .vtp with VTK's reader for it; the returned data set stays valid while
// `keep` holds its reader.
vtkDataSet* readSpatial(const std::string& path, std::vector<vtkSmartPointer<vtkObject>>& keep) {
  auto read = [&](auto reader) -> vtkDataSet* {
    reader->SetFileName(path.c_str());
    reader->Update();
    keep.push_back(reader);
    return vtkDataSet::SafeDownCast(reader->GetOutputDataObject(0));
  };
  if (path.size() > 4 && path.compare(path.size() - 4, 4, ".vti") == 0)
    return read(vtkSmartPointer<vtkXMLImageDataReader>::New());
  if (path.size() > 4 && path.compare(path.size() - 4, 4, ".vts") == 0)
    return read(vtkSmartPointer<vtkXMLStructuredGridReader>::New());
  return read(vtkSmartPointer<vtkXMLPolyDataReader>::New());
}

// A folder removed when the process ends.
struct TempFolder {
  fs::path dir;
  ~TempFolder() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

// The study's output folder, run once for all test cases of this file in a process. One folder
// per process: ctest runs this file's test cases as parallel processes.
const fs::path& sceneRun() {
  static const TempFolder folder{fs::temp_directory_path() /
                                 ("armstudy_paraview_scene_" + std::to_string(::getpid()))};
  static const fs::path out = [] {
    const fs::path& dir = folder.dir;
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::string text = kStudy;
    text.replace(text.find("DESIGN"), 6, sourcePath("designs/final_prototype_7dof.toml"));
    std::ofstream((dir / "scene.toml").string()) << text;
    std::string log;
    const int rc = runCommand(binaryPath() + " run " + (dir / "scene.toml").string() +
                                  " --output " + (dir / "out").string() + " --threads 2",
                              log);
    INFO(log);
    REQUIRE(rc == 0);
    return dir / "out" / "scene";
  }();
  return out;
}

std::vector<std::string> manifestFiles(const fs::path& out) {
  const auto man = nlohmann::json::parse(readFileOrThrow((out / "manifest.json").string()));
  return man["files"].get<std::vector<std::string>>();
}

}  // namespace

TEST_CASE("every spatial file of a study parses, has field data and overlays in world metres",
          "[scene][paraview][e2e]") {
  const fs::path out = sceneRun();
  const std::vector<std::string> files = manifestFiles(out);
  // The robot base (final prototype: base frame at the origin of W).
  const Eigen::Vector3d base(0, 0, 0);
  int world = 0, parameter = 0, pvd = 0;
  std::vector<vtkSmartPointer<vtkObject>> keep;
  double max_link_reach = 0;  // skeleton length of the arm at its best reach pose
  for (const std::string& f : files) {
    if (f.size() > 4 && f.compare(f.size() - 4, 4, ".pvd") == 0) {
      ++pvd;
      // Every step the collection names exists, in order of time, within the cap.
      const std::string text = readFileOrThrow((out / f).string());
      const std::regex ds("timestep=\"([^\"]+)\"[^>]*file=\"([^\"]+)\"");
      double last = -1;
      int steps = 0;
      for (std::sregex_iterator it(text.begin(), text.end(), ds), end; it != end; ++it, ++steps) {
        CHECK(std::stod((*it)[1].str()) > last);
        last = std::stod((*it)[1].str());
        CHECK(fs::exists((out / f).parent_path() / (*it)[2].str()));
      }
      CHECK(steps >= 2);
      CHECK(steps <= 50);
      continue;
    }
    if (!(f.ends_with(".vti") || f.ends_with(".vts") || f.ends_with(".vtp"))) continue;
    INFO(f);
    vtkDataSet* d = readSpatial((out / f).string(), keep);
    REQUIRE(d);
    REQUIRE(d->GetNumberOfPoints() > 0);
    const std::vector<std::string> coords = strings(d, "coordinates"), units = strings(d, "units");
    REQUIRE(coords.size() == 1);
    CHECK(!units.empty());
    // Every point array has a unit.
    for (int a = 0; a < d->GetPointData()->GetNumberOfArrays(); ++a) {
      const std::string name = d->GetPointData()->GetArrayName(a);
      bool has = false;
      for (const std::string& u : units) has = has || u.rfind(name + ":", 0) == 0;
      INFO(name);
      CHECK(has);
    }
    if (coords[0] != io::kWorldMetres) {
      ++parameter;  // the dexterity map over (gamma [rad], z [m]) beside its cylinder
      CHECK(f == "dexterity/final_prototype_7dof.vti");
      continue;
    }
    ++world;
    double b[6];
    d->GetBounds(b);
    for (int a = 0; a < 3; ++a) {
      CHECK(b[2 * a] >= base[a] - kSceneBox_m);
      CHECK(b[2 * a + 1] <= base[a] + kSceneBox_m);
    }
    if (f.find("_robot_best") != std::string::npos) {
      double len = 0, p[3], q[3];
      d->GetPoint(0, q);
      for (int i = 1; i <= 8; ++i) {  // skeleton: base, 7 frames, TCP
        d->GetPoint(i, p);
        len += std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
        std::copy(p, p + 3, q);
      }
      max_link_reach = std::max(max_link_reach, len);
    }
  }
  CHECK(parameter == 1);
  CHECK(pvd == 2);  // the tracked line without and with H_c
  CHECK(world >= 8);
  REQUIRE(max_link_reach > 0);

  // The stem map on its cylinder: point (gamma, z) = stem centre - r (sin gamma, cos gamma) at
  // height z, written out here; its reachable points within the arm's reach of the base.
  std::vector<vtkSmartPointer<vtkObject>> keep2;
  vtkDataSet* cyl =
      readSpatial((out / "dexterity/final_prototype_7dof_cylinder.vts").string(), keep2);
  vtkDataArray* gamma = cyl->GetPointData()->GetArray("gamma");
  vtkDataArray* z = cyl->GetPointData()->GetArray("z");
  vtkDataArray* reach = cyl->GetPointData()->GetArray("reachable");
  vtkDataArray* manip = cyl->GetPointData()->GetArray("manipulability_optimised");
  REQUIRE((gamma && z && reach && manip));
  REQUIRE(cyl->GetNumberOfPoints() == 5 * 4);
  int reachable = 0;
  for (vtkIdType k = 0; k < cyl->GetNumberOfPoints(); ++k) {
    const double g = (-60.0 + 30.0 * (k % 5)) * M_PI / 180, h = 0.9 + 0.1 * (k / 5);
    CHECK(std::abs(gamma->GetTuple1(k) - g) < kGeometryTolerance);
    CHECK(std::abs(z->GetTuple1(k) - h) < kGeometryTolerance);
    double p[3];
    cyl->GetPoint(k, p);
    CHECK(std::abs(p[0] - (kStemX - kRadius * std::sin(g))) < kGeometryTolerance);
    CHECK(std::abs(p[1] - (kStemY - kRadius * std::cos(g))) < kGeometryTolerance);
    CHECK(std::abs(p[2] - h) < kGeometryTolerance);
    if (reach->GetTuple1(k) == 1) {
      ++reachable;
      CHECK(std::isfinite(manip->GetTuple1(k)));
      CHECK(std::hypot(p[0] - base[0], p[1] - base[1], p[2] - base[2]) <= max_link_reach);
    } else {
      CHECK(std::isnan(manip->GetTuple1(k)));  // no solution, no manipulability
    }
  }
  CHECK(reachable > 0);
}

TEST_CASE("scene.py lists the world files and renders offscreen with ParaView's Python",
          "[scene][paraview][e2e]") {
  const fs::path out = sceneRun();
  const std::string text = readFileOrThrow((out / "scene.py").string());
  const std::size_t from = text.find("FILES = ["), to = text.find("]", from);
  REQUIRE(to != std::string::npos);
  const std::string script = text.substr(from, to - from);  // the list of files
  for (const std::string& f : manifestFiles(out)) {
    const bool listed = script.find("\"" + f + "\"") != std::string::npos;
    INFO(f);
    if (f.find("/step_") != std::string::npos)
      CHECK(!listed);  // through their .pvd
    else if (f.ends_with(".vti") || f.ends_with(".vts") || f.ends_with(".vtp") ||
             f.ends_with(".pvd"))
      CHECK(listed);
    else
      CHECK(!listed);
  }
  CHECK(script.find("\"scene/obstacles.vtp\"") != std::string::npos);

  // pvpython: the one ARMSTUDY_PVPYTHON names, else the ParaView that scripts/unpack-paraview.sh
  // (run by scripts/build.sh, i.e. the test command) unpacked into the build folder, else a system
  // one (Debian: paraview, python3-paraview, which conflicts with libvtk9-dev). Debian's ParaView
  // renders through X: without a display the test uses xvfb-run (package xvfb, which
  // scripts/install-deps.sh installs). A missing pvpython or a failed render fails the test.
  std::string log;
  const char* own = std::getenv("ARMSTUDY_PVPYTHON");
  std::string pvpython = own && *own ? own : "pvpython";
  if (!(own && *own) && fs::exists(ARMSTUDY_UNPACKED_PVPYTHON))
    pvpython = ARMSTUDY_UNPACKED_PVPYTHON;
  {
    INFO(
        "ParaView's pvpython is missing: scripts/unpack-paraview.sh (run by scripts/build.sh) "
        "unpacks it into "
        << ARMSTUDY_UNPACKED_PVPYTHON << ", or set ARMSTUDY_PVPYTHON");
    REQUIRE(runCommand("command -v " + pvpython, log) == 0);
  }
  const bool display = std::getenv("DISPLAY") != nullptr;
  const bool xvfb = !display && runCommand("command -v xvfb-run", log) == 0;
  // Two pictures of the same scene: with its colour bars and without them (--no-bars).
  auto render = [&](const std::string& name, const std::string& extra) {
    const fs::path png = out / name, xvfb_log = out / (name + ".xvfb.log");
    fs::remove(png);
    // xvfb-run writes what Xvfb and xauth say to xvfb_log (else nowhere): a failed start is named.
    const std::string runner = xvfb      ? "xvfb-run -a -e " + xvfb_log.string() + " " + pvpython
                               : display ? pvpython
                                         : pvpython + " --force-offscreen-rendering";
    const std::string command =
        runner + " " + (out / "scene.py").string() + " --screenshot " + png.string() + extra;
    auto xvfbSaid = [&] {
      std::error_code ec;
      return xvfb && fs::exists(xvfb_log, ec)
                 ? "\n(Xvfb: " + readFileOrThrow(xvfb_log.string()) + ")"
                 : std::string();
    };
    int rc = runCommand(command, log);
    // xvfb-run -a picks a free display but races with another xvfb-run starting at the same
    // moment, and a server slow to start on a loaded machine refuses the first connection ("bad X
    // server connection"): try twice more, after a pause, keeping every attempt's output.
    std::string all = log + (rc != 0 ? xvfbSaid() : "");
    for (int attempt = 0; rc != 0 && xvfb && attempt < 2; ++attempt) {
      std::this_thread::sleep_for(std::chrono::seconds(3));
      rc = runCommand(command, log);
      all += "\n--- again ---\n" + log + (rc != 0 ? xvfbSaid() : "");
    }
    INFO(command << "\n" << all);
    REQUIRE(rc == 0);
    REQUIRE(fs::exists(png));
    return png;
  };
  const fs::path with_bars = render("scene_test.png", ""),
                 without = render("scene_test_nobars.png", " --no-bars");
  auto load = [](const fs::path& png, std::vector<vtkSmartPointer<vtkObject>>& keep) {
    auto reader = vtkSmartPointer<vtkPNGReader>::New();
    reader->SetFileName(png.c_str());
    reader->Update();
    keep.push_back(reader);
    return reader->GetOutput();
  };
  std::vector<vtkSmartPointer<vtkObject>> images;
  vtkImageData* a = load(with_bars, images);
  vtkImageData* b = load(without, images);
  int dims[3], dims_b[3];
  a->GetDimensions(dims);
  b->GetDimensions(dims_b);
  REQUIRE(dims[0] * dims[1] > 0);
  REQUIRE((dims[0] == dims_b[0] && dims[1] == dims_b[1]));
  auto pixel = [](vtkImageData* img, int x, int y) {
    std::array<double, 3> c{};
    for (int k = 0; k < 3; ++k) c[k] = img->GetScalarComponentAsDouble(x, y, 0, k);
    return c;
  };
  const auto background = pixel(b, dims[0] - 1, dims[1] - 1);
  // The scene = what differs from the background without bars; the bars and their text = what
  // the bars change. A picture, not an empty view; no bar text over the scene (no pixel that is
  // both); nothing clipped at the picture's edges (neither scene nor bar text on its border).
  long scene = 0, bar = 0, overlap = 0, scene_on_border = 0, bar_on_border = 0;
  for (int y = 0; y < dims[1]; ++y)
    for (int x = 0; x < dims[0]; ++x) {
      const auto pb = pixel(b, x, y);
      const bool in_scene = pb != background, in_bar = pixel(a, x, y) != pb;
      const bool border = x < 2 || y < 2 || x >= dims[0] - 2 || y >= dims[1] - 2;
      scene += in_scene;
      bar += in_bar;
      overlap += in_scene && in_bar;
      scene_on_border += in_scene && border;
      bar_on_border += in_bar && border;
    }
  CHECK(scene > kMinDrawnShare * dims[0] * dims[1]);
  CHECK(bar > 0);  // the scene colours at least one array (manipulability, status, ...) with a bar
  CHECK(overlap == 0);
  CHECK(scene_on_border == 0);
  CHECK(bar_on_border == 0);
}
