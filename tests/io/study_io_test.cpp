// Study files: designs resolved relative to the study, variants derived with stable names,
// bad input rejected with file, line and key.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "common/errors.hpp"
#include "engine/study_file.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;
namespace fs = std::filesystem;

namespace {

// Writes a study into a fresh temporary folder next to a copy-free path to designs/.
std::string writeStudy(const std::string& name, const std::string& body) {
  const fs::path dir = fs::temp_directory_path() / "armstudy_study_test";
  fs::create_directories(dir);
  const fs::path p = dir / (name + ".toml");
  std::ofstream(p) << body;
  return p.string();
}

std::string designRef(const std::string& rel) {
  std::string s = "\"";
  s += sourcePath(rel);
  s += '"';
  return s;
}

}  // namespace

TEST_CASE("variants sweep table entries as a cartesian product with stable names", "[io][study]") {
  const std::string path =
      writeStudy("variants", "[study]\nname = \"v\"\n[[design]]\nfile = " +
                                 designRef("designs/first_prototype_9dof.toml") +
                                 "\n[[variant]]\nof = \"first_prototype_9dof\"\n"
                                 "set = { \"tcp.z\" = \"150 mm\" }\n"
                                 "sweep = { \"joint.j4.x\" = [0.30, 0.35, \"400 mm\"], "
                                 "\"base.y\" = [0.0, -0.1] }\n");
  const Study s = loadStudy(path);
  REQUIRE(s.designs.size() == 1 + 3 * 2);
  CHECK(s.designs[0].model.name == "first_prototype_9dof");
  // Keys are taken in sorted order (TOML tables are unordered); the first varies slowest.
  CHECK(s.designs[1].model.name == "first_prototype_9dof+tcp.z=0.15+base.y=0+j4.x=0.3");
  CHECK(s.designs[2].model.name == "first_prototype_9dof+tcp.z=0.15+base.y=0+j4.x=0.35");
  CHECK(s.designs[6].model.name == "first_prototype_9dof+tcp.z=0.15+base.y=-0.1+j4.x=0.4");
  CHECK(s.designs[6].model.joints[3].offset.x == Approx(0.4));
  CHECK(s.designs[6].model.T_WB.translation().y() == Approx(-0.1));
  CHECK(s.designs[6].model.T_NT.translation().z() == Approx(0.15));
  CHECK(s.designs[0].model.joints[3].offset.x == Approx(0.23));  // base design untouched
  CHECK(s.inputs.size() == 2);
}

TEST_CASE("bad study input names file, line and key", "[io][study][bad-input]") {
  auto expectError = [](const std::string& body, const std::string& key, const std::string& part) {
    const std::string path = writeStudy("bad", body);
    try {
      loadStudy(path);
      FAIL("expected an InputError");
    } catch (const InputError& e) {
      INFO(e.what());
      CHECK(e.file().find("bad.toml") != std::string::npos);
      CHECK(e.key() == key);
      CHECK(e.line() > 0);
      CHECK(std::string(e.what()).find(part) != std::string::npos);
    }
  };
  const std::string head = "[study]\nname = \"s\"\n";
  const std::string d9 =
      "[[design]]\nfile = " + designRef("designs/first_prototype_9dof.toml") + "\n";
  expectError(head + "[[design]]\nfile = \"no_such_design.toml\"\n", "design[0].file",
              "does not exist");
  expectError(head + d9 + "[[variant]]\nof = \"other\"\nset = { \"tcp.z\" = 0.1 }\n",
              "variant[0].of", "unknown design");
  expectError(
      head + d9 + "[[variant]]\nof = \"first_prototype_9dof\"\nset = { \"joint.j99.x\" = 0.1 }\n",
      "variant[0].set.joint.j99.x", "no joint");
  expectError(
      head + d9 +
          "[[variant]]\nof = \"first_prototype_9dof\"\nset = { \"joint.j4.x\" = \"10 deg\" }\n",
      "variant[0].set.joint.j4.x", "angle");
  expectError(
      head + d9 + "[[variant]]\nof = \"first_prototype_9dof\"\nsweep = { \"joint.j4.x\" = [] }\n",
      "variant[0].sweep.joint.j4.x", "non-empty");
  expectError(head + d9 + "colour = \"red\"\n", "design[0].colour", "unknown key");
  expectError("[study]\nname = \"bad name!\"\n" + d9, "study.name", "letters");
  expectError(head + d9 + d9, "design[1].file", "twice");
}
