#include "io/files.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "common/defaults.hpp"
#include "common/errors.hpp"

namespace armstudy {

std::string readFileOrThrow(const std::string& path) {
  // Only regular files of bounded size: a FIFO would block forever, /dev/zero never ends.
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st))
    throw InputError(path, 0, "", "cannot open file (it does not exist)");
  if (!std::filesystem::is_regular_file(st))
    throw InputError(
        path, 0, "",
        "not a regular file (a directory, FIFO or device); armstudy reads only regular files");
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > defaults::kMaxInputFileBytes)
    throw InputError(path, 0, "",
                     "file of " + std::to_string(size) + " bytes exceeds the input limit of " +
                         std::to_string(defaults::kMaxInputFileBytes) + " bytes");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string contentHash(const std::string& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string fileHash(const std::string& path) { return contentHash(readFileOrThrow(path)); }

namespace {

// InputError naming `path` when something other than a regular file or a symbolic link is there:
// renaming over it would replace a device, FIFO or socket with a regular file (a folder would
// fail half-way). A link is replaced by the new file, never followed, so its target stays as it
// was.
void refuseSpecialTarget(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode) || S_ISLNK(st.st_mode)) return;
  const char* what = S_ISDIR(st.st_mode)    ? "a folder"
                     : S_ISFIFO(st.st_mode) ? "a FIFO"
                     : S_ISCHR(st.st_mode)  ? "a character device"
                     : S_ISBLK(st.st_mode)  ? "a block device"
                     : S_ISSOCK(st.st_mode) ? "a socket"
                                            : "not a regular file";
  throw InputError(path, 0, "",
                   std::string("the output path is ") + what +
                       "; armstudy writes only regular files and leaves this one as it is: "
                       "choose another output path");
}

// A new temporary for writing `tmp`: created exclusively, never through a symbolic link (one left
// or planted at that name is removed first, not followed).
int openTemporary(const std::string& tmp) {
  constexpr int kFlags = O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC;
  int fd = ::open(tmp.c_str(), kFlags, 0666);
  if (fd < 0 && errno == EEXIST && ::unlink(tmp.c_str()) == 0)
    fd = ::open(tmp.c_str(), kFlags, 0666);
  return fd;
}

bool writeAll(int fd, const std::string& content) {
  std::size_t done = 0;
  while (done < content.size()) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return ::fsync(fd) == 0;
}

}  // namespace

void checkOutputPath(const std::string& path) { refuseSpecialTarget(path); }

void writeFileAtomic(const std::string& path, const std::string& content) {
  namespace fs = std::filesystem;
  refuseSpecialTarget(path);
  const fs::path target(path);
  if (target.has_parent_path()) fs::create_directories(target.parent_path());
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  const int fd = openTemporary(tmp);
  if (fd < 0) throw std::runtime_error("cannot write " + tmp + ": " + std::strerror(errno));
  const bool ok = writeAll(fd, content);
  const int err = errno;
  if (::close(fd) != 0 || !ok) {
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot write " + tmp + ": " + std::strerror(ok ? errno : err));
  }
  fs::rename(tmp, target);
}

namespace {

namespace fs = std::filesystem;

// `folder` with symbolic links resolved as far as it exists, without a trailing separator.
fs::path resolvedFolder(const std::string& folder) {
  fs::path p = fs::weakly_canonical(fs::absolute(fs::path(folder)));
  if (p.filename().empty()) p = p.parent_path();
  return p;
}

// "<name>.tmp.<digits>": a writeFileAtomic temporary.
bool isAtomicTemporary(const std::string& name) {
  const auto dot = name.rfind(".tmp.");
  return dot != std::string::npos && dot + 5 < name.size() &&
         name.find_first_not_of("0123456789", dot + 5) == std::string::npos;
}

}  // namespace

void checkOutputFolder(const std::string& folder) {
  std::error_code ec;
  const fs::file_status st = fs::status(folder, ec);
  if (fs::exists(st) && !fs::is_directory(st))
    throw InputError(folder, 0, "",
                     std::string("the output folder is ") +
                         (fs::is_regular_file(st) ? "a file" : "a FIFO, device or socket") +
                         ", not a folder; armstudy leaves it as it is: choose another --out");
}

