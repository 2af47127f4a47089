// The 3-D views of the spatial studies that are not maps: a calibration's residuals over the
// workspace, the harvest holding grid, the tracking runs among obstacles. Each view.html is read
// back (tests/view_page.hpp) and its points, values, units and statuses are compared with what
// the study wrote elsewhere or with the design's own kinematics: residuals.csv and the data with
// forward kinematics, the holding grid's .vti (read with VTK), the runs' CSV files.
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLImageDataReader.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "kinematics/kinematics.hpp"
#include "shipped_output.hpp"
#include "study/checkpoint.hpp"
#include "test_support.hpp"
#include "view_page.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

constexpr double kFloat32Rel = 1e-6;  // a value carried as float32, relative
const double kPosTol = test::kViewPositionQuantum;

// A CSV of numbers and text, by column name (the runs' files hold the closest pair's name).
struct Table {
  std::vector<std::string> head;
  std::vector<std::vector<std::string>> rows;
  double at(std::size_t r, const std::string& col) const {
    for (std::size_t c = 0; c < head.size(); ++c)
      if (head[c] == col) return std::stod(rows[r][c]);
    FAIL("no column " << col);
    return 0;
  }
};
Table readTable(const fs::path& p) {
  std::istringstream in(readFileOrThrow(p.string()));
  Table t;
  std::string line;
  for (bool first = true; std::getline(in, line); first = false) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    (first ? t.head : (t.rows.emplace_back(), t.rows.back())) = cells;
  }
  return t;
}

std::vector<test::ViewMap> viewMaps(const fs::path& out, nlohmann::json* data = nullptr) {
  REQUIRE(fs::exists(out / "view.html"));
  const nlohmann::json d = test::viewPageData(readFileOrThrow((out / "view.html").string()));
  CHECK(d["stride"] == 1);  // every point is carried
  std::vector<test::ViewMap> maps;
  for (const auto& c : d["clouds"]) maps.push_back(test::viewMap(c));
  if (data) *data = d;
  return maps;
}

const test::ViewMap& mapNamed(const std::vector<test::ViewMap>& maps, const std::string& name) {
  for (const test::ViewMap& m : maps)
    if (m.name == name) return m;
  FAIL("no map " << name);
  return maps.front();
}

// A study of one TCP calibration entry: the virtual 7-DoF's TCP data of arm_calibration.
std::string tcpStudyText(const std::string& name) {
  return "[study]\nname = \"" + name + "\"\n[[design]]\nfile = \"" +
         test::sourcePath("designs/final_prototype_7dof.toml") +
         "\"\n[[calibration]]\nname = \"tcp\"\nkind = \"tcp\"\ndesign = "
         "\"final_prototype_7dof\"\ndata = \"" +
         test::sourcePath("studies/data/arm_tcp_synth.csv") + "\"\nauto = true\n";
}

fs::path runStudyText(const std::string& name, const std::string& toml) {
  const fs::path dir = test::emptyTempDir(name);
  const fs::path file = dir / (name + ".toml");
  writeFileAtomic(file.string(), toml);
  RunOptions ro;
  ro.output_root = (dir / "out").string();
  ro.threads = 2;
  ro.progress = false;
  (void)runStudy(loadStudy(file.string()), ro);
  return dir / "out" / name;
}

}  // namespace

