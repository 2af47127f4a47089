#pragma once
// The one way stages write result files: every file goes through a Writer rooted at the study's
// output folder, which writes it atomically (io/files.hpp) and lists it, relative to the folder,
// in writing order (the manifest's file list and `--overwrite` cleanup come from that list).
#include <future>
#include <string>
#include <utility>
#include <vector>

namespace armstudy {

class Writer {
 public:
  explicit Writer(std::string root) : root_(std::move(root)) {}
  Writer(Writer&&) = default;
  // Waits for the background writes (their failures reach only flush()).
  ~Writer();
  // Absolute path of a file relative to the output folder (for writers that take a path, e.g.
  // VTK and PNG; call add() after they wrote it).
  std::string path(const std::string& rel) const;
  // Writes `content` atomically to <root>/<rel> (parents created) and lists it.
  void text(const std::string& rel, const std::string& content);
  // Lists the files now and writes them (atomically, in the given order) on a background thread
  // while the caller goes on: for many files whose content is ready, e.g. a reach grid's files that
  // the ranks rendered (each file is synced to disk, so writing them waits for the disk). Call
  // flush() before the files are read or the stage returns.
  void textLater(std::vector<std::pair<std::string, std::string>> files);
  // Waits until every background write is done; rethrows the first that failed.
  void flush();
  // Lists a file another writer wrote at path(rel).
  void add(const std::string& rel) { files_.push_back(rel); }
  const std::string& root() const { return root_; }
  const std::vector<std::string>& files() const { return files_; }

 private:
  std::string root_;
  std::vector<std::string> files_;
  std::vector<std::future<void>> later_;
};

}  // namespace armstudy
