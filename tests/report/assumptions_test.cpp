// Assumptions on the page (shipped harvest_torque study): each fruit a design misses because its
// tracking reached a joint limit is named in the answer with that joint and the limit, marked as an
// assumed limit when the design says its joint limits are assumed; the design assumption lines
// the misses rest on and the study's own [study] assumptions are listed under the answer in
// report.md and report.html.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/study_file.hpp"
#include "io/files.hpp"
#include "model/model_notes.hpp"
#include "shipped_output.hpp"
#include "test_support.hpp"

using namespace armstudy;
namespace fs = std::filesystem;

namespace {

constexpr double kDegreeTolerance = 0.5;  // [deg] the answer writes a limit in whole degrees

// The fruits of <design>_fruits.csv that stopped at a joint limit, with the joint the CSV names.
std::map<int, std::string> limitStops(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> head;
  for (std::istringstream h(line); std::getline(h, line, ',');) head.push_back(line);
  const auto col = [&](const std::string& n) {
    const auto at = std::find(head.begin(), head.end(), n);
    REQUIRE(at != head.end());
    return static_cast<std::size_t>(at - head.begin());
  };
  const std::size_t fruit = col("fruit"), status = col("status"), joint = col("failing_joint");
  std::map<int, std::string> out;
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    for (std::istringstream r(line); std::getline(r, line, ',');) c.push_back(line);
    c.resize(head.size());
    if (c[status] == "tracking_joint_limit_reached") out[std::stoi(c[fruit])] = c[joint];
  }
  return out;
}

// The design's answer line in report.md: "fruits 0, 1: <why>; fruit 4: <why>" -> fruit -> why.
std::map<int, std::string> missReasons(const std::string& md, const std::string& design) {
  const auto at = md.find("`" + design + "` picks");
  REQUIRE(at != std::string::npos);
  const std::string line = md.substr(at, md.find('\n', at) - at);
  const auto m = line.find("misses ");
  std::map<int, std::string> out;
  if (m == std::string::npos) return out;
  std::string rest = line.substr(m + 7);
  if (!rest.empty() && rest.back() == '.') rest.pop_back();
  std::size_t from = 0;
  while (from < rest.size()) {
    std::size_t end = rest.find("; fruit", from);
    if (end == std::string::npos) end = rest.size();
    const std::string group = rest.substr(from, end - from);
    const auto colon = group.find(": ");
    REQUIRE(colon != std::string::npos);
    std::string nums = group.substr(group.find(' ') + 1, colon - group.find(' ') - 1);
    std::replace(nums.begin(), nums.end(), ',', ' ');
    std::istringstream ns(nums);
    for (int f; ns >> f;) out[f] = group.substr(colon + 2);
    from = end + 2;
  }
  return out;
}

std::string section(const std::string& md, const std::string& heading) {
  const auto at = md.find("## " + heading + "\n");
  if (at == std::string::npos) return "";
  return md.substr(at, md.find("\n## ", at + 3) - at);
}

}  // namespace

TEST_CASE(
    "harvest_torque: a miss at a joint limit names the joint and the limit, says the limit is "
    "assumed, and the assumptions it rests on are listed under the answer",
    "[harvest][report]") {
  const fs::path out = test::shippedOutput("harvest_torque");
  const Study s = loadStudy(test::sourcePath("studies/harvest_torque.toml"));
  const std::string md = readFileOrThrow((out / "report.md").string());
  const std::string html = readFileOrThrow((out / "report.html").string());
  const std::string assumptions = section(md, "Assumptions");
  REQUIRE(!assumptions.empty());
  REQUIRE(s.assumptions.size() >= 2);
  for (const std::string& a : s.assumptions) {
    CHECK(assumptions.find(a) != std::string::npos);
    CHECK(html.find(a.substr(0, 40)) != std::string::npos);
  }
  CHECK(html.find(">Assumptions</h") != std::string::npos);

  int stops = 0;
  for (const StudyDesign& d : s.designs) {
    const Model& m = d.model;
    INFO(m.name);
    const auto csv =
        limitStops(readFileOrThrow((out / "harvest" / (m.name + "_fruits.csv")).string()));
    const auto why = missReasons(md, m.name);
    const std::vector<std::string> limit_lines = notes::about(m, notes::kJointLimits);
    REQUIRE(!limit_lines.empty());  // both final prototypes assume their joint limits
    for (const auto& [fruit, joint] : csv) {
      INFO("fruit " << fruit);
      ++stops;
      REQUIRE(why.count(fruit));
      const std::string& w = why.at(fruit);
      const std::string lead = "the tracking reached " + joint + "'s joint limit ";
      REQUIRE(w.rfind(lead, 0) == 0);
      const auto j = std::find_if(m.joints.begin(), m.joints.end(),
                                  [&](const Joint& x) { return x.name == joint; });
      REQUIRE(j != m.joints.end());
      const double shown = std::stod(w.substr(lead.size()));
      if (j->type == JointType::Revolute) {
        CHECK(w.find(" deg") != std::string::npos);
        const double lo = j->limits.q_min * 180 / M_PI, hi = j->limits.q_max * 180 / M_PI;
        CHECK(std::min(std::abs(shown - lo), std::abs(shown - hi)) < kDegreeTolerance);
      } else {
        CHECK((shown == Approx(j->limits.q_min) || shown == Approx(j->limits.q_max)));
      }
      CHECK(w.find("(an assumed limit)") != std::string::npos);
    }
    if (!csv.empty())
      for (const std::string& a : limit_lines)
        CHECK(assumptions.find("`" + m.name + "`: " + a) != std::string::npos);
  }
  CHECK(stops >= 5);  // the 7-DoF alone stops at a joint limit on 5 of its 8 fruits
}

