#pragma once
// The three failure channels of armstudy (docs/architecture.md):
//  1. InputError: bad input in a design, study or data file. Carries file, line and key;
//     caught once in main, printed once, non-zero exit, nothing half-written.
//  2. ARMSTUDY_CHECK: a broken programmer precondition. Always on; aborts with a message.
//  3. Expected numerical outcomes (unreachable, singular, in collision): status values in
//     result structs, never exceptions.
#include <stdexcept>
#include <string>

namespace armstudy {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, std::string key, const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  int line_;
  std::string key_;
  std::string message_;
};

[[noreturn]] void checkFailed(const char* expr, const char* file, int line, const std::string& msg);

}  // namespace armstudy

#define ARMSTUDY_CHECK(cond, msg)                                         \
  do {                                                                    \
    if (!(cond)) ::armstudy::checkFailed(#cond, __FILE__, __LINE__, msg); \
  } while (0)
