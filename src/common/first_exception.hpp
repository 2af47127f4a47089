#pragma once
// Exceptions out of an OpenMP loop (one must not leave a parallel region): callbacks inside the
// loop run through FirstException::call, and rethrow() after the loop throws the first one caught.
#include <exception>
#include <utility>

namespace armstudy {

class FirstException {
 public:
  // Calls f(); keeps the exception it throws when it is the first one (thread-safe).
  template <class F>
  void call(F&& f) {
    try {
      std::forward<F>(f)();
    } catch (...) {
#pragma omp critical(armstudy_first_exception)
      if (!first_) first_ = std::current_exception();
    }
  }
  // Throws the kept exception, if any.
  void rethrow() const {
    if (first_) std::rethrow_exception(first_);
  }

 private:
  std::exception_ptr first_;
};

}  // namespace armstudy
