#include "calibration/history.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <system_error>

#include "common/errors.hpp"
#include "common/format.hpp"
#include "io/csv_io.hpp"
#include "io/files.hpp"

namespace armstudy::calibration {

HistoryFile readHistory(const std::string& path, const std::string& kind) {
  HistoryFile h;
  h.path = path;
  h.text = std::string(kHistoryHeader) + "\n";
  if (!std::filesystem::exists(path)) return h;
  const std::string text = readFileOrThrow(path);
  const std::vector<io::CsvLine> lines = io::splitCsvLines(text);
  const std::vector<io::CsvLine> header = io::splitCsvLines(kHistoryHeader);
  if (lines.empty() || lines.front().cells != header.front().cells)
    throw InputError(path, lines.empty() ? 1 : lines.front().line, "",
                     "history file has an unexpected header (written by another armstudy "
                     "version?); move it away "
                     "or use another output folder");
  for (std::size_t k = 1; k < lines.size(); ++k) {
    const io::CsvLine& l = lines[k];
    if (l.cells.size() != header.front().cells.size())
      throw InputError(path, l.line, "",
                       "history row has " + std::to_string(l.cells.size()) + " cells, expected " +
                           std::to_string(header.front().cells.size()));
    if (l.cells[kHistoryKindColumn] != kind)
      throw InputError(path, l.line, "kind",
                       "history of kind '" + l.cells[kHistoryKindColumn] +
                           "' in this output folder, this run is of kind '" + kind +
                           "'; move it away or use another output folder");
    h.rows.push_back(l.cells);
    h.next_run = std::max(h.next_run, std::atoi(l.cells[0].c_str()) + 1);
  }
  h.text = text;
  if (!h.text.empty() && h.text.back() != '\n') h.text += "\n";
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

std::string historyNumber(double v) { return formatG(v, 6); }

namespace fs = std::filesystem;

namespace {
// <out>.lock beside the output folder (its parent created when missing).
std::string lockPathBeside(const std::string& out_dir) {
  const fs::path out = fs::path(out_dir).lexically_normal();
  const fs::path p = out.has_filename() ? out : out.parent_path();
  std::error_code ec;
  if (!p.parent_path().empty()) fs::create_directories(p.parent_path(), ec);
  return p.string() + ".lock";
}
}  // namespace

StagedOutput::StagedOutput(const std::string& out_dir, bool lock) : out_(out_dir) {
  checkOutputFolder(out_dir);  // before the lock file beside it is made
  if (lock) lock_.emplace(lockPathBeside(out_dir), out_dir);
  staging_ = makeStagingFolder(out_dir);
}

StagedOutput::~StagedOutput() {
  std::error_code ec;
  fs::remove_all(staging_, ec);  // after commit() only the emptied folder is left
}

void StagedOutput::commit() {
  if (committed_) return;
  publishFolder(staging_, out_);  // the whole folder at once
  committed_ = true;
}

}  // namespace armstudy::calibration
