#include "server/worker_pool.h"

#include <algorithm>
#include <utility>

namespace ctb::server {

namespace {
WorkerPool::Options AtLeastOneThread(WorkerPool::Options o) {
  o.max_threads = std::max(o.max_threads, 1);
  return o;
}
}  // namespace

WorkerPool::WorkerPool(Options options) : options_(AtLeastOneThread(options)) {}

WorkerPool::~WorkerPool() { Shutdown(); }

void WorkerPool::Enqueue(std::function<void()> job) {
  std::vector<std::unique_ptr<Worker>> done;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (shutdown_) return;
    done = TakeFinished();
    if (!idle_.empty()) {
      Worker* w = idle_.back();
      idle_.pop_back();
      w->job = std::move(job);
      w->wake.notify_one();
    } else if (static_cast<int>(workers_.size()) < options_.max_threads) {
      auto w = std::make_unique<Worker>();
      w->job = std::move(job);
      Worker* raw = w.get();
      workers_.push_back(std::move(w));
      ++started_;
      raw->thread = std::thread([this, raw] { Run(raw); });
    } else {
      queue_.push_back(std::move(job));
    }
  }
  for (auto& w : done) w->thread.join();  // they have left Run already: quick
}

void WorkerPool::Run(Worker* w) {
  std::function<void()> job = std::move(w->job);
  w->job = nullptr;
  for (;;) {
    job();
    job = nullptr;
    std::unique_lock<std::mutex> lock(mu_);
    if (!queue_.empty()) {
      job = std::move(queue_.front());
      queue_.pop_front();
      continue;
    }
    if (!WaitForJob(lock, w)) return;
    job = std::move(w->job);
    w->job = nullptr;
  }
}

bool WorkerPool::WaitForJob(std::unique_lock<std::mutex>& lock, Worker* w) {
  if (shutdown_) return false;
  idle_.push_back(w);
  bool woken = w->wake.wait_for(lock, options_.idle_retire, [&] { return w->job || shutdown_; });
  if (w->job) return true;  // Enqueue took it off the idle stack
  idle_.erase(std::find(idle_.begin(), idle_.end(), w));
  if (!woken && !shutdown_) Retire(w);
  return false;
}

void WorkerPool::Retire(Worker* w) {
  auto it = std::find_if(workers_.begin(), workers_.end(), [&](auto& p) { return p.get() == w; });
  finished_.push_back(std::move(*it));
  workers_.erase(it);
  ++retired_;
}

std::vector<std::unique_ptr<WorkerPool::Worker>> WorkerPool::TakeFinished() {
  std::vector<std::unique_ptr<Worker>> out;
  out.swap(finished_);
  return out;
}

void WorkerPool::Shutdown() {
  std::list<std::unique_ptr<Worker>> running;
  std::vector<std::unique_ptr<Worker>> done;
  {
    std::lock_guard<std::mutex> lock(mu_);
    shutdown_ = true;
    for (Worker* w : idle_) w->wake.notify_one();
    running.swap(workers_);
    done = TakeFinished();
  }
  for (auto& w : running) w->thread.join();
  for (auto& w : done) w->thread.join();
}

WorkerPool::Stats WorkerPool::stats() const {
  std::lock_guard<std::mutex> lock(mu_);
  Stats s;
  s.threads = static_cast<int>(workers_.size());
  s.idle = static_cast<int>(idle_.size());
  s.queued = static_cast<int>(queue_.size());
  s.started = started_;
  s.retired = retired_;
  return s;
}

}  // namespace ctb::server
