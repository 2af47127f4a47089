// The [[tracking]] stage (docs/tracking.md): thesis Fig. 5.13 from the shipped study file, checked
// against independent recomputation from the written joint trajectories (forward kinematics,
// collision distances, the line recomputed from q0), reproducibility, the ParaView scene read back
// with VTK, the joint-limit status, and bad input.
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "collision/collision.hpp"
#include "common/errors.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/csv_io.hpp"
#include "io/files.hpp"
#include "kinematics/kinematics.hpp"
#include "shipped_output.hpp"
#include "stages/tracking/tracking_stage.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

// Fig. 5.13 acceptance (as tests/collision/fig513_test.cpp): explicit Euler at 1 ms with a strong
// null-space motion keeps the TCP within 1.5 mm of the line.
constexpr double kFig513Tracking_m = 1.5e-3;
// Without a secondary objective the drift-compensated tracking stays on the line to a micrometre.
constexpr double kPlainTracking_m = 1e-6;
// The CSV holds 10 significant digits; quantities recomputed from its q agree to this.
constexpr double kCsvRecompute_m = 1e-7;
// Joint speeds from differences of CSV joint values (10 digits over a 1 ms step).
constexpr double kSpeedFromCsvRelative = 1e-5;
// The shipped sphere centre is written with 6 decimals in the study file.
constexpr double kCentreWritten_m = 1e-6;

const std::string kStudy = "studies/fig5_13_obstacle.toml";

// A CSV with numeric columns `numeric` and the text of every cell by column name.
struct RunCsv {
  io::CsvTable table;
  std::map<std::string, std::vector<std::string>> text;
};

RunCsv readRunCsv(const std::string& path, const std::vector<std::string>& numeric) {
  RunCsv r;
  r.table = io::readCsv(path, io::CsvSchema{numeric, {}});
  std::istringstream in(readFileOrThrow(path));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) header.push_back(c);
  }
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::size_t a = 0;
    for (std::size_t b; (b = line.find(',', a)) != std::string::npos; a = b + 1)
      cells.push_back(line.substr(a, b - a));
    cells.push_back(line.substr(a));
    REQUIRE(cells.size() == header.size());
    for (std::size_t i = 0; i < header.size(); ++i) r.text[header[i]].push_back(cells[i]);
  }
  return r;
}

RunOptions runOptions(const fs::path& root, int threads) {
  RunOptions ro;
  ro.output_root = root.string();
  ro.threads = threads;
  ro.overwrite = true;
  ro.progress = false;
  return ro;
}

const Model& studyModel(const Study& s, const std::string& name) {
  for (const auto& d : s.designs)
    if (d.model.name == name) return d.model;
  FAIL("no design " << name);
  throw 0;
}

}  // namespace

TEST_CASE("the shipped sphere sits where the Fig. 5.13 recipe puts it", "[tracking][thesis]") {
  // The middle of link j3 (frames j3 and j4) at the middle sample of the unweighted minimum-norm
  // run (no null-space term, W = I), plus (0.19, 0.08, 0.04) m.
  const Study s = loadStudy(test::sourcePath(kStudy));
  REQUIRE(stageSettings<std::vector<tracking::TrackingEntry>>(s, "tracking")->size() == 1);
  REQUIRE(s.obstacles.size() == 1);
  const tracking::TrackingEntry& e =
      stageSettings<std::vector<tracking::TrackingEntry>>(s, "tracking")->at(0);
  const Model& m = studyModel(s, e.design);
  const tracking::LineReference line = tracking::lineReference(m, e);
  KinematicsWorkspace ws(m);
  ik::TrackingOptions o;
  o.redundancy.alpha = e.redundancy.alpha;
  const ik::Reference ref = [&](double t) { return line(t); };
  const auto off = ik::trackReference(m, ws, ref, e.q0, e.duration_s, nullptr, nullptr, o);
  REQUIRE(off.status == ik::TrackingStatus::Completed);
  forwardKinematics(m, ws, off.samples[off.samples.size() / 2].q);
  const Eigen::Vector3d centre =
      0.5 * (ws.p_WF[2] + ws.p_WF[3]) + Eigen::Vector3d(0.19, 0.08, 0.04);
  INFO("recomputed centre: " << centre.transpose().format(Eigen::IOFormat(Eigen::FullPrecision)));
  CHECK(s.obstacles[0].type == SsvType::Point);
  CHECK((s.obstacles[0].p_W[0] - centre).norm() < kCentreWritten_m);
  CHECK(s.obstacles[0].radius_m == Approx(0.06).margin(1e-15));
}

