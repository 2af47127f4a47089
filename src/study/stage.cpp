#include "study/stage.hpp"

#include <filesystem>

#include "io/files.hpp"
#include "study/checkpoint.hpp"

namespace armstudy {

std::string RunOptions::validate() const {
  if (output_root.empty()) return "output root is empty";
  if (threads < 0) return "thread count must not be negative";
  if (unit_items < 0) return "unit size must not be negative";
  return "";
}

long UnitRunner::run(const UnitBatch& batch) const {
  std::vector<std::size_t> todo;
  long resumed = 0;
  for (std::size_t k = 0; k < batch.ids.size(); ++k) {
    std::string bytes;
    if (store_.load(batch.ids[k], bytes) && batch.load(k, bytes))
      ++resumed;
    else
      todo.push_back(k);
  }
  if (!todo.empty())
    batch.compute(todo, [&](std::size_t k, const std::string& bytes) { store_.save(batch.ids[k], bytes); });
  return resumed;
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

}  // namespace armstudy
