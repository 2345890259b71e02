// Milliseconds since a point of the steady clock: the solvers' budgets and answer times.
#pragma once

#include <chrono>

namespace ctb {

inline long MsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0)
      .count();
}

}  // namespace ctb
