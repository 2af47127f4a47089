// Design-space exploration (docs/exploration.md): the geometry that follows a variant's link
// lengths, the Pareto front against a brute force, determinism and resume.
#include "stages/explore/explore.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "collision/distance.hpp"
#include "common/errors.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "io/variant.hpp"
#include "model/geometry_follows.hpp"
#include "study/stage.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

// A point counts as inside a volume when it is within the radius of its core, up to this [m].
constexpr double kInsideTolerance_m = 1e-12;
// Points sampled along each link segment.
constexpr int kSegmentSamples = 50;

double distanceToCore(const CollisionVolume& v, const Eigen::Vector3d& p) {
  Eigen::Vector3d closest;
  switch (v.type) {
    case SsvType::Point:
      return (p - v.p_L[0]).norm();
    case SsvType::Line:
      return std::sqrt(collision::squaredDistancePointSegment(p, v.p_L[0], v.p_L[1], closest));
    case SsvType::Triangle:
      return std::sqrt(
          collision::squaredDistancePointTriangle(p, v.p_L[0], v.p_L[1], v.p_L[2], closest));
  }
  return 1e300;
}

// Fraction of the segment from the origin of body `link` to `end` (its frame) that lies inside the
// union of the body's volumes.
double coveredFraction(const Model& m, int link, const Eigen::Vector3d& end) {
  int inside = 0;
  for (int s = 0; s <= kSegmentSamples; ++s) {
    const Eigen::Vector3d p = end * (double(s) / kSegmentSamples);
    bool in = false;
    for (const CollisionVolume& v : m.collision.volumes)
      in |= v.link == link && distanceToCore(v, p) <= v.radius_m + kInsideTolerance_m;
    inside += in;
  }
  return double(inside) / (kSegmentSamples + 1);
}

Eigen::Vector3d linkEnd(const Model& m, int link) {
  const PoseXYZABG& p = link + 1 < m.dof() ? m.joints[link + 1].offset : m.tcp;
  return {p.x, p.y, p.z};
}

std::map<std::string, std::string> resultFiles(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), dir).string();
    if (rel == "manifest.json" || rel.rfind(".partial", 0) == 0) continue;
    out[rel] = readFileOrThrow(e.path().string());
  }
  return out;
}

fs::path freshDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() /
                     ("armstudy_explore_test_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string write(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
  return p.string();
}

// A small spraying row for the first prototype (6-DoF): cheap enough for a brute force.
std::string reachStudy(const std::string& name, const std::string& extra) {
  return "[study]\nname = \"" + name + "\"\n[[design]]\nfile = \"" +
         sourcePath("designs/first_prototype_6dof.toml") + "\"\n" + extra + R"(
[reach]
task_space = "spraying"
position_tolerance = "1 mm"
orientation_tolerance = "0.5 deg"
[[reach.grid]]
name = "row"
x = { from = "-0.6 m", to = "0.6 m", step = "0.2 m" }
y = { from = "0.5 m", to = "1.1 m", step = "0.2 m" }
z = "1.2 m"
alpha = "0 deg"
gamma = "0 deg"
)";
}

const char* kParams = R"(
[[explore.parameter]]
key = "joint.j4.x"
values = ["0.13 m", "0.23 m", "0.33 m"]
[[explore.parameter]]
key = "joint.j5.x"
values = ["0.3 m", "0.4 m", "0.5 m"]
)";

const char* kObjectives = R"(
[[explore.objective]]
label = "row coverage"
metric = "reach/row/{design}/reachable_fraction"
goal = "max"
[[explore.objective]]
label = "manipulability"
metric = "reach/row/{design}/manipulability_mean"
goal = "max"
[[explore.objective]]
label = "link length"
metric = "cost/link_length"
goal = "min"
)";

std::string exploreStudy(const fs::path& dir, const std::string& name) {
  return write(dir / (name + ".toml"),
               reachStudy(name, "") +
                   "[explore]\ndesign = \"first_prototype_6dof\"\nfront_designs = 1\n" + kParams +
                   kObjectives);
}

}  // namespace

