// Internal to planner/smt: a thread that interrupts a z3 context at a deadline or on
// cancellation. Not a public header.
#pragma once

#include <z3++.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace ctb::smt {

// Interrupts the context at the deadline or on cancellation, every 20 ms until stopped (an
// interrupt that arrives between two checks could otherwise be lost).
class Watchdog {
 public:
  Watchdog(z3::context& z, std::chrono::steady_clock::time_point deadline,
           const std::atomic<bool>* cancel)
      : z_(z), deadline_(deadline), cancel_(cancel), thread_([this] { Loop(); }) {}
  ~Watchdog() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  bool Fired() const { return fired_.load(); }

 private:
  void Loop() {
    std::unique_lock<std::mutex> lock(mu_);
    while (!stop_) {
      cv_.wait_for(lock, std::chrono::milliseconds(20));
      if (stop_) break;
      if (std::chrono::steady_clock::now() >= deadline_ || (cancel_ && cancel_->load())) {
        fired_ = true;
        z_.interrupt();
      }
    }
  }

  z3::context& z_;
  std::chrono::steady_clock::time_point deadline_;
  const std::atomic<bool>* cancel_;
  std::mutex mu_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::atomic<bool> fired_{false};
  std::thread thread_;
};

}  // namespace ctb::smt