TEST_CASE("thesis Fig. 5.13 from the shipped study: the plain run hits the sphere, H_c avoids it",
          "[tracking][thesis]") {
  const fs::path root = fs::temp_directory_path() / "armstudy_tracking_fig513";
  fs::remove_all(root);
  const Study s = loadStudy(test::sourcePath(kStudy));
  REQUIRE(stageSettings<std::vector<tracking::TrackingEntry>>(s, "tracking")->size() == 1);
  const tracking::TrackingEntry& e =
      stageSettings<std::vector<tracking::TrackingEntry>>(s, "tracking")->at(0);
  const Model& m = studyModel(s, e.design);
  const RunSummary a = runStudy(s, runOptions(root / "a", 2));
  const fs::path out = fs::path(a.output_dir) / "tracking";

  // Independent line: p0 = FK(q0 as read), p1 = p0 + the delta written in the study.
  KinematicsWorkspace ws(m);
  forwardKinematics(m, ws, e.q0);
  const Eigen::Vector3d p0 = ws.p_WT, p1 = p0 + Eigen::Vector3d(0.6, 0, 0);
  auto onLine = [&](double t) -> Eigen::Vector3d { return p0 + (p1 - p0) * (t / e.duration_s); };

  std::vector<std::string> numeric = {
      "t_s", "x_m", "y_m", "z_m", "position_error_m", "obstacle_distance_m", "self_distance_m"};
  for (const Joint& j : m.joints) numeric.push_back("q_" + j.name);
  collision::CollisionWorkspace cws(m);
  const auto summary = nlohmann::json::parse(readFileOrThrow((out / "summary.json").string()));
  REQUIRE(summary["entries"].size() == 1);
  const auto& runs = summary["entries"][0]["runs"];

  struct Recomputed {
    int rows = 0;
    double min_d = 1e9, max_err = 0, final_err = 0, last_t = 0;
    double max_speed_ratio = 0;  // from Euler steps q_k+1 = q_k + qdot_k dt (eq. 5.49)
    std::string pair;
    bool all_clear = true;
  };
  auto recompute = [&](const std::string& run) {
    const RunCsv csv = readRunCsv((out / ("fig5_13_" + run + ".csv")).string(), numeric);
    Recomputed r;
    r.rows = csv.table.rows();
    Eigen::VectorXd q(m.dof()), q_prev(m.dof());
    for (int k = 0; k < r.rows; ++k) {
      for (int i = 0; i < m.dof(); ++i) q[i] = csv.table.column("q_" + m.joints[i].name)[k];
      if (k > 0)
        for (int i = 0; i < m.dof(); ++i)
          r.max_speed_ratio = std::max(r.max_speed_ratio, std::abs(q[i] - q_prev[i]) * e.rate_Hz /
                                                              m.joints[i].limits.qd_max);
      q_prev = q;
      forwardKinematics(m, ws, q);
      collision::collisionDistances(m, ws, s.obstacles, cws);
      const double d = collision::minEnvironmentDistance(cws);
      const std::string pair = collision::pairName(m, cws.env[cws.closest_env], true, s.obstacles);
      CHECK(std::abs(d - csv.table.column("obstacle_distance_m")[k]) < kCsvRecompute_m);
      CHECK(pair == csv.text.at("obstacle_pair")[k]);
      CHECK(std::abs(collision::minSelfDistance(cws) - csv.table.column("self_distance_m")[k]) <
            kCsvRecompute_m);
      if (d < r.min_d) {
        r.min_d = d;
        r.pair = pair;
      }
      r.all_clear = r.all_clear && d > 0;
      const double t = csv.table.column("t_s")[k];
      r.last_t = t;
      const double err = (ws.p_WT - onLine(t)).norm();
      CHECK(std::abs(err - csv.table.column("position_error_m")[k]) < kCsvRecompute_m);
      r.max_err = std::max(r.max_err, err);
      r.final_err = (ws.p_WT - p1).norm();
    }
    return r;
  };

  const Recomputed plain = recompute("plain");
  INFO("plain: min distance " << plain.min_d << " (" << plain.pair << "), max TCP error "
                              << plain.max_err);
  CHECK(plain.rows == 4001);
  CHECK(plain.min_d < 0);  // the upper arm runs into the sphere
  CHECK(plain.pair == "j3-obstacle:sphere");
  CHECK(plain.max_err < kPlainTracking_m);
  CHECK(runs[0]["run"] == "plain");
  CHECK(runs[0]["completed"] == true);
  CHECK(runs[0]["collision_free"] == false);
  CHECK(runs[0]["min_obstacle_pair"] == plain.pair);
  CHECK(std::abs(runs[0]["min_obstacle_distance_m"].get<double>() - plain.min_d) < kCsvRecompute_m);
  CHECK(runs[0]["first_contact_pair"] == "j3-obstacle:sphere");
  CHECK(runs[0]["first_contact_s"].get<double>() > 0.5);  // clear at the start

  const Recomputed with = recompute("with_hc");
  INFO("with H_c: min distance " << with.min_d << " (" << with.pair << "), max TCP error "
                                 << with.max_err);
  CHECK(with.rows == 4001);
  CHECK(with.last_t == Approx(e.duration_s).margin(1e-12));
  CHECK(with.all_clear);                    // every sample clear of the sphere
  CHECK(with.max_err < kFig513Tracking_m);  // while the TCP stays on the line
  CHECK(with.final_err < kFig513Tracking_m);
  CHECK(runs[1]["run"] == "with_hc");
  CHECK(runs[1]["completed"] == true);
  CHECK(runs[1]["collision_free"] == true);
  CHECK(runs[1]["first_contact_s"].is_null());
  CHECK(std::abs(runs[1]["max_position_error_m"].get<double>() - with.max_err) < kCsvRecompute_m);
  // The reported peak joint speed matches the Euler steps of the written trajectory (its maximum
  // lies inside the run), and the avoidance stays within every joint's speed limit.
  CHECK(runs[1]["max_joint_speed_ratio"].get<double>() ==
        Approx(with.max_speed_ratio).epsilon(kSpeedFromCsvRelative));
  CHECK(runs[0]["max_joint_speed_ratio"].get<double>() >=
        plain.max_speed_ratio * (1 - kSpeedFromCsvRelative));
  CHECK(with.max_speed_ratio < 1.0);

  // Summary metrics for `armstudy check`.
  const auto& M = a.metrics.scalars;
  CHECK(M.at("tracking/fig5_13/plain/collision_free") == 0.0);
  CHECK(M.at("tracking/fig5_13/with_hc/collision_free") == 1.0);
  CHECK(M.at("tracking/fig5_13/with_hc/completed") == 1.0);
  CHECK(M.at("tracking/fig5_13/plain/min_obstacle_distance_m") < 0);
  CHECK(M.at("tracking/fig5_13/with_hc/min_obstacle_distance_m") > 0);
  CHECK(M.at("tracking/fig5_13/with_hc/max_tcp_error_m") < kFig513Tracking_m);

  // The ParaView scenes read back with VTK's XML reader.
  for (const std::string run : {"plain", "with_hc"}) {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName((out / ("fig5_13_" + run + ".vtp")).c_str());
    reader->Update();
    vtkPolyData* poly = reader->GetOutput();
    REQUIRE(poly->GetNumberOfPoints() > 0);
    vtkDataArray* time = poly->GetPointData()->GetArray("time");
    vtkDataArray* part = poly->GetPointData()->GetArray("part");
    vtkDataArray* contact = poly->GetPointData()->GetArray("in_contact");
    vtkDataArray* radius = poly->GetPointData()->GetArray("radius");
    REQUIRE(time);
    REQUIRE(part);
    REQUIRE(contact);
    REQUIRE(radius);
    int skeleton_points = 0, contact_points = 0;
    double max_time = 0;
    for (vtkIdType p = 0; p < poly->GetNumberOfPoints(); ++p) {
      double xyz[3];
      poly->GetPoint(p, xyz);
      const int k = static_cast<int>(part->GetTuple1(p));
      if (k == 2) ++skeleton_points;
      if (k == 2 && contact->GetTuple1(p) == 1) ++contact_points;
      if (k == 1) max_time = std::max(max_time, time->GetTuple1(p));
      if (k == 3) {  // obstacle: core point or on a circle of its radius around it
        const double dc = (Eigen::Vector3d(xyz[0], xyz[1], xyz[2]) - s.obstacles[0].p_W[0]).norm();
        CHECK((dc < 1e-12 || std::abs(dc - radius->GetTuple1(p)) < 1e-12));
      }
    }
    // 9 skeletons of base + 7 frame origins + TCP; lines: reference, TCP path, 9 skeletons, 3
    // circles.
    CHECK(skeleton_points == 9 * (m.dof() + 2));
    CHECK(poly->GetNumberOfLines() == 1 + 1 + 9 + 3);
    CHECK(max_time == Approx(e.duration_s).margin(1e-12));
    if (run == "plain")
      CHECK(contact_points > 0);  // some snapshot shows the collision
    else
      CHECK(contact_points == 0);
  }

  // Byte-identical result files with another thread count (timings only in the manifest).
  const RunSummary b = runStudy(s, runOptions(root / "b", 1));
  REQUIRE(a.files_written == b.files_written);
  int compared = 0;
  for (const std::string& f : a.files_written) {
    if (f.rfind("tracking/", 0) != 0) continue;
    ++compared;
    INFO(f);
    CHECK(readFileOrThrow((fs::path(a.output_dir) / f).string()) ==
          readFileOrThrow((fs::path(b.output_dir) / f).string()));
  }
  // Per run csv, vtp, pvd and its 31 step .vtp (docs/tracking.md); 2 plots, report, summary.
  CHECK(compared == 2 * (3 + 31) + 2 + 2);
  fs::remove_all(root);
}

