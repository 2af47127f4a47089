#include "study/checkpoint.hpp"

#include <algorithm>
#include <csignal>
#include <cstdlib>
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

const CheckpointStore& CheckpointStore::disabled() {
  static const CheckpointStore off;
  return off;
}

CheckpointStore::CheckpointStore(std::string output_dir, std::string fingerprint,
                                 std::string& message)
    : dir_(partialDir(output_dir)) {
  message.clear();
  if (const char* n = std::getenv("ARMSTUDY_TEST_ABORT_AFTER_UNITS"))
    abort_after_units_ = static_cast<std::size_t>(std::max(0L, std::atol(n)));
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
  for (char c : id)
    safe += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == '_' ||
             c == '+' || c == '=')
                ? c
                : '_';
  return (fs::path(dir_) / "units" / (safe + "." + contentHash(id).substr(8, 8) + ".unit"))
      .string();
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
  std::string p = unitPath(id);
  writeFileAtomic(p, bytes);
  const std::lock_guard<std::mutex> g(saved_mutex_);
  saved_.push_back(std::move(p));
  // The test hook (checkpoint.hpp): killed as abruptly as by `kill -9`, no handler, no clean-up.
  if (saved_.size() == abort_after_units_) std::raise(SIGKILL);
}

void CheckpointStore::removeSaved() {
  std::error_code ec;  // a file already gone (e.g. removed by hand) is fine
  for (const std::string& p : saved_) fs::remove(p, ec);
  saved_.clear();
}

void CheckpointStore::finish() {
  if (enabled()) fs::remove_all(dir_);
}

std::vector<ItemRange> splitRange(long count, long per_range) {
  per_range = std::max(1L, per_range);
  std::vector<ItemRange> out;
  for (long b = 0; b < count; b += per_range) out.push_back({b, std::min(count, b + per_range)});
  return out;
}

RangeCountdown::RangeCountdown(const std::vector<ItemRange>& ranges)
    : left_(new std::atomic<long>[ranges.size()]) {
  for (std::size_t k = 0; k < ranges.size(); ++k)
    left_[k].store(ranges[k].size(), std::memory_order_relaxed);
}

bool RangeCountdown::itemDone(std::size_t range) {
  return left_[range].fetch_sub(1, std::memory_order_acq_rel) == 1;
}

void UnitWriter::putString(const std::string& s) {
  put<std::uint64_t>(s.size());
  bytes_ += s;
}

UnitReader::UnitReader(const std::string& bytes, std::string_view magic) : b_(bytes) {
  ok_ = b_.compare(0, magic.size(), magic) == 0;
  pos_ = ok_ ? magic.size() : b_.size();
}

bool UnitReader::take(std::size_t n) {
  if (!ok_ || n > b_.size() - pos_) {
    ok_ = false;
    return false;
  }
  pos_ += n;
  return true;
}

std::string UnitReader::getString() {
  const auto n = get<std::uint64_t>();
  if (!ok_ || n > b_.size() - pos_) {
    ok_ = false;
    return {};
  }
  std::string s = b_.substr(pos_, n);
  pos_ += n;
  return s;
}

}  // namespace armstudy
