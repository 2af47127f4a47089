#include "study/stage.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "io/files.hpp"
#include "io/toml_reader.hpp"
#include "study/checkpoint.hpp"

namespace armstudy {

void StageContext::warn(const std::string& text) const {
  if (warnings)
    warnings(text);
  else
    std::fprintf(stderr, "armstudy: warning: %s\n", text.c_str());
}

bool readSectionTable(const SectionInput& in, const std::string& key,
                      const std::function<void(io::TableReader&)>& parse) {
  const toml::table* t = in.top.table(key);
  if (!t) return false;
  io::TableReader r(*t, in.top.file(), key);
  parse(r);
  r.finish();
  return true;
}

std::string RunOptions::validate() const {
  if (output_root.empty()) return "output root is empty";
  if (threads < 0 || threads > defaults::kMaxThreads)
    return "thread count must be within 0.." + std::to_string(defaults::kMaxThreads) +
           " (0 = all cores)";
  if (unit_items < 0 || unit_items > defaults::kMaxUnitItems)
    return "unit size must be within 0.." + std::to_string(defaults::kMaxUnitItems) +
           " (0 = each stage's default)";
  if (search_group_ranks < 0) return "search group ranks must not be negative";
  if (preview_stride < 0 || preview_stride > defaults::kMaxPreviewStride)
    return "preview stride must be within 0.." + std::to_string(defaults::kMaxPreviewStride) +
           " (0 = no preview)";
  return "";
}

const StageSettings* Study::settings(const std::string& stage) const {
  for (const StudySection& s : sections)
    if (s.stage && s.stage->name() == stage) return s.settings.get();
  return nullptr;
}

std::vector<const Model*> Study::models() const {
  std::vector<const Model*> m;
  for (const StudyDesign& d : designs) m.push_back(&d.model);
  return m;
}

std::string Writer::path(const std::string& rel) const {
  return (std::filesystem::path(root_) / rel).string();
}

void Writer::text(const std::string& rel, const std::string& content) {
  writeFileAtomic(path(rel), content);
  files_.push_back(rel);
}

void Writer::report(const std::string& rel, report::Document doc) {
  text(rel, report::toMarkdown(doc));
  reports_.push_back({rel, std::move(doc)});
}

}  // namespace armstudy
