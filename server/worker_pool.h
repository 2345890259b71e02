// The HTTP server's worker threads, started on demand and retired when idle.
//
// cpp-httplib's own pool starts all its threads at once and wakes any of them for a job, so over
// a day of traffic every thread (144 at the defaults) has served requests and keeps glibc's
// per-thread cache of freed memory (up to 234 KiB each): the resident size creeps up by tens of
// MB (bench/results/soak.md). This pool hands a job to the thread that went idle last, starts a
// thread only when none is idle (up to the cap), and lets a thread that stayed idle for
// `idle_retire` end, which gives its cache back. The threads that serve are then as many as the
// requests at once, not as many as the cap.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace ctb::server {

class WorkerPool {
 public:
  struct Options {
    int max_threads = 8;                                  // at most this many at once
    std::chrono::milliseconds idle_retire{30'000};        // an idle thread ends after this
  };
  struct Stats {
    int threads = 0;        // running now (serving or idle)
    int idle = 0;           // of which waiting for a job
    int queued = 0;         // jobs waiting for a thread (all threads busy at the cap)
    long started = 0;       // threads started since the pool was made
    long retired = 0;       // threads that ended after idling
  };

  explicit WorkerPool(Options options);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  // Runs `job` on an idle thread (the one idle the shortest time), on a new thread when none is
  // idle and the cap allows, or else as soon as a thread is free. Ignored after Shutdown.
  void Enqueue(std::function<void()> job);
  // Runs the jobs already queued, then ends and joins every thread. Idempotent.
  void Shutdown();
  Stats stats() const;

 private:
  struct Worker {
    std::condition_variable wake;
    std::function<void()> job;
    std::thread thread;
  };

  void Run(Worker* w);
  // Waits (lock held) for a job handed to `w`; false when the thread should end.
  bool WaitForJob(std::unique_lock<std::mutex>& lock, Worker* w);
  void Retire(Worker* w);  // lock held
  std::vector<std::unique_ptr<Worker>> TakeFinished();  // lock held

  const Options options_;
  mutable std::mutex mu_;
  bool shutdown_ = false;
  std::vector<Worker*> idle_;                     // a stack: back() went idle last
  std::deque<std::function<void()>> queue_;
  std::list<std::unique_ptr<Worker>> workers_;    // running
  std::vector<std::unique_ptr<Worker>> finished_; // retired, to be joined
  long started_ = 0;
  long retired_ = 0;
};

}  // namespace ctb::server
