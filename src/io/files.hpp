#pragma once
// File helpers: whole-file reads, content hashes, atomic writes.
#include <string>

namespace armstudy {

// Reads a whole file; throws InputError(path) when it cannot be opened.
std::string readFileOrThrow(const std::string& path);

// Content fingerprint of bytes: 64-bit FNV-1a as 16 hex digits, prefixed "fnv1a64:". Used to
// record which inputs a run read and to detect changed inputs; not a cryptographic hash.
std::string contentHash(const std::string& bytes);
std::string fileHash(const std::string& path);

// Writes `content` to `path` atomically: a temporary file beside it, flushed, then renamed over
// the target. An interrupted run never leaves a half-written file. Creates parent folders.
void writeFileAtomic(const std::string& path, const std::string& content);

}  // namespace armstudy

namespace armstudy {

// Exclusive use of an output folder for one process (issue 19): creates the folder (an
// InputError naming it when that fails), takes an advisory lock on <folder>/.armstudy.lock
// (InputError "another armstudy run is writing to <folder>" when another process holds it; the
// kernel releases it when a process dies, even by SIGKILL), then removes the temporaries
// (`*.tmp.<pid>`) that writeFileAtomic of a killed run left behind. The destructor releases the
// lock (the empty lock file stays).
class OutputFolderLock {
 public:
  explicit OutputFolderLock(const std::string& folder);
  ~OutputFolderLock();
  OutputFolderLock(const OutputFolderLock&) = delete;
  OutputFolderLock& operator=(const OutputFolderLock&) = delete;
  int staleTemporariesRemoved() const { return removed_; }

 private:
  std::string path_;
  int fd_ = -1;
  int removed_ = 0;
};

}  // namespace armstudy
