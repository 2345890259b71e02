// Solver slots shared by every front end: at most `workers` solves run, at most `queue` wait;
// beyond that Enter() refuses. A place can be reserved ahead (a stream, before its 200 head is
// sent) and counts as admitted until it enters or is given back. Internal to the core.
// Thread-safe.
#pragma once

#include <atomic>
#include <condition_variable>
#include <mutex>

#include "app/metrics.h"

namespace ctb::app {

class JobGate {
 public:
  JobGate(int workers, int queue, Metrics& m) : workers_(workers), queue_(queue), m_(m) {}
  // Waits for a slot; false when every place is taken (running, waiting or reserved) or
  // `stopping` became true while waiting. With `reserved`, the place reserved before is used.
  bool Enter(const std::atomic<bool>& stopping, bool reserved = false) {
    std::unique_lock<std::mutex> lock(mu_);
    if (reserved) --reserved_;
    else if (running_ + waiting_ + reserved_ >= workers_ + queue_) return false;
    if (running_ >= workers_) {
      ++waiting_;
      m_.solver_queued = waiting_;
      cv_.wait(lock, [&] { return running_ < workers_ || stopping.load(); });
      --waiting_;
      m_.solver_queued = waiting_;
      if (stopping.load()) {
        cv_.notify_all();
        return false;
      }
    }
    m_.solver_running = ++running_;
    return true;
  }
  void Leave() {
    std::lock_guard<std::mutex> lock(mu_);
    m_.solver_running = --running_;
    cv_.notify_one();
  }
  void WakeAll() { cv_.notify_all(); }
  // A place held for a job that enters later; false when every place is taken.
  bool Reserve() {
    std::lock_guard<std::mutex> lock(mu_);
    if (running_ + waiting_ + reserved_ >= workers_ + queue_) return false;
    ++reserved_;
    return true;
  }
  void Unreserve() {
    std::lock_guard<std::mutex> lock(mu_);
    --reserved_;
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  int running_ = 0, waiting_ = 0, reserved_ = 0;
  const int workers_, queue_;
  Metrics& m_;
};

}  // namespace ctb::app
