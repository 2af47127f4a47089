#pragma once
// history.csv of a calibration output folder: one row per model of every compare/fit run, the
// data behind the "error ladder" plot. Shared by the drive and arm kinds.
#include <string>
#include <vector>

namespace armstudy::calibration {

struct HistoryFile {
  std::string path;
  std::string text;                              // whole file content, header first
  std::vector<std::vector<std::string>> rows;    // data rows, split at commas
  int next_run = 1;                              // run number for the rows appended now
};

// Reads `path` (or starts a new file) and checks its header; an unexpected header is an
// InputError (a history of another kind in the same folder).
HistoryFile readHistory(const std::string& path, const std::string& header);
// Appends one row (commas inside cells become ';').
void appendHistoryRow(HistoryFile& h, std::vector<std::string> cells);
// Writes the file atomically.
void writeHistory(const HistoryFile& h);
// "%.6g" formatting used for the numeric cells.
std::string historyNumber(double v);

}  // namespace armstudy::calibration
