#pragma once
// history.csv of a calibration output folder: one row per model of every compare/fit run, the
// data behind the "error ladder" plot. One format for every kind (kHistoryHeader; the kind is a
// column), read through the engine's one CSV tokenizer (io::splitCsvLines).
#include <optional>
#include <string>
#include <vector>

#include "io/files.hpp"

namespace armstudy::calibration {

struct HistoryFile {
  std::string path;
  std::string text;                            // whole file content, header first
  std::vector<std::vector<std::string>> rows;  // data rows, split at commas
  int next_run = 1;                            // run number for the rows appended now
};

inline constexpr const char* kHistoryHeader =
    "run,command,kind,design,data_hash,model,effects,n_params,n_rows,train_rmse,heldout_rmse,unit,"
    "aic,bic";
inline constexpr int kHistoryKindColumn = 2;

// Reads `path` (or starts a new file) and checks it: another header or a row of another kind is an
// InputError naming the file and line (a history of another kind in the same output folder).
HistoryFile readHistory(const std::string& path, const std::string& kind);
// Appends one row (commas inside cells become ';').
void appendHistoryRow(HistoryFile& h, std::vector<std::string> cells);
// Writes the file atomically.
void writeHistory(const HistoryFile& h);
// "%.6g" formatting used for the numeric cells.
std::string historyNumber(double v);

// The files of one compare/fit run: nothing is written into the output folder until the
// whole result exists. Every file goes to a staging folder beside it (`<out>.staging.<pid>`);
// commit() swaps that folder in as a whole (io/files.hpp publishFolder). A run that
// fails before commit() (bad input, full disk) leaves the output folder exactly as it was: the
// destructor removes the staging folder. While it exists, the output folder is locked (a lock file
// beside it, `<out>.lock`, since the folder itself is swapped): a second compare/fit into the same
// folder stops with "another armstudy run is writing to ..." instead of losing the first's
// history row. Construct it before reading anything from the output folder. `lock` false: the
// caller holds the lock of an enclosing folder (a study run's output folder), so no lock file is
// left among the results.
class StagedOutput {
 public:
  explicit StagedOutput(const std::string& out_dir, bool lock = true);
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;
  const std::string& dir() const { return staging_; }  // write the run's files here
  const std::string& outDir() const { return out_; }
  void commit();

 private:
  std::string out_;
  std::optional<FileLock> lock_;
  std::string staging_;
  bool committed_ = false;
};

}  // namespace armstudy::calibration
