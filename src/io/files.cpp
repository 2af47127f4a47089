#include "io/files.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/defaults.hpp"
#include "common/errors.hpp"

namespace armstudy {

std::string readFileOrThrow(const std::string& path) {
  // Only regular files of bounded size: a FIFO would block forever, /dev/zero never ends.
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st)) throw InputError(path, 0, "", "cannot open file (it does not exist)");
  if (!std::filesystem::is_regular_file(st))
    throw InputError(path, 0, "", "not a regular file (a directory, FIFO or device); armstudy reads only regular files");
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > defaults::kMaxInputFileBytes)
    throw InputError(path, 0, "", "file of " + std::to_string(size) + " bytes exceeds the input limit of " +
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

void writeFileAtomic(const std::string& path, const std::string& content) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  if (target.has_parent_path()) fs::create_directories(target.parent_path());
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw std::runtime_error("cannot write " + tmp);
    const bool ok = std::fwrite(content.data(), 1, content.size(), f) == content.size() &&
                    std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
    std::fclose(f);
    if (!ok) {
      std::remove(tmp.c_str());
      throw std::runtime_error("cannot write " + tmp);
    }
  }
  fs::rename(tmp, target);
}

OutputFolderLock::OutputFolderLock(const std::string& folder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec || !fs::is_directory(folder))
    throw InputError(folder, 0, "", "cannot create the output folder" + (ec ? ": " + ec.message() : std::string()));
  path_ = (fs::path(folder) / ".armstudy.lock").string();
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw InputError(folder, 0, "", "cannot write into the output folder");
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw InputError(folder, 0, "", "another armstudy run is writing to this output folder; wait for it or choose "
                                    "another --output");
  }
  // Temporaries of writeFileAtomic ("<name>.tmp.<pid>") left by a killed run: no other run can be
  // writing here now.
  for (auto it = fs::recursive_directory_iterator(folder, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const auto dot = name.rfind(".tmp.");
    if (dot == std::string::npos || dot + 5 >= name.size() || !it->is_regular_file()) continue;
    if (name.find_first_not_of("0123456789", dot + 5) != std::string::npos) continue;
    std::error_code rm;
    if (fs::remove(it->path(), rm)) ++removed_;
  }
}

OutputFolderLock::~OutputFolderLock() {
  // The lock file stays (removing it would let a run that opened it just before lock a file no
  // later run sees); closing releases the lock.
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace armstudy
