#include "study/checkpoint.hpp"

#include <filesystem>

#include "common/errors.hpp"
#include "io/files.hpp"

namespace armstudy {

namespace fs = std::filesystem;

static std::string partialDir(const std::string& output_dir) {
  return (fs::path(output_dir) / ".partial").string();
}

bool CheckpointStore::hasPartialRun(const std::string& output_dir) {
  return fs::exists(fs::path(partialDir(output_dir)) / "fingerprint");
}

CheckpointStore::CheckpointStore() = default;

CheckpointStore::CheckpointStore(std::string output_dir, std::string fingerprint, std::string& message)
    : dir_(partialDir(output_dir)) {
  message.clear();
  const fs::path fp = fs::path(dir_) / "fingerprint";
  if (fs::exists(fp)) {
    const std::string old = readFileOrThrow(fp.string());
    if (old == fingerprint) {
      for (const auto& e : fs::directory_iterator(fs::path(dir_) / "units"))
        if (e.path().extension() == ".unit") ++completed_;
      message = "resuming: " + std::to_string(completed_) + " completed unit(s) found in " + dir_;
      return;
    }
    // Say what changed, as far as the fingerprint lines tell.
    std::string why = "the inputs changed since the interrupted run";
    std::size_t a = 0, b = 0;
    while (a < old.size() && b < fingerprint.size()) {
      const std::size_t ea = old.find('\n', a), eb = fingerprint.find('\n', b);
      const std::string la = old.substr(a, ea - a), lb = fingerprint.substr(b, eb - b);
      if (la != lb) {
        why = "'";
        why += lb.substr(0, lb.find('='));
        why += "' changed since the interrupted run";
        break;
      }
      if (ea == std::string::npos || eb == std::string::npos) break;
      a = ea + 1;
      b = eb + 1;
    }
    message = "starting fresh because " + why + " (discarding " + dir_ + ")";
    fs::remove_all(dir_);
  } else if (fs::exists(dir_)) {
    fs::remove_all(dir_);  // a store without fingerprint was never usable
  }
  fs::create_directories(fs::path(dir_) / "units");
  writeFileAtomic(fp.string(), fingerprint);
}

std::string CheckpointStore::unitPath(const std::string& id) const {
  std::string safe;
  for (char c : id) safe += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == '_' ||
                             c == '+' || c == '=')
                                ? c
                                : '_';
  return (fs::path(dir_) / "units" / (safe + "." + contentHash(id).substr(8, 8) + ".unit")).string();
}

bool CheckpointStore::load(const std::string& id, std::string& bytes) const {
  if (!enabled()) return false;
  const std::string p = unitPath(id);
  if (!fs::exists(p)) return false;
  bytes = readFileOrThrow(p);
  return true;
}

void CheckpointStore::save(const std::string& id, const std::string& bytes) const {
  if (!enabled()) return;
  writeFileAtomic(unitPath(id), bytes);
}

void CheckpointStore::finish() {
  if (enabled()) fs::remove_all(dir_);
}

}  // namespace armstudy