TEST_CASE("a variant's collision volumes move and stretch with its links and contain them",
          "[explore][collision]") {
  const Model base = loadDesign(sourcePath("designs/final_prototype_7dof.toml"));
  // Upper arm and forearm longer, shoulder offset shorter, forearm offset changed on a second
  // axis, TCP further out: every kind of link end the rule handles.
  const Overrides ov{{"joint.j4.x", 0.45},
                     {"joint.j7.x", 0.55},
                     {"joint.j7.y", -0.06},
                     {"joint.j2.y", 0.40},
                     {"tcp.z", 0.18}};
  const Model v = deriveVariant(base, ov, "test", 1);
  REQUIRE(v.collision.volumes.size() == base.collision.volumes.size());
  int checked = 0;
  for (int link = 0; link < v.dof(); ++link) {
    const Eigen::Vector3d a_old = linkEnd(base, link), a_new = linkEnd(v, link);
    bool has = false;
    for (const CollisionVolume& c : v.collision.volumes) has |= c.link == link;
    if (!has) continue;
    INFO("link " << v.joints[link].name);
    CHECK(coveredFraction(base, link, a_old) == 1.0);  // the design's own volumes contain its links
    CHECK(coveredFraction(v, link, a_new) == 1.0);     // and the variant's contain the new ones
    if (a_new.norm() > a_old.norm() + 0.05) {
      CHECK(coveredFraction(base, link, a_new) <
            1.0);  // the old volumes would not (the test bites)
      ++checked;
    }
  }
  CHECK(checked == 3);  // lengthened: j3 (upper arm), j4 (forearm), j9 (TCP); j1 got shorter
  // Notes say what was adapted; volumes of unchanged links are untouched.
  int notes = 0;
  for (const auto& a : v.assumptions) notes += a.rfind("Geometry follows", 0) == 0;
  CHECK(notes == 4);
  for (std::size_t k = 0; k < v.collision.volumes.size(); ++k)
    if (v.collision.volumes[k].link == 1 || v.collision.volumes[k].link == -1)
      CHECK(v.collision.volumes[k].p_L == base.collision.volumes[k].p_L);
}

TEST_CASE("the stretch maps the link origin and end exactly and re-estimates inertias",
          "[explore]") {
  const Eigen::Vector3d a_old(0.4, -0.0295, -0.043), a_new(0.5, -0.06, -0.043);
  CHECK((stretchPoint(Eigen::Vector3d::Zero(), a_old, a_new)).norm() == 0.0);
  CHECK((stretchPoint(a_old, a_old, a_new) - a_new).norm() < kHandCheckTolerance);
  // A housing beyond the end moves rigidly with it along x.
  const Eigen::Vector3d h(0.45, -0.0295, -0.043);
  CHECK(std::abs(stretchPoint(h, a_old, a_new).x() - 0.55) < kHandCheckTolerance);

  // A slender rod along x (I = diag(1e-4, 0.04, 0.04)) stretched by s = 1.5: its second moment
  // Sigma = tr(I)/2 E - I = diag(0.03995, 5e-5, 5e-5) scales by s^2 along x, so I_yy = I_zz =
  // 2.25 * 0.03995 + 5e-5 (about s^2 times the rod's m L^2 / 12), I_xx stays; the mass is kept.
  Model m = parseDesign(R"([design]
name = "rod"
[[joint]]
name = "a"
type = "revolute"
x = 0
y = 0
z = 0
alpha = 0
beta = 0
gamma = 0
min = -1
max = 1
[[joint]]
name = "b"
type = "revolute"
x = 0.4
y = 0
z = 0
alpha = 0
beta = 0
gamma = 0
min = -1
max = 1
[tcp]
x = 0.1
[[inertia]]
link = "a"
mass = 3.0
com = [0.2, 0, 0]
inertia = [1e-4, 0.04, 0.04, 0, 0, 0]
[[inertia]]
link = "b"
mass = 1.0
inertia = [0.01, 0.01, 0.01, 0, 0, 0]
)",
                        "rod");
  const Model v = deriveVariant(m, {{"joint.b.x", 0.6}}, "test", 1);
  CHECK(v.inertias[0].mass_kg == 3.0);
  CHECK(std::abs(v.inertias[0].p_com_m.x() - 0.3) < kHandCheckTolerance);
  const double transverse = 2.25 * 0.03995 + 5e-5;
  CHECK(std::abs(v.inertias[0].I_com_kgm2(0, 0) - 1e-4) < kHandCheckTolerance);
  CHECK(std::abs(v.inertias[0].I_com_kgm2(1, 1) - transverse) < kHandCheckTolerance);
  CHECK(std::abs(v.inertias[0].I_com_kgm2(2, 2) - transverse) < kHandCheckTolerance);
  CHECK(v.inertias[1].I_com_kgm2 == m.inertias[1].I_com_kgm2);  // link b did not change
}

