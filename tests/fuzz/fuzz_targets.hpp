#pragma once
// Fuzz targets of the readers: each takes arbitrary bytes as the content of one input
// file and must either accept it or throw InputError naming the file. Anything else (another
// exception, a failed ARMSTUDY_CHECK, a crash, a sanitizer report) is a finding.
//
// Used twice: tests/fuzz/replay_test.cpp runs them on the corpus and on seeded mutations of it in
// every test run (a few seconds each), and tests/fuzz/libfuzzer_main.cpp turns each into a
// libFuzzer binary for the on-demand `fuzz` target (clang; README "Fuzzing").
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "common/errors.hpp"
#include "io/csv_io.hpp"
#include "io/design_io.hpp"
#include "io/urdf_io.hpp"
#ifndef ARMSTUDY_CORE_ONLY
#include "calibration/joint_log.hpp"
#include "engine/study_file.hpp"
#endif
#include "study/regression.hpp"

namespace armstudy::fuzz {

// Thrown when an InputError does not name its file: the message a user sees must say which file.
struct UnnamedInputError : std::logic_error {
  using std::logic_error::logic_error;
};

inline void requireNamed(const InputError& e, const std::string& file) {
  if (e.file() != file)
    throw UnnamedInputError("InputError names '" + e.file() + "', not '" + file + "': " + e.what());
}

inline std::string bytes(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// A design file's text.
inline void design(const std::uint8_t* data, std::size_t size) {
  const std::string file = "fuzz_design.toml";
  try {
    (void)parseDesign(bytes(data, size), file);
  } catch (const InputError& e) {
    requireNamed(e, file);
  }
}

// A measurement CSV (the strict reader behind every data file), read twice: with two required and
// one optional column (the header checks), and with the columns its own first line names (the
// first required, the others optional), so that the rows are read too: cell counts, numbers,
// finiteness, plausibility. Returns whether the second reading accepted the text.
inline bool csv(const std::uint8_t* data, std::size_t size) {
  const std::string file = "fuzz_data.csv", text = bytes(data, size);
  try {
    (void)io::parseCsv(text, file, io::CsvSchema{{"q", "current_a"}, {"temperature_c"}});
  } catch (const InputError& e) {
    requireNamed(e, file);
  }
  try {
    io::CsvSchema own;
    if (const auto lines = io::splitCsvLines(text); !lines.empty()) {
      own.required = {lines[0].cells[0]};
      own.optional.assign(lines[0].cells.begin() + 1, lines[0].cells.end());
    }
    (void)io::parseCsv(text, file, own);
    return true;
  } catch (const InputError& e) {
    requireNamed(e, file);
  }
  return false;
}

// A regression baseline (JSON).
inline void baseline(const std::uint8_t* data, std::size_t size) {
  const std::string file = "fuzz.baseline.json";
  try {
    (void)parseBaseline(bytes(data, size), file, "regression");
  } catch (const InputError& e) {
    requireNamed(e, file);
  }
}

// A URDF file, imported with its collision volumes fitted (boxes, cylinders and spheres; meshes a
// fuzzed file names are looked up beside the working folder, where there are none, and become
// notes).
inline void urdf(const std::uint8_t* data, std::size_t size) {
  const std::string file = "fuzz_robot.urdf";
  try {
    (void)importUrdfText(bytes(data, size), file, UrdfOptions{});
  } catch (const InputError& e) {
    requireNamed(e, file);
  }
}

// A collision mesh of a URDF (STL bytes, binary or ASCII), read through the importer: the bytes
// become link.stl in a scratch folder, beside a one-joint URDF whose link names it; the mesh is
// read with assimp, checked and fitted with swept-sphere volumes. The error must name the URDF.
inline void urdf_mesh(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  static const fs::path dir = [] {
    const fs::path d =
        fs::temp_directory_path() / ("armstudy_fuzz_urdf_mesh." + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  const std::string file = (dir / "fuzz_mesh.urdf").string();
  {
    std::ofstream out(dir / "link.stl", std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  const std::string urdf =
      "<robot name=\"fuzz\"><link name=\"base\"/><link name=\"l1\"><collision><geometry>"
      "<mesh filename=\"link.stl\" scale=\"0.001 0.001 0.001\"/></geometry></collision></link>"
      "<joint name=\"j1\" type=\"revolute\"><parent link=\"base\"/><child link=\"l1\"/>"
      "<axis xyz=\"0 0 1\"/><limit lower=\"-2\" upper=\"2\" effort=\"1\" velocity=\"1\"/>"
      "</joint></robot>";
  try {
    (void)importUrdfText(urdf, file, UrdfOptions{});
  } catch (const InputError& e) {
    requireNamed(e, file);
  }
}

#ifndef ARMSTUDY_CORE_ONLY
// A study file, in a scratch copy of the repository's layout (studies/ beside designs/, the
// shipped data reachable as studies/data) so its relative paths resolve. The error may name the
// study or a file it refers to; it must name a file.
inline void study(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  static const fs::path root = [] {
    const fs::path r =
        fs::temp_directory_path() / ("armstudy_fuzz_study." + std::to_string(::getpid()));
    fs::create_directories(r / "studies");
    std::error_code ec;
    fs::create_directory_symlink(fs::path(ARMSTUDY_SOURCE_DIR) / "designs", r / "designs", ec);
    fs::create_directory_symlink(fs::path(ARMSTUDY_SOURCE_DIR) / "studies" / "data",
                                 r / "studies" / "data", ec);
    return r;
  }();
  const std::string file = (root / "studies" / "fuzz.toml").string();
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    (void)loadStudy(file);
  } catch (const InputError& e) {
    if (e.file().empty())
      throw UnnamedInputError(std::string("InputError names no file: ") + e.what());
  }
}

// A measured joint log of the 6-joint first prototype: one CSV holding the time column `t`, the
// positions q1..q6 and the efforts e1..e6, read through the joint-log reader twice, by its time
// column and by a sample period of 1 ms, filtered, decimated by 2 and trimmed by 5 ms. The error
// names the log or the settings' study file.
inline void jointLog(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  static const Model model =
      loadDesign(std::string(ARMSTUDY_SOURCE_DIR) + "/designs/first_prototype_6dof.toml");
  static const std::string file =
      (fs::temp_directory_path() /
       ("armstudy_fuzz_joint_log." + std::to_string(::getpid()) + ".csv"))
          .string();
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  calibration::JointLogSpec s;
  s.study_file = "fuzz_study.toml";
  s.study_line = 1;
  s.study_key = "calibration[0].measured";
  for (const Joint& j : model.joints) s.joints.push_back(j.name);
  s.positions = {file, {"q1", "q2", "q3", "q4", "q5", "q6"}, 1.0, {}};
  s.efforts = {file, {"e1", "e2", "e3", "e4", "e5", "e6"}, 1.0, {}};
  s.coupling = Eigen::MatrixXd::Identity(6, 6);
  s.offsets = Eigen::VectorXd::Zero(6);
  s.cutoff_Hz = 50;
  s.decimate = 2;
  s.trim_s = 5e-3;
  for (const bool timed : {true, false}) {
    s.time_column = timed ? "t" : "";
    s.sample_period_s = timed ? 0.0 : 1e-3;
    try {
      (void)calibration::readJointLog(s, model);
    } catch (const InputError& e) {
      if (e.file() != file) requireNamed(e, s.study_file);
    }
  }
}
#endif

}  // namespace armstudy::fuzz