TEST_CASE("the shipped Fig. 5.13 study passes `armstudy check` against its committed baseline",
          "[tracking][regression]") {
  // The fixture "shipped: fig5_13_obstacle" runs the check once per suite (tests/CMakeLists.txt).
  const nlohmann::json check = test::shippedCheck("fig5_13_obstacle");
  CHECK(check.at("passed").get<bool>());
  CHECK(check.at("rows").size() == 14);
}

namespace {

fs::path writeStudy(const fs::path& dir, const std::string& body) {
  fs::create_directories(dir);
  const fs::path p = dir / "study.toml";
  std::ofstream(p) << "[study]\nname = \"t\"\n[[design]]\nfile = \""
                   << test::sourcePath("designs/final_prototype_7dof.toml") << "\"\n"
                   << body;
  return p;
}

}  // namespace

TEST_CASE("a joint that leaves its limits stops the run and is named", "[tracking]") {
  // The plain Fig. 5.13 motion moves j2 by a known amount; a variant whose j2 limit sits halfway
  // along that motion must stop there with joint_limit_reached (j2) while the other run may not.
  const fs::path dir = fs::temp_directory_path() / "armstudy_tracking_limit";
  fs::remove_all(dir);
  const std::string entry = R"(
[[tracking]]
name = "short"
design = "DESIGN"
q0 = [0, 0.2, 0.3, 1.2, 0, 0.6, 0]
delta = ["0.3 m", 0, 0]
duration = 1.0
[tracking.nullspace]
gain = 10
[tracking.avoidance]
safety_distance = "50 mm"
)";
  auto withDesign = [&](const std::string& d) {
    std::string s = entry;
    s.replace(s.find("DESIGN"), 6, d);
    return s;
  };
  const Study free = loadStudy(writeStudy(dir, withDesign("final_prototype_7dof")).string());
  const Model& m = studyModel(free, "final_prototype_7dof");
  const tracking::EntryResult r0 = tracking::evaluateTrackingEntry(
      m, stageSettings<std::vector<tracking::TrackingEntry>>(free, "tracking")->at(0));
  REQUIRE(r0.plain.completed());
  CHECK(r0.plain.collisionFree());  // no obstacles here: self distances only
  CHECK(std::isinf(r0.plain.min_obstacle_distance_m));
  // Joint j2 (index 1): where does it end, and which way does it move?
  const double q_start = r0.plain.samples.front().q[1], q_end = r0.plain.samples.back().q[1];
  REQUIRE(std::abs(q_end - q_start) > 0.02);
  const double limit = 0.5 * (q_start + q_end);
  const std::string key = q_end > q_start ? "joint.j2.max" : "joint.j2.min";
  std::ostringstream v;
  v.precision(17);
  v << "[[variant]]\nof = \"final_prototype_7dof\"\nset = { \"" << key << "\" = " << limit
    << " }\n";
  const std::string variant = variantName("final_prototype_7dof", {{key, limit}});
  const Study lim = loadStudy(writeStudy(dir, v.str() + withDesign(variant)).string());
  const tracking::EntryResult r1 = tracking::evaluateTrackingEntry(
      studyModel(lim, variant),
      stageSettings<std::vector<tracking::TrackingEntry>>(lim, "tracking")->at(0));
  CHECK(r1.plain.status == ik::TrackingStatus::JointLimitReached);
  CHECK(r1.plain.limit_joint == 1);
  CHECK(r1.plain.statusText(m) == "joint_limit_reached (j2)");
  CHECK(!r1.plain.completed());
  REQUIRE(!r1.plain.samples.empty());
  CHECK(r1.plain.samples.back().t < 1.0);
  // Every recorded sample is within the limit; the motion up to there is the free one.
  for (std::size_t k = 0; k < r1.plain.samples.size(); ++k) {
    CHECK(
        (q_end > q_start ? r1.plain.samples[k].q[1] <= limit : r1.plain.samples[k].q[1] >= limit));
    CHECK((r1.plain.samples[k].q - r0.plain.samples[k].q).norm() == 0.0);
  }
  // Through the stage: the completed metric and the status in summary.json.
  const RunSummary sum = runStudy(lim, runOptions(dir / "out", 2));
  CHECK(sum.metrics.scalars.at("tracking/short/plain/completed") == 0.0);
  const auto j = nlohmann::json::parse(
      readFileOrThrow((fs::path(sum.output_dir) / "tracking" / "summary.json").string()));
  CHECK(j["entries"][0]["runs"][0]["status"] == "joint_limit_reached");
  CHECK(j["entries"][0]["runs"][0]["limit_joint"] == "j2");
  // The stop rests on the design's joint limits: its assumption about them is listed.
  const std::string md = readFileOrThrow((fs::path(sum.output_dir) / "report.md").string());
  const auto listed = md.find("## Assumptions");
  REQUIRE(listed != std::string::npos);
  CHECK(md.find("`" + variant + "`: Joint limits are not given", listed) != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("bad [[tracking]] input is an InputError with file, line and key, and nothing is written",
          "[tracking][input]") {
  const fs::path dir = fs::temp_directory_path() / "armstudy_tracking_bad";
  fs::remove_all(dir);
  const std::string good = R"(
[[obstacle]]
name = "ball"
type = "sphere"
points = [[0.4, 0.8, 0.9]]
radius = "50 mm"

[[tracking]]
name = "line"
design = "final_prototype_7dof"
q0 = [0, 0.2, 0.3, 1.2, 0, 0.6, 0]
task_space = "position"
delta = ["0.2 m", 0, 0]
duration = 1.0
obstacles = ["ball"]
[tracking.nullspace]
gain = 10
[tracking.avoidance]
safety_distance = "100 mm"
weight = 2
self = true
)";
  REQUIRE_NOTHROW(loadStudy(writeStudy(dir, good).string()));
  struct Case {
    std::string from, to, key, from2 = "", to2 = "";
  };
  const Case cases[] = {
      {"design = \"final_prototype_7dof\"", "design = \"nope\"", "tracking[0].design"},
      {"obstacles = [\"ball\"]", "obstacles = [\"bal\"]", "tracking[0].obstacles"},
      {"obstacles = [\"ball\"]", "obstacles = [\"ball\", \"ball\"]", "tracking[0].obstacles"},
      {"q0 = [0, 0.2, 0.3, 1.2, 0, 0.6, 0]", "q0 = [0, 0.2, 0.3, 1.2, 0, 0.6]", "tracking[0].q0"},
      {"q0 = [0, 0.2, 0.3, 1.2, 0, 0.6, 0]", "q0 = [0, 0.2, 0.3, 1.2, 0, 0.6, \"400 deg\"]",
       "tracking[0].q0"},
      {"q0 = [0, 0.2, 0.3, 1.2, 0, 0.6, 0]", "q0 = [\"5 m\", 0.2, 0.3, 1.2, 0, 0.6, 0]",
       "tracking[0].q0"},
      {"q0 = [0, 0.2, 0.3, 1.2, 0, 0.6, 0]", "q0 = [\"10 deg\", 0.2, 0.3, 1.2, 0, 0.6, 0]",
       "tracking[0].q0"},
      {"duration = 1.0", "duration = 0", "tracking[0].duration"},
      {"duration = 1.0", "duration = -1.0", "tracking[0].duration"},
      {"duration = 1.0", "duration = \"1 s\"", "tracking[0].duration"},
      {"duration = 1.0", "duration = 1.0\nrate = 0", "tracking[0].rate"},
      {"safety_distance = \"100 mm\"", "safety_distance = \"-100 mm\"",
       "tracking[0].avoidance.safety_distance"},
      {"safety_distance = \"100 mm\"", "safety_distance = 0",
       "tracking[0].avoidance.safety_distance"},
      {"weight = 2", "weight = 0", "tracking[0].avoidance.weight"},
      {"weight = 2", "weight = 2\nblend = 1.5", "tracking[0].avoidance.blend"},
      {"gain = 10", "gain = -1", "tracking[0].nullspace.gain"},
      {"gain = 10", "gain = 10\njoint_weights = [1, 1]", "tracking[0].nullspace.joint_weights"},
      {"duration = 1.0", "duration = 1.0\ndurration = 2", "tracking[0].durration"},
      {"gain = 10", "gain = 10\ngian = 1", "tracking[0].nullspace.gian"},
      {"weight = 2", "weight = 2\nsafety = 1", "tracking[0].avoidance.safety"},
      {"delta = [\"0.2 m\", 0, 0]", "delta = [\"0.2 m\", 0, 0]\nto = [1, 1, 1]", "tracking[0].to"},
      {"delta = [\"0.2 m\", 0, 0]", "", "tracking[0].delta"},
      {"delta = [\"0.2 m\", 0, 0]", "delta = [\"0.2 deg\", 0, 0]", "tracking[0].delta"},
      {"task_space = \"position\"", "task_space = \"joint\"", "tracking[0].task_space"},
      {"task_space = \"position\"", "task_space = \"full\"\nstop_at_joint_limit = 1",
       "tracking[0].stop_at_joint_limit"},
      {"duration = 1.0", "duration = 1.0\nsnapshots = -1", "tracking[0].snapshots"},
      {"name = \"line\"", "name = \"a line\"", "tracking[0].name"},
      {"obstacles = [\"ball\"]", "obstacles = []", "tracking[0].avoidance", "self = true",
       "self = false"},
      {"self = true", "self = \"yes\"", "tracking[0].avoidance.self"},
  };
  for (const Case& c : cases) {
    std::string body = good;
    REQUIRE(body.find(c.from) != std::string::npos);
    body.replace(body.find(c.from), c.from.size(), c.to);
    if (!c.from2.empty()) body.replace(body.find(c.from2), c.from2.size(), c.to2);
    const std::string path = writeStudy(dir, body).string();
    INFO(c.to);
    try {
      (void)loadStudy(path);
      FAIL("no InputError");
    } catch (const InputError& e) {
      INFO(e.what());
      CHECK(e.file() == path);
      CHECK(e.line() > 3);
      CHECK(e.key() == c.key);
    }
  }
  // A second entry with the same name.
  {
    const std::string path =
        writeStudy(dir, good + good.substr(good.find("[[tracking]]"))).string();
    try {
      (void)loadStudy(path);
      FAIL("no InputError for a duplicate name");
    } catch (const InputError& e) {
      CHECK(e.key() == "tracking[1].name");
    }
  }
  // Through the CLI: exit 2, the message names file, line and key, and nothing is written.
  std::string body = good;
  body.replace(body.find("duration = 1.0"), 14, "duration = 0");
  const std::string path = writeStudy(dir, body).string();
  std::string out;
  CHECK(test::runCommand(
            test::binaryPath() + " run " + path + " --output " + (dir / "out").string(), out) == 2);
  CHECK(out.find("tracking[0].duration") != std::string::npos);
  CHECK(!fs::exists(dir / "out" / "t"));
  fs::remove_all(dir);
}
