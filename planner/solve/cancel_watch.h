// A thread that watches a job's cancellation conditions while it runs (the core's jobs, the explainer's probes).
// It polls `should_cancel` every `period` and sets `flag` when it returns true (or throws);
// Stop() wakes it at once and joins it, so ending a job never waits for a poll period.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace ctb {

class CancelWatch {
 public:
  CancelWatch(std::atomic<bool>& flag, std::function<bool()> should_cancel,
              std::chrono::milliseconds period = std::chrono::milliseconds(100))
      : thread_([this, &flag, should_cancel = std::move(should_cancel), period]() noexcept {
          std::unique_lock<std::mutex> lock(mu_);
          while (!stopped_) {
            bool cancel = true;
            try {
              lock.unlock();
              cancel = should_cancel();
              lock.lock();
            } catch (...) {
              if (!lock.owns_lock()) lock.lock();
            }
            if (cancel) {
              flag = true;
              return;
            }
            cv_.wait_for(lock, period, [this] { return stopped_; });
          }
        }) {}
  CancelWatch(const CancelWatch&) = delete;
  CancelWatch& operator=(const CancelWatch&) = delete;
  ~CancelWatch() { Stop(); }

  // Idempotent; returns once the watching thread has ended.
  void Stop() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stopped_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  bool stopped_ = false;
  std::thread thread_;  // last: started once the members it uses exist
};

}  // namespace ctb