TEST_CASE(
    "harvest_torque: each joint's peak effort carries its own unit (N m revolute, N prismatic)",
    "[harvest][report]") {
  const fs::path out = test::shippedOutput("harvest_torque");
  const Study s = loadStudy(test::sourcePath("studies/harvest_torque.toml"));
  const std::string md = readFileOrThrow((out / "harvest" / "report.md").string());
  int rows = 0;
  for (const StudyDesign& d : s.designs) {
    const auto sec = md.find("## " + d.model.name + "\n");
    REQUIRE(sec != std::string::npos);
    const auto table = md.find("Per joint, worst", sec);
    REQUIRE(table != std::string::npos);
    for (const Joint& j : d.model.joints) {
      INFO(d.model.name << " " << j.name);
      const auto at = md.find("\n| " + j.name + " | ", table);
      REQUIRE(at != std::string::npos);
      const auto b = at + j.name.size() + 6;
      std::string cell = md.substr(b, md.find(" |", b) - b);
      const std::string unit = j.type == JointType::Revolute ? " N m" : " N";
      CHECK(cell.size() > unit.size());
      CHECK(cell.compare(cell.size() - unit.size(), unit.size(), unit) == 0);
      CHECK(std::isfinite(std::stod(cell)));
      ++rows;
    }
  }
  CHECK(rows == 16);  // 9 + 7 joints
}

TEST_CASE("harvest_torque: the profile plots show the fruits a drive limit stops, then picked ones",
          "[harvest][report]") {
  const fs::path out = test::shippedOutput("harvest_torque");
  const Study s = loadStudy(test::sourcePath("studies/harvest_torque.toml"));
  const int plot_fruits = 2;  // the study's plot_fruits
  int failed_plotted = 0;
  for (const StudyDesign& d : s.designs) {
    INFO(d.model.name);
    std::istringstream in(
        readFileOrThrow((out / "harvest" / (d.model.name + "_fruits.csv")).string()));
    std::string line;
    std::getline(in, line);
    std::vector<int> failed, picked;
    while (std::getline(in, line)) {  // fruit,x,y,z,status,feasible,...
      std::vector<std::string> c;
      for (std::istringstream r(line); std::getline(r, line, ',');) c.push_back(line);
      if (c[4] != "ok") continue;
      (c[5] == "1" ? picked : failed).push_back(std::stoi(c[0]));
    }
    std::vector<int> want = failed;
    want.insert(want.end(), picked.begin(), picked.end());
    want.resize(std::min<std::size_t>(want.size(), plot_fruits));
    for (int f = 0; f < 8; ++f) {
      const bool plotted = fs::exists(
          out / "harvest" / (d.model.name + "_fruit" + std::to_string(f) + "_current.svg"));
      INFO("fruit " << f);
      CHECK(plotted == (std::find(want.begin(), want.end(), f) != want.end()));
      if (plotted && std::find(failed.begin(), failed.end(), f) != failed.end()) ++failed_plotted;
    }
  }
  CHECK(failed_plotted == 3);  // 9-DoF fruits 2 and 4, 7-DoF fruit 4
}

TEST_CASE(
    "spraying_row: the poses blocked by joint limits list the design's joint-limit assumption",
    "[reach][report]") {
  const fs::path out = test::shippedOutput("spraying_row");
  const Study s = loadStudy(test::sourcePath("studies/spraying_row.toml"));
  const auto summary = nlohmann::json::parse(readFileOrThrow((out / "summary.json").string()));
  const std::string assumptions =
      section(readFileOrThrow((out / "report.md").string()), "Assumptions");
  long blocked = 0;
  for (const auto& d : summary["reach"]["grids"][0]["designs"])
    blocked += d["status_counts"]["joint_limits"].get<long>();
  REQUIRE(blocked > 0);  // the scenario: some poses fail on a joint limit
  const Model& m = s.designs[0].model;
  const auto lines = notes::about(m, notes::kJointLimits);
  REQUIRE(lines.size() == 1);
  CHECK(assumptions.find("`" + m.name + "`: " + lines[0]) != std::string::npos);
}