TEST_CASE("the non-dominated set of hand-made candidates", "[explore]") {
  std::vector<explore::Objective> obj(3);
  obj[0].goal = explore::Goal::Maximise;
  obj[1].goal = explore::Goal::Minimise;
  obj[2].goal = explore::Goal::None;  // a constraint only: not part of dominance
  auto cand = [](std::vector<double> v, bool feasible = true) {
    explore::Candidate c;
    c.values = std::move(v);
    c.feasible = feasible;
    return c;
  };
  const std::vector<explore::Candidate> c{
      cand({1, 1, 0}),         // 0 front
      cand({2, 2, 5}),         // 1 front
      cand({1, 2, 0}),         // 2 dominated by 0 and 1
      cand({2, 2, -5}),        // 3 equal to 1: both stay
      cand({3, 0, 0}, false),  // 4 would dominate all, but infeasible
      cand({0.5, 0.5, 0}),     // 5 front (best in the second goal)
  };
  CHECK(explore::paretoFront(c, obj) == std::vector<std::size_t>{0, 1, 3, 5});
}

TEST_CASE("the explore front equals the brute-force front of the same variants",
          "[explore][slow]") {
  const fs::path dir = freshDir("brute");
  // Explore: exhaustive over 3 x 3 values.
  const Study ex = loadStudy(exploreStudy(dir, "explore_small"));
  const StageResult er = runStage(ex, "explore", (dir / "ex").string());
  // Brute force: the same variants as an ordinary [[variant]] sweep through the reach stage, the
  // front computed here from the metrics.
  const Study bf = loadStudy(write(dir / "brute.toml", reachStudy("brute", R"(
[[variant]]
of = "first_prototype_6dof"
sweep = { "joint.j4.x" = ["0.13 m", "0.23 m", "0.33 m"], "joint.j5.x" = ["0.3 m", "0.4 m", "0.5 m"] }
)")));
  REQUIRE(bf.designs.size() == 10);
  const StageResult br = runStage(bf, "reach", (dir / "bf").string());
  std::vector<std::array<double, 3>> v;  // larger is better
  for (const StudyDesign& d : bf.designs) {
    const std::string p = "reach/row/" + d.model.name + "/";
    v.push_back({br.metrics.scalars.at(p + "reachable_fraction"),
                 br.metrics.scalars.at(p + "manipulability_mean"),
                 -explore::totalLinkLength(d.model)});
  }
  std::set<std::string> expected;
  for (std::size_t i = 0; i < v.size(); ++i) {
    bool dominated = false;
    for (std::size_t j = 0; j < v.size(); ++j) {
      bool ge = true, gt = false;
      for (int k = 0; k < 3; ++k) ge &= v[j][k] >= v[i][k], gt |= v[j][k] > v[i][k];
      dominated |= ge && gt;
    }
    if (!dominated) expected.insert(bf.designs[i].model.name);
  }
  std::set<std::string> got;
  for (const auto& [k, x] : er.metrics.scalars)
    if (k.rfind("explore/front/", 0) == 0) got.insert(k.substr(14, k.rfind('/') - 14));
  CHECK(er.metrics.scalars.at("explore/evaluations") == 10);
  CHECK(got == expected);
  CHECK(er.metrics.scalars.at("explore/front_size") == static_cast<double>(expected.size()));
  // The front design's file loads and is the variant.
  bool design_file = false;
  for (const std::string& f : er.files)
    if (f.rfind("explore/front/", 0) == 0 && f.size() > 5 && f.substr(f.size() - 5) == ".toml") {
      const Model m = loadDesign((dir / "ex" / f).string());
      for (const std::string& e : expected) design_file |= m.name == explore::fileSafeName(e);
    }
  CHECK(design_file);
  fs::remove_all(dir);
}

TEST_CASE("an exploration is the same with 1 and 2 threads and resumes after losing units",
          "[explore][slow]") {
  const fs::path dir = freshDir("det");
  // NLopt search (DIRECT_L then BOBYQA) within a small budget.
  const std::string path = write(dir / "opt.toml", reachStudy("opt", "") + R"([explore]
design = "first_prototype_6dof"
method = "optimise"
budget = 12
front_designs = 1
[[explore.parameter]]
key = "joint.j4.x"
from = "0.13 m"
to = "0.33 m"
step = "0.02 m"
[[explore.parameter]]
key = "joint.j5.x"
from = "0.3 m"
to = "0.5 m"
[[explore.constraint]]
terms = { "joint.j4.x" = 1, "joint.j5.x" = 1 }
max = "0.8 m"
)" + kObjectives);
  const Study s = loadStudy(path);
  RunOptions one, two;
  one.threads = 1;
  two.threads = 2;
  runStage(s, "explore", (dir / "t1").string(), one);
  runStage(s, "explore", (dir / "t2").string(), two);
  const auto ref = resultFiles(dir / "t1");
  REQUIRE(ref.count("explore/candidates.csv") == 1);
  CHECK(ref == resultFiles(dir / "t2"));
  // The budget counts candidates the stages evaluated, not NLopt's calls (revisits of snapped
  // points and constraint-breaking points are free): the phases' evaluations, the candidates
  // written (one line each, plus the header and the base design) and the budget agree.
  {
    const std::string& md = ref.at("explore/explore.md");
    const std::regex phase(R"(\((\d+) evaluations in (\d+) calls, ([^)]+)\))");
    std::vector<std::array<std::string, 3>> phases;
    for (auto it = std::sregex_iterator(md.begin(), md.end(), phase); it != std::sregex_iterator();
         ++it)
      phases.push_back({(*it)[1], (*it)[2], (*it)[3]});
    REQUIRE(phases.size() == 2);  // DIRECT_L, then BOBYQA
    const int global = std::stoi(phases[0][0]), polish = std::stoi(phases[1][0]);
    CHECK(std::stoi(phases[0][1]) >= global);
    CHECK(global <= 9);  // (1 - 0.25) x 12
    CHECK(polish <= 3);
    if (phases[0][2] == "budget spent") CHECK(global == 9);
    const std::string& csv = ref.at("explore/candidates.csv");
    CHECK(static_cast<int>(std::count(csv.begin(), csv.end(), '\n')) == 1 + 1 + global + polish);
  }

  // Killed midway (simulated: every second saved unit lost), resumed: the same files.
  const std::string out = (dir / "resumed").string();
  std::string msg;
  {
    CheckpointStore store(out, "fp\n", msg);
    CHECK(runStage(s, "explore", out, two, &store).units_resumed == 0);
  }
  std::vector<fs::path> units;
  for (const auto& e : fs::recursive_directory_iterator(fs::path(out) / ".partial"))
    if (e.path().extension() == ".unit") units.push_back(e.path());
  std::sort(units.begin(), units.end());
  REQUIRE(units.size() > 4);
  for (std::size_t k = 1; k < units.size(); k += 2) fs::remove(units[k]);
  fs::remove_all(fs::path(out) / "explore");
  CheckpointStore store(out, "fp\n", msg);
  CHECK(runStage(s, "explore", out, one, &store).units_resumed > 0);
  CHECK(resultFiles(out) == ref);
  fs::remove_all(dir);
}

namespace {

// The rows of candidates.csv by name: its cells after the name.
std::map<std::string, std::vector<std::string>> csvRows(const std::string& csv) {
  std::map<std::string, std::vector<std::string>> rows;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    for (std::istringstream r(line); std::getline(r, line, ',');) cells.push_back(line);
    const std::string name = cells.front();
    cells.erase(cells.begin());
    rows[name] = cells;
  }
  return rows;
}

// The exploration's outputs on its front: candidates.csv reads back to the very values the run
// computed (its metrics); the answer names, per objective with a goal, a front design whose value
// is the front's best (found here from the CSV) with all its objective values; the report names
// the parameters as the study does.
void checkFrontOutputs(const Study& s, const StageResult& r, const std::string& csv,
                       const std::string& md) {
  const auto& o = *stageSettings<explore::ExploreOptions>(s, "explore");
  const std::size_t np = o.parameters.size(), no = o.objectives.size();
  const auto rows = csvRows(csv);
  std::vector<std::string> front;
  for (const auto& [name, cells] : rows) {
    REQUIRE(cells.size() == np + no + 3);
    if (cells[np + no + 1] != "1") continue;
    front.push_back(name);
    for (std::size_t k = 0; k < no; ++k)  // exactly the run's value, not a rounded one
      CHECK(std::stod(cells[np + k]) ==
            r.metrics.scalars.at("explore/front/" + name + "/" + std::to_string(k)));
  }
  REQUIRE(!front.empty());
  REQUIRE(r.answer.size() == 1);
  const std::string& a = r.answer[0];
  for (std::size_t k = 0; k < no; ++k) {
    if (o.objectives[k].goal == explore::Goal::None) continue;
    const double sign = o.objectives[k].goal == explore::Goal::Minimise ? -1 : 1;
    double best = -1e300;
    for (const std::string& n : front) best = std::max(best, sign * std::stod(rows.at(n)[np + k]));
    const std::string lead =
        "best " + o.objectives[k].label.substr(0, o.objectives[k].label.find(" [")) + ": `";
    const auto at = a.find(lead);
    INFO(a);
    REQUIRE(at != std::string::npos);
    const auto b = at + lead.size();
    const std::string name = a.substr(b, a.find('`', b) - b);
    REQUIRE(rows.count(name));
    CHECK(sign * std::stod(rows.at(name)[np + k]) == best);
    const std::string values = a.substr(b, a.find(')', b) - b);
    for (const auto& ob : o.objectives) CHECK(values.find(ob.label + " ") != std::string::npos);
  }
  CHECK(a.find("balanced: `") != std::string::npos);
  for (const auto& p : o.parameters) {
    CHECK(p.label != p.key);
    CHECK(md.find(">" + p.label + " [m]") == std::string::npos);  // table headers, not raw
    CHECK(md.find("| " + p.label + " [m]") != std::string::npos);
  }
}

}  // namespace

TEST_CASE(
    "the shipped exploration study, made fast, runs and places the thesis design against its front",
    "[explore][slow]") {
  // studies/explore_final_prototype.toml with a coarse stem map, 2 fruits, short approaches and a
  // budget of 6 calls; everything else (parameters, constraint, objectives, search) as shipped.
  std::string text = readFileOrThrow(sourcePath("studies/explore_final_prototype.toml"));
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
  };
  replace("../designs/", sourcePath("designs/"));
  replace(R"(step = "10 deg")", R"(step = "30 deg")");
  replace(R"(z = { min = "0 m", max = "1.5 m", step = "5 cm" })",
          R"(z = { min = "0.3 m", max = "1.3 m", step = "25 cm" })");
  replace("stems = 4", "stems = 1");
  replace("duration = 2.0", "duration = 0.5");
  replace("rate = 500", "rate = 200");
  replace("budget = 80", "budget = 6");
  replace("front_designs = 3", "front_designs = 1");
  const fs::path dir = freshDir("shipped");
  const Study s = loadStudy(write(dir / "explore_final_prototype.toml", text));
  // Asked for previews of progressive maps, the candidates' stem maps show none (they are not
  // what a person waits for).
  RunOptions ro;
  ro.preview_stride = 2;
  int previews = 0;
  ro.on_preview = [&](const std::string&) { ++previews; };
  const StageResult r = runStage(s, "explore", (dir / "out").string(), ro);
  CHECK(previews == 0);
  CHECK(r.metrics.scalars.at("explore/evaluations") >= 3);
  CHECK(r.metrics.scalars.at("explore/front_size") >= 1);
  const std::string md = readFileOrThrow((dir / "out/explore/explore.md").string());
  CHECK(md.find("## Pareto front") != std::string::npos);
  CHECK(md.find("final_prototype_7dof (base design)") != std::string::npos);
  CHECK((md.find("The base design is on the front") != std::string::npos ||
         md.find("The base design is dominated by") != std::string::npos));
  const std::string csv = readFileOrThrow((dir / "out/explore/candidates.csv").string());
  CHECK(csv.rfind("name,joint.j4.x,joint.j7.x,joint.j2.y,joint.j1.z,stem map coverage", 0) == 0);
  checkFrontOutputs(s, r, csv, md);
  fs::remove_all(dir);
}

