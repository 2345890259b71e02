// The HTTP server's worker pool (server/worker_pool.h): threads on demand up to the cap, the
// thread idle the shortest time reused first, idle threads retired, queued jobs run at shutdown.
// No test waits a fixed time: each waits for a state the pool must reach (up to a minute).
#include "server/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

namespace ctb::server {
namespace {

using namespace std::chrono_literals;

template <class Pred>
bool WaitUntil(Pred pred) {
  auto deadline = std::chrono::steady_clock::now() + 60s;
  while (!pred()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(1ms);
  }
  return true;
}

// A gate the jobs wait at until the test opens it.
class Gate {
 public:
  void Wait() {
    std::unique_lock<std::mutex> lock(mu_);
    ++waiting_;
    cv_.notify_all();
    cv_.wait(lock, [&] { return open_; });
  }
  void Open() {
    std::lock_guard<std::mutex> lock(mu_);
    open_ = true;
    cv_.notify_all();
  }
  int waiting() {
    std::lock_guard<std::mutex> lock(mu_);
    return waiting_;
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  int waiting_ = 0;
  bool open_ = false;
};

WorkerPool::Options Cap(int n, std::chrono::milliseconds retire = 60s) { return {n, retire}; }

TEST(WorkerPool, JobsOneAfterAnotherRunOnOneThread) {
  WorkerPool pool(Cap(16));
  std::set<std::thread::id> ran_on;
  std::mutex mu;
  for (int i = 0; i < 40; ++i) {
    std::atomic<bool> done{false};
    pool.Enqueue([&] {
      std::lock_guard<std::mutex> lock(mu);
      ran_on.insert(std::this_thread::get_id());
      done = true;
    });
    ASSERT_TRUE(WaitUntil([&] { return done && pool.stats().idle == 1; }));
  }
  EXPECT_EQ(ran_on.size(), 1u);
  EXPECT_EQ(pool.stats().started, 1);
  EXPECT_EQ(pool.stats().threads, 1);
}

TEST(WorkerPool, StartsAThreadPerJobAtOnceUpToTheCapThenQueues) {
  WorkerPool pool(Cap(3));
  Gate gate;
  std::atomic<int> finished{0};
  for (int i = 0; i < 5; ++i) pool.Enqueue([&] { gate.Wait(); ++finished; });
  ASSERT_TRUE(WaitUntil([&] { return gate.waiting() == 3; }));
  WorkerPool::Stats s = pool.stats();
  EXPECT_EQ(s.threads, 3);
  EXPECT_EQ(s.idle, 0);
  EXPECT_EQ(s.queued, 2);
  gate.Open();
  ASSERT_TRUE(WaitUntil([&] { return finished == 5 && pool.stats().idle == 3; }));
  EXPECT_EQ(pool.stats().started, 3);
  EXPECT_EQ(pool.stats().queued, 0);
}

TEST(WorkerPool, TheThreadIdleTheShortestTimeTakesTheNextJob) {
  WorkerPool pool(Cap(4));
  Gate first, second;
  std::thread::id a, b, next;
  pool.Enqueue([&] { a = std::this_thread::get_id(); first.Wait(); });
  pool.Enqueue([&] { b = std::this_thread::get_id(); second.Wait(); });
  ASSERT_TRUE(WaitUntil([&] { return first.waiting() == 1 && second.waiting() == 1; }));
  first.Open();  // a goes idle first ...
  ASSERT_TRUE(WaitUntil([&] { return pool.stats().idle == 1; }));
  second.Open();  // ... then b
  ASSERT_TRUE(WaitUntil([&] { return pool.stats().idle == 2; }));
  std::atomic<bool> done{false};
  pool.Enqueue([&] { next = std::this_thread::get_id(); done = true; });
  ASSERT_TRUE(WaitUntil([&] { return done.load(); }));
  EXPECT_NE(a, b);
  EXPECT_EQ(next, b);
}

TEST(WorkerPool, IdleThreadsEndAndTheirPlacesAreTakenAgain) {
  WorkerPool pool(Cap(4, 20ms));
  Gate gate;
  std::atomic<int> finished{0};
  for (int i = 0; i < 4; ++i) pool.Enqueue([&] { gate.Wait(); ++finished; });
  ASSERT_TRUE(WaitUntil([&] { return gate.waiting() == 4; }));
  gate.Open();
  ASSERT_TRUE(WaitUntil([&] { return pool.stats().threads == 0; }));
  EXPECT_EQ(finished, 4);
  EXPECT_EQ(pool.stats().retired, 4);
  std::atomic<bool> done{false};
  pool.Enqueue([&] { done = true; });  // joins the retired threads and starts a fresh one
  ASSERT_TRUE(WaitUntil([&] { return done.load(); }));
  EXPECT_EQ(pool.stats().started, 5);
}

TEST(WorkerPool, ShutdownRunsWhatIsQueuedThenIgnoresNewJobs) {
  WorkerPool pool(Cap(1));
  Gate gate;
  std::atomic<int> ran{0};
  pool.Enqueue([&] { gate.Wait(); ++ran; });
  ASSERT_TRUE(WaitUntil([&] { return gate.waiting() == 1; }));
  for (int i = 0; i < 5; ++i) pool.Enqueue([&] { ++ran; });
  EXPECT_EQ(pool.stats().queued, 5);
  gate.Open();
  pool.Shutdown();
  EXPECT_EQ(ran, 6);
  EXPECT_EQ(pool.stats().threads, 0);
  pool.Enqueue([&] { ++ran; });
  pool.Shutdown();
  EXPECT_EQ(ran, 6);
}

}  // namespace
}  // namespace ctb::server
