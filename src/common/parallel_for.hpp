#pragma once
// A parallel loop whose iterations may throw (one must not leave an OpenMP region by an
// exception): every iteration runs, the exceptions are kept per index, and after the loop the
// first one in index order is rethrown, so which error a caller sees does not depend on timing.
#include <exception>
#include <vector>

namespace armstudy {

// Runs body(k) for k in [0, n) on `threads` threads (dynamic schedule, one iteration at a time).
template <class Body>
void parallelFor(int n, int threads, const Body& body) {
  std::vector<std::exception_ptr> errors(n > 0 ? n : 0);
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (int k = 0; k < n; ++k) {
    try {
      body(k);
    } catch (...) {
      errors[k] = std::current_exception();
    }
  }
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace armstudy
