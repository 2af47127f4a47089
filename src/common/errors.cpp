#include "common/errors.hpp"

#include <cstdio>
#include <cstdlib>

namespace armstudy {

static std::string formatInputError(const std::string& file, int line, const std::string& key,
                                    const std::string& message) {
  std::string s = file.empty() ? std::string("<input>") : file;
  if (line > 0) {
    s += ':';
    s += std::to_string(line);
  }
  s += ": ";
  if (!key.empty()) {
    s += "key '";
    s += key;
    s += "': ";
  }
  s += message;
  return s;
}

InputError::InputError(std::string file, int line, std::string key, const std::string& message)
    : std::runtime_error(formatInputError(file, line, key, message)),
      file_(std::move(file)),
      line_(line),
      key_(std::move(key)),
      message_(message) {}

void checkFailed(const char* expr, const char* file, int line, const std::string& msg) {
  std::fprintf(stderr, "armstudy: internal check failed: %s (%s:%d): %s\n", expr, file, line,
               msg.c_str());
  std::abort();
}

}  // namespace armstudy
