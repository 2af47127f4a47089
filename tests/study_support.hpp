#pragma once
// A shipped study run the way the tests that check its written files need it.
#include <filesystem>
#include <string>

#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "test_support.hpp"

namespace armstudy::test {

// Runs the study file `rel` (relative to the source tree) on 2 threads, without progress, into the
// output root `root` (a study's folder there is replaced) and returns the study's output folder,
// root/<study name>.
inline std::filesystem::path runShippedStudy(const std::string& rel,
                                             const std::filesystem::path& root) {
  const Study s = loadStudy(sourcePath(rel));
  RunOptions ro;
  ro.output_root = root.string();
  ro.threads = 2;
  ro.overwrite = true;
  ro.progress = false;
  (void)runStudy(s, ro);
  return root / s.name;
}

}  // namespace armstudy::test
