#include "calibration/history.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <system_error>

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

StagedOutput::StagedOutput(const std::string& out_dir)
    : out_(out_dir), staging_(makeStagingFolder(out_dir)) {}

StagedOutput::~StagedOutput() {
  std::error_code ec;
  fs::remove_all(staging_, ec);  // after commit() only the emptied folder is left
}

void StagedOutput::commit() {
  if (committed_) return;
  publishFolder(staging_, out_);  // the whole folder at once (issue 19)
  committed_ = true;
}

}  // namespace armstudy::calibration
