#pragma once
// The one way stages write result files: every file goes through a Writer rooted at the study's
// output folder, which writes it atomically (io/files.hpp) and lists it, relative to the folder,
// in writing order (the manifest's file list and `--overwrite` cleanup come from that list).
#include <string>
#include <utility>
#include <vector>

#include "report/document.hpp"

namespace armstudy {

class Writer {
 public:
  explicit Writer(std::string root) : root_(std::move(root)) {}
  Writer(Writer&&) = default;
  // Absolute path of a file relative to the output folder (for writers that take a path, e.g.
  // VTK and PNG; call add() after they wrote it).
  std::string path(const std::string& rel) const;
  // Writes `content` atomically to <root>/<rel> (parents created) and lists it.
  void text(const std::string& rel, const std::string& content);
  // Writes the report document `doc` as Markdown to <root>/<rel>, lists it and keeps the document
  // (report.html renders it).
  void report(const std::string& rel, report::Document doc);
  // Lists a file another writer wrote at path(rel).
  void add(const std::string& rel) { files_.push_back(rel); }
  const std::string& root() const { return root_; }
  const std::vector<std::string>& files() const { return files_; }
  const std::vector<report::ReportFile>& reports() const { return reports_; }

 private:
  std::string root_;
  std::vector<std::string> files_;
  std::vector<report::ReportFile> reports_;
};

}  // namespace armstudy
