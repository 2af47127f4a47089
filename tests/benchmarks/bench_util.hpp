#pragma once
// Minimal timing harness for the on-demand benchmarks: repeated timed batches, median reported.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace armstudy::bench {

// Runs fn() `iters` times per batch, `batches` times; returns the median time per call [s].
template <class Fn>
double timePerCall(Fn&& fn, int iters, int batches = 7) {
  std::vector<double> t;
  for (int b = 0; b < batches; ++b) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < iters; ++i) fn(i);
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() /
                iters);
  }
  std::nth_element(t.begin(), t.begin() + t.size() / 2, t.end());
  return t[t.size() / 2];
}

// Keeps the optimiser from dropping a computed value.
inline void doNotOptimize(double v) { asm volatile("" : : "g"(v) : "memory"); }

}  // namespace armstudy::bench