TEST_CASE(
    "view.html of a TCP calibration: the rows' positions with their position error in mm, "
    "before and after the fit, flagged cells and the arm at the worst row",
    "[report][calibration][study]") {
  const std::string design = test::sourcePath("designs/final_prototype_7dof.toml"),
                    data = test::sourcePath("studies/data/arm_tcp_synth.csv");
  const fs::path out = runStudyText("tcp_view", tcpStudyText("tcp_view"));
  nlohmann::json page;
  const auto maps = viewMaps(out, &page);
  REQUIRE(maps.size() == 2);
  const test::ViewMap &before = mapNamed(maps, "tcp before the fit: TCP position error"),
                      &after = mapNamed(maps, "tcp after the fit: TCP position error");
  const std::string html = readFileOrThrow((out / "view.html").string());
  CHECK(html.find("<option value=\"value\">residual</option>") != std::string::npos);
  CHECK(html.find("data rows' TCP positions") != std::string::npos);
  const Table in = readTable(data), res = readTable(out / "calibration/tcp/residuals.csv");
  REQUIRE(before.p_W.size() == in.rows.size());
  REQUIRE(after.p_W.size() == in.rows.size());
  const Model m = loadDesign(design);
  KinematicsWorkspace ws(m);
  std::size_t worst = 0;
  for (std::size_t r = 0; r < in.rows.size(); ++r) {
    INFO("row " << r);
    Eigen::VectorXd q(m.dof());
    for (int j = 0; j < m.dof(); ++j) q[j] = in.at(r, "q" + std::to_string(j + 1));
    forwardKinematics(m, ws, q);
    const Eigen::Vector3d measured(in.at(r, "x"), in.at(r, "y"), in.at(r, "z"));
    for (int a = 0; a < 3; ++a) {  // TCP data: the measured position
      CHECK(before.p_W[r][a] == Approx(measured[a]).margin(kPosTol));
      CHECK(after.p_W[r][a] == Approx(measured[a]).margin(kPosTol));
    }
    // Before: the design as it is; after: the fit's residuals as residuals.csv holds them.
    const double before_mm = 1e3 * (measured - ws.p_WT).norm();
    const double after_mm = 1e3 * Eigen::Vector3d(res.at(r, "residual_x"), res.at(r, "residual_y"),
                                                  res.at(r, "residual_z"))
                                      .norm();
    CHECK(before.value[r] == Approx(before_mm).epsilon(kFloat32Rel));
    CHECK(after.value[r] == Approx(after_mm).epsilon(kFloat32Rel));
    if (before.value[r] > before.value[worst]) worst = r;
  }
  CHECK(before.unit == "mm");
  CHECK(after.quantity == before.quantity);  // one colour scale before and after
  // Statuses: rows in a workspace cell result.json flags before the fit; none after it.
  const nlohmann::json result =
      nlohmann::json::parse(readFileOrThrow((out / "calibration/tcp/result.json").string()));
  CHECK(result["flagged_after"] == 0);
  int flagged_rows = 0, shown_flagged = 0;
  for (std::size_t r = 0; r < in.rows.size(); ++r) {
    bool in_flagged = false;
    for (const auto& b : result["regions_before"]) {
      if (b["space"] != "workspace") continue;
      bool inside = true;
      for (int a = 0; a < 3; ++a) {
        const double x = in.at(r, std::string(1, "xyz"[a]));
        inside = inside && x >= b["lo"][a].get<double>() && x <= b["hi"][a].get<double>();
      }
      in_flagged = in_flagged || inside;
    }
    flagged_rows += in_flagged;
    shown_flagged += before.status[r] == 0;
    CHECK(after.status[r] == 1);
  }
  CHECK(flagged_rows > 0);
  CHECK(shown_flagged == flagged_rows);
  // The arm of the before map ends at the design's TCP at the row of the largest error.
  Eigen::VectorXd q(m.dof());
  for (int j = 0; j < m.dof(); ++j) q[j] = in.at(worst, "q" + std::to_string(j + 1));
  forwardKinematics(m, ws, q);
  REQUIRE(!before.arm_W.empty());
  for (int a = 0; a < 3; ++a) CHECK(before.arm_W.back()[a] == Approx(ws.p_WT[a]).margin(1e-3));
  CHECK(before.caption.find("line " + std::to_string(worst + 2)) != std::string::npos);
}

namespace {

// The holding map of `design` in the view against the holding .vti of the study folder `out`;
// returns the drive-limited points seen.
std::size_t checkHoldingView(const fs::path& out, const std::vector<test::ViewMap>& maps,
                             const std::string& design) {
  {
    INFO(design);
    const test::ViewMap& v = mapNamed(maps, "static holding: " + design);
    CHECK(v.unit == "1");
    CHECK(v.quantity == "max |I| / I_continuous over the revolute joints");
    auto reader = vtkSmartPointer<vtkXMLImageDataReader>::New();
    reader->SetFileName((out / "harvest" / (design + "_holding.vti")).string().c_str());
    reader->Update();
    vtkImageData* img = reader->GetOutput();
    vtkDataArray* status = img->GetPointData()->GetArray("status");
    vtkDataArray* ratio = img->GetPointData()->GetArray("max_current_ratio_revolute");
    REQUIRE(status);
    REQUIRE(ratio);
    std::size_t k = 0, limited = 0;
    for (vtkIdType p = 0; p < img->GetNumberOfPoints(); ++p) {
      const int s = static_cast<int>(status->GetTuple1(p));
      if (s == 0) continue;  // unreachable: not drawn
      REQUIRE(k < v.p_W.size());
      double x[3];
      img->GetPoint(p, x);
      for (int a = 0; a < 3; ++a) CHECK(v.p_W[k][a] == Approx(x[a]).margin(kPosTol));
      CHECK(v.status[k] == (s == 1 ? 0 : 5));  // the holding map's colours: holdable, drive limit
      CHECK(v.value[k] == Approx(ratio->GetTuple1(p)).epsilon(kFloat32Rel));
      limited += s == 2;
      ++k;
    }
    CHECK(k == v.p_W.size());
    CHECK(k > 0);
    CHECK(v.arm_W.size() >= 3);
    return limited;
  }
}

}  // namespace

TEST_CASE(
    "view.html of harvest_torque: the holding grid's points, statuses and current ratios "
    "as the holding .vti holds them",
    "[report][study]") {
  const fs::path out = test::shippedOutput("harvest_torque");
  const auto maps = viewMaps(out);
  REQUIRE(maps.size() == 2);
  for (const std::string design : {"final_prototype_9dof", "final_prototype_7dof"})
    checkHoldingView(out, maps, design);
}

