#pragma once
// File helpers: whole-file reads, content hashes, atomic writes.
#include <optional>
#include <string>

namespace armstudy {

// Reads a whole file; throws InputError(path) when it cannot be opened.
std::string readFileOrThrow(const std::string& path);

// Content fingerprint of bytes: 64-bit FNV-1a as 16 hex digits, prefixed "fnv1a64:". Used to
// record which inputs a run read and to detect changed inputs; not a cryptographic hash.
std::string contentHash(const std::string& bytes);
std::string fileHash(const std::string& path);

// Writes `content` to `path` atomically: a temporary file beside it ("<path>.tmp.<pid>", created
// exclusively, never through a symbolic link), flushed, then renamed over the target. An
// interrupted run never leaves a half-written file. Creates parent folders. The one writer for
// every output file, user paths (`--out`) included: an existing folder, FIFO, device or socket at
// `path` is refused with an InputError naming it (the node stays as it is, nothing is written); a
// symbolic link at `path` is replaced by the new file, never followed (its target stays as it
// was).
void writeFileAtomic(const std::string& path, const std::string& content);
// The check writeFileAtomic makes before writing, for commands that check an output path before
// their work: an InputError naming `path` when a folder, FIFO, device or socket is there.
void checkOutputPath(const std::string& path);

// An output folder published as a whole: a run writes its complete result into a
// staging folder beside the output folder, then publishFolder swaps it in, so a reader of the
// output folder finds the previous complete result or the new one, never a mix.
//
// A fresh, empty staging folder "<folder>.staging.<pid>" beside `folder` (symbolic links in
// `folder` resolved, so both are on one file system). Staging folders of processes that no longer
// exist (a run killed before or after its swap) are removed first. InputError naming `folder` when
// the staging folder cannot be created.
std::string makeStagingFolder(const std::string& folder);
// InputError naming `folder` when something other than a folder (or a link to one) is there, a
// file, FIFO or device: a command that writes a whole folder checks before it writes anything.
void checkOutputFolder(const std::string& folder);
// Moves the complete folder `staging` into place as `folder` in one step. Entries of `folder` that
// `staging` does not have are hard-linked (or copied) into it first, so files the new result does
// not replace stay; writeFileAtomic temporaries are left behind. Then the two folders are
// exchanged atomically (renameat2 RENAME_EXCHANGE; a plain rename when `folder` does not exist
// yet) and the previous folder, now at the staging path, is removed. A failure before the exchange
// leaves `folder` untouched. On a file system without RENAME_EXCHANGE the previous folder is
// renamed aside first, so `folder` is missing for the moment between two renames.
void publishFolder(const std::string& staging, const std::string& folder);

}  // namespace armstudy

namespace armstudy {

// An advisory lock (flock) on `path` (created when missing) for this process, released by the
// destructor or when the process dies (even by SIGKILL). Throws InputError(`subject`, "another
// armstudy run is writing to this output folder ...") when another process holds it.
class FileLock {
 public:
  FileLock(const std::string& path, const std::string& subject);
  ~FileLock();
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_ = -1;
};

// Exclusive use of an output folder for one process: creates the folder (an
// InputError naming it when that fails), takes an advisory lock on <folder>/.armstudy.lock
// (InputError "another armstudy run is writing to <folder>" when another process holds it; the
// kernel releases it when a process dies, even by SIGKILL; the lock file is opened without
// following a link), refuses a symbolic link anywhere below the folder (an InputError naming it:
// the run would write through it), then removes the temporaries (`*.tmp.<pid>`) that
// writeFileAtomic of a killed run left behind. The destructor releases the
// lock (the empty lock file stays).
class OutputFolderLock {
 public:
  explicit OutputFolderLock(const std::string& folder);
  ~OutputFolderLock();
  OutputFolderLock(const OutputFolderLock&) = delete;
  OutputFolderLock& operator=(const OutputFolderLock&) = delete;
  int staleTemporariesRemoved() const { return removed_; }

 private:
  std::optional<FileLock> lock_;
  int removed_ = 0;
};

}  // namespace armstudy