TEST_CASE("explore sections with bad input are refused with file, line and key", "[explore]") {
  const fs::path dir = freshDir("bad");
  auto fails = [&](const std::string& section, const std::string& what) {
    const std::string p = write(dir / "bad.toml", reachStudy("bad", "") + section);
    try {
      loadStudy(p);
    } catch (const InputError& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(what) != std::string::npos);
      return;
    }
    FAIL("accepted: " << section);
  };
  const std::string head = "[explore]\ndesign = \"first_prototype_6dof\"\n";
  fails(head + kObjectives, "explore.parameter");
  fails(head + kParams, "explore.objective");
  fails("[explore]\ndesign = \"nope\"\n" + std::string(kParams) + kObjectives,
        "not part of the study");
  fails(head + "[[explore.parameter]]\nkey = \"joint.j9.x\"\nvalues = [1]\n" + kObjectives,
        "no joint named 'j9'");
  fails(head + kParams +
            "[[explore.objective]]\nmetric = \"reach/row/reachable_fraction\"\ngoal = \"max\"\n",
        "{design}");
  fails(head + kParams + kObjectives +
            "[[explore.constraint]]\nterms = { \"joint.j1.z\" = 1 }\nmax = 1\n",
        "is not a parameter");
  fails(head + "stages = [\"harvest\"]\n" + kParams + kObjectives, "no [harvest] section");
  fails(head + kParams +
            "[[explore.objective]]\nmetric = \"cost/link_length\"\ngoal = \"min\"\n"
            "resolution = -0.1\n",
        "resolution must be 0 or more");
  fs::remove_all(dir);
}