TEST_CASE(
    "view.html of a harvest holding grid with drives too weak to hold some poses: those "
    "points in the holding map's drive-limit colour",
    "[report][study]") {
  // The 7-DoF with its 6.5 A drives' continuous current cut to 0.5 A.
  std::string design = readFileOrThrow(test::sourcePath("designs/final_prototype_7dof.toml"));
  std::size_t cut = 0;
  for (std::size_t at = design.find("continuous_current = 6.5"); at != std::string::npos;
       at = design.find("continuous_current = 6.5", at), ++cut)
    design.replace(at, 24, "continuous_current = 0.5");
  REQUIRE(cut > 0);
  const fs::path dir = test::emptyTempDir("harvest_weak_view");
  writeFileAtomic((dir / "weak.toml").string(), design);
  std::string study = readFileOrThrow(test::sourcePath("studies/harvest_torque.toml"));
  study = study.substr(study.find("[harvest]"));
  study = study.substr(0, study.find("[regression]"));
  const std::string head = "[study]\nname = \"harvest_weak\"\n[[design]]\nfile = \"" +
                           (dir / "weak.toml").string() + "\"\n";
  const fs::path out = runStudyText("harvest_weak", head + study);
  const auto maps = viewMaps(out);
  REQUIRE(maps.size() == 1);
  CHECK(checkHoldingView(out, maps, "final_prototype_7dof") > 0);
}

TEST_CASE(
    "view.html of fig5_13_obstacle: each run's TCP path with its distance to the sphere in "
    "mm, the contacts, and the arm at the closest approach",
    "[report][study][tracking]") {
  const fs::path out = test::shippedOutput("fig5_13_obstacle");
  nlohmann::json page;
  const auto maps = viewMaps(out, &page);
  REQUIRE(maps.size() == 2);
  CHECK(page["solids"].size() >= 1);  // the sphere
  const nlohmann::json summary =
      nlohmann::json::parse(readFileOrThrow((out / "tracking/summary.json").string()));
  int contacts = 0;
  for (const auto& [run, file] :
       {std::pair<std::string, std::string>{"without H_c", "plain"}, {"with H_c", "with_hc"}}) {
    INFO(run);
    const test::ViewMap& v = mapNamed(maps, "fig5_13 " + run + ": TCP path");
    CHECK(v.unit == "mm");
    CHECK(v.quantity == "distance to the obstacles");
    const Table t = readTable(out / "tracking" / ("fig5_13_" + file + ".csv"));
    REQUIRE(v.p_W.size() == t.rows.size());
    double closest = INFINITY;
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      const double d = t.at(r, "obstacle_distance_m");
      CHECK(v.p_W[r][0] == Approx(t.at(r, "x_m")).margin(kPosTol));
      CHECK(v.p_W[r][2] == Approx(t.at(r, "z_m")).margin(kPosTol));
      CHECK(v.value[r] == Approx(1e3 * d).epsilon(kFloat32Rel).margin(1e-6));
      const bool contact = d < 0 || t.at(r, "self_distance_m") < 0;
      CHECK(v.status[r] == (contact ? 1 : 0));
      contacts += contact;
      closest = std::min(closest, d);
    }
    int matched = 0;
    for (const auto& e : summary["entries"])
      for (const auto& j : e["runs"])
        if (j["run"] == file) {
          CHECK(j["min_obstacle_distance_m"].get<double>() == Approx(closest));
          ++matched;
        }
    CHECK(matched == 1);
    CHECK(v.caption.find("closest approach") != std::string::npos);
    CHECK(v.arm_W.size() >= 3);
  }
  CHECK(contacts > 0);  // the run without H_c touches the sphere
}

TEST_CASE("a calibration entry resumed from its checkpoint hands the view the same maps",
          "[report][calibration][study][checkpoint]") {
  const fs::path dir = test::emptyTempDir("tcp_view_resume");
  writeFileAtomic((dir / "tcp_resume.toml").string(), tcpStudyText("tcp_resume"));
  const Study s = loadStudy((dir / "tcp_resume.toml").string());
  const std::string out = (dir / "out" / s.name).string();
  fs::create_directories(out);
  std::string message;
  CheckpointStore store(out, studyFingerprint(s), message);
  RunOptions ro;
  ro.output_root = (dir / "out").string();
  ro.threads = 2;
  ro.progress = false;
  const StageResult a = runStage(s, "calibration", out, ro, &store);
  const StageResult b = runStage(s, "calibration", out, ro, &store);
  CHECK(a.units_resumed == 0);
  CHECK(b.units_resumed == 1);
  REQUIRE(a.view.size() == 2);
  REQUIRE(b.view.size() == a.view.size());
  CHECK(b.view_about == a.view_about);
  for (std::size_t k = 0; k < a.view.size(); ++k) {
    const report::ViewCloud &x = a.view[k], &y = b.view[k];
    INFO(x.name);
    CHECK(y.name == x.name);
    CHECK(y.p_W == x.p_W);
    CHECK(y.status == x.status);
    CHECK(y.status_names == x.status_names);
    CHECK(y.value == x.value);  // every value finite: compared exactly
    CHECK(y.value_unit == x.value_unit);
    CHECK(y.value_quantity == x.value_quantity);
    CHECK(y.point_size_m == x.point_size_m);
    CHECK(y.arm_W == x.arm_W);
    CHECK(y.arm_caption == x.arm_caption);
  }
}
