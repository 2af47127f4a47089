#pragma once
// Saving completed work as a study goes, so an interrupted run (Ctrl-C, kill, power loss) resumes
// and finishes with exactly the files an uninterrupted run writes (docs/regression.md).
//
// Work is split into independent units (design/variant x grid chunk), each with a stable id. A
// unit's result is saved atomically under <output>/.partial/units/ as soon as it is done. The
// folder is stamped with a fingerprint of everything the results depend on (armstudy version and
// git revision, the study and design file hashes, resolved settings); a resume with a different
// fingerprint starts fresh and says why, never mixing old and new results.
#include <string>

namespace armstudy {

class CheckpointStore {
 public:
  // Opens (or creates) the store in `output_dir`. `message` receives one line for the user:
  // "resuming: N completed unit(s) found" or "starting fresh because ...", or stays empty when
  // there was nothing to resume.
  CheckpointStore(std::string output_dir, std::string fingerprint, std::string& message);
  // Disabled store: never loads, never saves (for runs that must not touch disk, e.g. tests).
  CheckpointStore();

  bool enabled() const { return !dir_.empty(); }
  // Loads a unit saved by an earlier run with the same fingerprint.
  bool load(const std::string& unit_id, std::string& bytes) const;
  // Saves a completed unit (atomic). Thread-safe: distinct units may be saved concurrently.
  void save(const std::string& unit_id, const std::string& bytes) const;
  int completedUnits() const { return completed_; }
  // Removes the store after the final result files and manifest are written.
  void finish();

  static bool hasPartialRun(const std::string& output_dir);

 private:
  std::string unitPath(const std::string& unit_id) const;
  std::string dir_;
  int completed_ = 0;
};

}  // namespace armstudy
