// A URDF design whose links lack collision volumes (a mesh not found, a link without <collision>):
// the run names them in its CLI output and on the report's first screen, and the self-collision
// line counts the links it covers. Oracle: the fixture's links, written by hand.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/files.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace armstudy;

namespace {

// base (box) -> j1 -> l1 (cylinder) -> j2 -> l2 (a mesh that is not there) -> j3 -> l3 (none).
std::string partialArm() {
  auto joint = [](const std::string& n, const std::string& p, const std::string& c,
                  const std::string& xyz, const std::string& axis) {
    return "<joint name=\"" + n + "\" type=\"revolute\"><parent link=\"" + p +
           "\"/><child link=\"" + c + "\"/><origin xyz=\"" + xyz + "\"/><axis xyz=\"" + axis +
           "\"/><limit lower=\"-3\" upper=\"3\" effort=\"10\" velocity=\"1\"/></joint>\n";
  };
  return std::string("<robot name=\"partial\">\n") +
         "<link name=\"base\"><collision><geometry><box size=\"0.2 0.2 0.1\"/></geometry>"
         "</collision></link>\n"
         "<link name=\"l1\"><collision><origin xyz=\"0 0 0.15\"/><geometry><cylinder "
         "radius=\"0.04\" length=\"0.2\"/></geometry></collision></link>\n"
         "<link name=\"l2\"><collision><geometry><mesh filename=\"meshes/l2_not_there.stl\"/>"
         "</geometry></collision></link>\n"
         "<link name=\"l3\"/>\n" +
         joint("j1", "base", "l1", "0 0 0.1", "0 0 1") +
         joint("j2", "l1", "l2", "0 0 0.3", "0 1 0") + joint("j3", "l2", "l3", "0.4 0 0", "0 1 0") +
         "</robot>\n";
}

}  // namespace

TEST_CASE(
    "URDF partial collision model: the links without volumes are named in the CLI output "
    "and on the report's first screen") {
  const fs::path dir = test::emptyTempDir("urdf_partial_collision");
  std::ofstream(dir / "partial.urdf") << partialArm();
  std::ofstream(dir / "study.toml")
      << "[study]\nname = \"partial\"\n[[design]]\nfile = \"partial.urdf\"\n"
         "[reach]\ntask_space = \"position\"\n[[reach.grid]]\nname = \"g\"\n"
         "x = { from = \"0.3 m\", to = \"0.4 m\", step = \"0.1 m\" }\ny = \"0 m\"\nz = \"0.5 m\"\n";
  std::string out;
  REQUIRE(test::runCommand(test::binaryPath() + " run " + (dir / "study.toml").string() +
                               " --output " + (dir / "out").string(),
                           out) == 0);
  INFO(out);
  const std::string expected =
      "2 of 4 links have no collision volume: 'l2' (collision mesh not found or unreadable), "
      "'l3' (no <collision> element); self-collision covers the other 2 links only";
  CHECK(out.find(expected) != std::string::npos);
  const std::string md = readFileOrThrow((dir / "out/partial/report.md").string());
  INFO(md);
  const auto warnings = md.find("## Warnings"), details = md.find("## Details");
  REQUIRE(warnings != std::string::npos);
  const auto at = md.find(expected);
  CHECK(at != std::string::npos);
  CHECK(at > warnings);
  CHECK(at < details);
  const std::string html = readFileOrThrow((dir / "out/partial/report.html").string());
  const auto html_at = html.find("2 of 4 links have no collision volume");
  CHECK(html_at != std::string::npos);
  CHECK(html_at < html.find("Details"));
  const std::string reach = readFileOrThrow((dir / "out/partial/reach/report.md").string());
  CHECK(reach.find("Self-collision: on for the links with collision volumes (`partial` 2 of 4 "
                   "links)") != std::string::npos);
}
