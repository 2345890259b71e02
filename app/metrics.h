// Prometheus text-format metrics. Thread-safe.
#pragma once

#include <atomic>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace ctb::app {

class Metrics {
 public:
  void Request(const std::string& route, int status, double seconds);
  void LlmCall(int calls, int repairs);
  std::atomic<int> solver_running{0};
  std::atomic<int> solver_queued{0};
  std::atomic<long> solver_rejected{0};
  std::string Render() const;

 private:
  static const std::vector<double>& Buckets();
  mutable std::mutex mu_;
  std::map<std::pair<std::string, int>, long> requests_;
  std::map<std::string, std::vector<long>> latency_;  // cumulative bucket counts + count
  std::map<std::string, double> latency_sum_;
  long llm_calls_ = 0, llm_repairs_ = 0;
};

}  // namespace ctb::app