TEST_CASE("an exploration killed midway (SIGKILL) resumes into the files of an uninterrupted run",
          "[explore][slow][e2e]") {
  const fs::path dir = freshDir("kill");
  const std::string study = exploreStudy(dir, "k");
  std::string log;
  REQUIRE(
      runCommand(binaryPath() + " run " + study + " --threads 1 --output " + (dir / "ref").string(),
                 log) == 0);
  const fs::path out = dir / "out/k";
  auto exploreUnits = [&] {
    long n = 0;
    std::error_code ec;
    for (fs::directory_iterator it(out / ".partial/units", ec), end; !ec && it != end;
         it.increment(ec))
      n += it->path().filename().string().rfind("explore_", 0) == 0;
    return n;
  };
  // Killed with SIGKILL right after its sixth saved unit (the checkpoint store's test hook). Saved
  // in order: the reach stage's unit, the base design's exploration unit, then for each candidate
  // its reach unit and its exploration unit; so three of the 10 exploration units (the base and
  // two of the 9 grid points) are saved.
  const int killed = runKilledAfterUnits(
      binaryPath() + " run " + study + " --threads 1 --output " + (dir / "out").string(), 6, log);
  {
    INFO(log);
    REQUIRE(killed == kKilledStatus);
  }
  REQUIRE_FALSE(fs::exists(out / "manifest.json"));
  CHECK(exploreUnits() == 3);
  // Resumed with another thread count.
  REQUIRE(
      runCommand(binaryPath() + " run " + study + " --threads 2 --output " + (dir / "out").string(),
                 log) == 0);
  INFO(log);
  CHECK(log.find("resuming:") != std::string::npos);
  CHECK(resultFiles(out) == resultFiles(dir / "ref/k"));
  fs::remove_all(dir);
}
