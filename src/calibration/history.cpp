#include "calibration/history.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include <system_error>
#include <unistd.h>

#include "common/errors.hpp"
#include "io/files.hpp"

namespace armstudy::calibration {

HistoryFile readHistory(const std::string& path, const std::string& header) {
  HistoryFile h;
  h.path = path;
  if (!std::filesystem::exists(path)) {
    h.text = header + "\n";
    return h;
  }
  h.text = readFileOrThrow(path);
  std::istringstream is(h.text);
  std::string line;
  std::getline(is, line);
  if (line != header)
    throw InputError(path, 1, "",
                     "history file has an unexpected header (another kind?); move it away or use another "
                     "output folder");
  while (std::getline(is, line)) {
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    h.rows.push_back(cells);
  }
  for (const auto& r : h.rows)
    if (!r.empty()) h.next_run = std::max(h.next_run, std::atoi(r[0].c_str()) + 1);
  return h;
}

void appendHistoryRow(HistoryFile& h, std::vector<std::string> cells) {
  std::string line;
  for (auto& c : cells) {
    std::replace(c.begin(), c.end(), ',', ';');
    if (!line.empty()) line += ',';
    line += c;
  }
  h.text += line + "\n";
  h.rows.push_back(std::move(cells));
}

void writeHistory(const HistoryFile& h) { writeFileAtomic(h.path, h.text); }

std::string historyNumber(double v) {
  char b[48];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

namespace fs = std::filesystem;

StagedOutput::StagedOutput(const std::string& out_dir) : out_(out_dir) {
  fs::path p = fs::path(out_dir).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  staging_ = p.string() + ".staging." + std::to_string(::getpid());
  std::error_code ec;
  fs::remove_all(staging_, ec);
  fs::create_directories(staging_, ec);
  if (ec) throw InputError(staging_, 0, "--out", "cannot create the staging folder of the output: " + ec.message());
}

StagedOutput::~StagedOutput() {
  std::error_code ec;
  fs::remove_all(staging_, ec);  // after commit() only the emptied folder is left
}

void StagedOutput::commit() {
  if (committed_) return;
  std::error_code ec;
  fs::create_directories(out_, ec);
  if (ec) throw InputError(out_, 0, "--out", "cannot create the output folder: " + ec.message());
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(staging_))
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), staging_).generic_string());
  auto last = [](const std::string& f) { return f == "result.json" ? 1 : f == "history.csv" ? 2 : 0; };
  std::stable_sort(files.begin(), files.end(), [&](const std::string& a, const std::string& b) {
    return last(a) != last(b) ? last(a) < last(b) : a < b;
  });
  for (const std::string& f : files) {
    const fs::path to = fs::path(out_) / f;
    fs::create_directories(to.parent_path());
    fs::rename(fs::path(staging_) / f, to);  // same file system: atomic per file
  }
  committed_ = true;
}

}  // namespace armstudy::calibration
