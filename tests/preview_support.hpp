#pragma once
// What the progressive-map tests share (RunOptions::preview_stride): a study run without and with
// previews, and the comparison of the two output folders.
#include <catch2/catch.hpp>
#include <filesystem>
#include <functional>
#include <set>
#include <string>

#include "engine/run.hpp"
#include "io/files.hpp"
#include "test_support.hpp"

namespace armstudy::test {

// Runs `study` on 2 threads without a preview into <dir>/plain and with preview stride `k` into
// <dir>/progressive, `announce` getting each preview's file as it appears.
inline void runWithAndWithoutPreview(const Study& study, const std::filesystem::path& dir, int k,
                                     const std::function<void(const std::string&)>& announce) {
  RunOptions plain;
  plain.output_root = (dir / "plain").string();
  plain.threads = 2;
  plain.progress = false;
  runStudy(study, plain);
  RunOptions progressive = plain;
  progressive.output_root = (dir / "progressive").string();
  progressive.preview_stride = k;
  progressive.on_preview = announce;
  runStudy(study, progressive);
}

// The files of the study folder `progressive` that `plain` lacks; every other file but the
// manifest (which holds timings and options) must have the same bytes in both, and more than 20
// are compared.
inline std::set<std::string> previewExtraFiles(const std::filesystem::path& plain,
                                               const std::filesystem::path& progressive) {
  const std::set<std::string> a = filesUnder(plain), b = filesUnder(progressive);
  std::set<std::string> extra;
  for (const std::string& f : b)
    if (!a.count(f)) extra.insert(f);
  int compared = 0;
  for (const std::string& f : a) {
    if (f == "manifest.json") continue;
    INFO(f);
    CHECK(readFileOrThrow((progressive / f).string()) == readFileOrThrow((plain / f).string()));
    ++compared;
  }
  CHECK(compared > 20);
  return extra;
}

}  // namespace armstudy::test