std::string makeStagingFolder(const std::string& folder) {
  checkOutputFolder(folder);
  const fs::path target = resolvedFolder(folder);
  const std::string prefix = target.filename().string() + ".staging.",
                    aside = target.filename().string() + ".previous.";
  // The process id after `p` in `name`, when `name` is p<digits> and that process no longer exists.
  auto deadPid = [](const std::string& name, const std::string& p) {
    if (name.rfind(p, 0) != 0 || name.size() == p.size() ||
        name.find_first_not_of("0123456789", p.size()) != std::string::npos)
      return false;
    const long pid = std::strtol(name.c_str() + p.size(), nullptr, 10);
    return pid > 0 && pid != ::getpid() && ::kill(static_cast<pid_t>(pid), 0) != 0 &&
           errno == ESRCH;
  };
  std::error_code ec;
  // Leftovers of killed runs: the staging folder of a run killed before its swap, the previous
  // folder of a run killed between the swap and the removal, or (without RENAME_EXCHANGE) the
  // previous folder renamed aside, which goes back when the output folder is missing.
  for (auto it = fs::directory_iterator(target.parent_path(), ec);
       !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code rm;
    if (deadPid(name, prefix)) {
      fs::remove_all(it->path(), rm);
    } else if (deadPid(name, aside)) {
      if (!fs::exists(fs::symlink_status(target))) fs::rename(it->path(), target, rm);
      if (fs::exists(it->path())) fs::remove_all(it->path(), rm);
    }
  }
  ec.clear();
  const fs::path staging = target.parent_path() / (prefix + std::to_string(::getpid()));
  fs::remove_all(staging, ec);
  ec.clear();
  fs::create_directories(staging, ec);
  if (ec || !fs::is_directory(staging))
    throw InputError(folder, 0, "",
                     "cannot create the staging folder " + staging.string() +
                         " beside the output folder" + (ec ? ": " + ec.message() : std::string()));
  return staging.string();
}

void publishFolder(const std::string& staging, const std::string& folder) {
  const fs::path target = resolvedFolder(folder), from(staging);
  if (!fs::is_directory(from))
    throw std::runtime_error("cannot publish " + staging + ": not a folder");
  if (fs::exists(fs::symlink_status(target))) {
    // Keep what the new result does not replace (a compare's files beside a fit's, the history of
    // a folder this run did not write): hard links cost no copy and leave the previous folder as
    // it is until the exchange.
    for (auto it = fs::recursive_directory_iterator(target);
         it != fs::recursive_directory_iterator(); ++it) {
      const fs::path rel = it->path().lexically_relative(target), to = from / rel;
      const fs::file_status st = it->symlink_status();
      if (fs::exists(fs::symlink_status(to))) {
        // The new result's entry wins; a previous folder merges only into a new folder.
        if (fs::is_directory(st) && !fs::is_directory(fs::symlink_status(to)))
          it.disable_recursion_pending();
        continue;
      }
      if (fs::is_directory(st)) {
        fs::create_directory(to);
      } else if (fs::is_symlink(st)) {
        fs::copy_symlink(it->path(), to);
      } else if (fs::is_regular_file(st) && !isAtomicTemporary(rel.filename().string())) {
        std::error_code ec;
        fs::create_hard_link(it->path(), to, ec);
        if (ec) fs::copy_file(it->path(), to);
      }
    }
    if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
      // The previous folder, now at the staging path; a leftover goes with the next staging folder.
      std::error_code ec;
      fs::remove_all(from, ec);
      return;
    }
    if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP)
      throw std::runtime_error("cannot move " + staging + " into place as " + target.string() +
                               ": " + std::strerror(errno));
    const fs::path aside = target.parent_path() /
                           (target.filename().string() + ".previous." + std::to_string(::getpid()));
    fs::rename(target, aside);
    fs::rename(from, target);
    std::error_code ec;
    fs::remove_all(aside, ec);
    return;
  }
  fs::create_directories(target.parent_path());
  fs::rename(from, target);
}

FileLock::FileLock(const std::string& path, const std::string& subject) {
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd_ < 0 && errno == ELOOP)
    throw InputError(path, 0, "",
                     "the lock file is a symbolic link; armstudy never writes through links "
                     "there: remove it");
  if (fd_ < 0) throw InputError(subject, 0, "", "cannot write into the output folder");
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw InputError(subject, 0, "",
                     "another armstudy run is writing to this output folder; wait for it or choose "
                     "another --output");
  }
}

FileLock::~FileLock() {
  // The lock file stays (removing it would let a run that opened it just before lock a file no
  // later run sees); closing releases the lock.
  if (fd_ >= 0) ::close(fd_);
}

namespace {

// One pass over `folder` (the folder itself may be a link): an InputError naming the first
// symbolic link below it, through which the run would write out of the folder or onto another of
// its files; otherwise the temporaries of writeFileAtomic ("<name>.tmp.<pid>") a killed run left
// behind, which are removed. Returns their number.
int checkOutputFolderEntries(const std::string& folder) {
  std::vector<fs::path> stale;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(folder, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    std::error_code st;
    if (it->is_symlink(st))
      throw InputError(it->path().string(), 0, "",
                       "a symbolic link inside the output folder " + folder +
                           "; armstudy never writes through links there: remove it (or choose "
                           "another --output)");
    if (isAtomicTemporary(it->path().filename().string()) && it->is_regular_file(st))
      stale.push_back(it->path());
  }
  int removed = 0;
  for (const fs::path& p : stale) removed += fs::remove(p, ec) ? 1 : 0;
  return removed;
}

}  // namespace

OutputFolderLock::OutputFolderLock(const std::string& folder) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec || !fs::is_directory(folder))
    throw InputError(
        folder, 0, "",
        "cannot create the output folder" + (ec ? ": " + ec.message() : std::string()));
  lock_.emplace((fs::path(folder) / ".armstudy.lock").string(), folder);
  removed_ = checkOutputFolderEntries(folder);  // no other run can be writing here now
}

OutputFolderLock::~OutputFolderLock() = default;

}  // namespace armstudy
