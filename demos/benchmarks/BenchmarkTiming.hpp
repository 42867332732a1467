// SPDX-License-Identifier: Zlib
#pragma once
// Timing shared by the benchmark programs: medians, because these machines are shared and noisy.

#include <algorithm>
#include <chrono>
#include <functional>
#include <vector>

namespace hydrotex::bench {

/// Median wall time of `runs` calls of `work` (ms), each call timed on its own.
inline double medianMs(int runs, const std::function<void()>& work) {
  std::vector<double> times;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    work();
    times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

}  // namespace hydrotex::bench
