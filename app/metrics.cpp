#include "app/metrics.h"

#include <sstream>

namespace ctb::app {

const std::vector<double>& Metrics::Buckets() {
  static const std::vector<double> b = {0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 60};
  return b;
}

void Metrics::Request(const std::string& route, int status, double seconds) {
  std::lock_guard<std::mutex> lock(mu_);
  ++requests_[{route, status}];
  auto& h = latency_[route];
  if (h.empty()) h.assign(Buckets().size() + 1, 0);
  for (std::size_t i = 0; i < Buckets().size(); ++i)
    if (seconds <= Buckets()[i]) ++h[i];
  ++h.back();
  latency_sum_[route] += seconds;
}

void Metrics::LlmCall(int calls, int repairs) {
  std::lock_guard<std::mutex> lock(mu_);
  llm_calls_ += calls;
  llm_repairs_ += repairs;
}

std::string Metrics::Render() const {
  std::lock_guard<std::mutex> lock(mu_);
  std::ostringstream o;
  o << "# HELP ctb_http_requests_total HTTP requests by route and status.\n"
       "# TYPE ctb_http_requests_total counter\n";
  for (const auto& [k, v] : requests_)
    o << "ctb_http_requests_total{route=\"" << k.first << "\",status=\"" << k.second << "\"} " << v << "\n";
  o << "# HELP ctb_http_request_duration_seconds Request latency by route.\n"
       "# TYPE ctb_http_request_duration_seconds histogram\n";
  for (const auto& [route, h] : latency_) {
    for (std::size_t i = 0; i < Buckets().size(); ++i)
      o << "ctb_http_request_duration_seconds_bucket{route=\"" << route << "\",le=\"" << Buckets()[i]
        << "\"} " << h[i] << "\n";
    o << "ctb_http_request_duration_seconds_bucket{route=\"" << route << "\",le=\"+Inf\"} " << h.back() << "\n";
    o << "ctb_http_request_duration_seconds_sum{route=\"" << route << "\"} " << latency_sum_.at(route) << "\n";
    o << "ctb_http_request_duration_seconds_count{route=\"" << route << "\"} " << h.back() << "\n";
  }
  o << "# HELP ctb_solver_jobs_running Solver jobs running.\n# TYPE ctb_solver_jobs_running gauge\n"
    << "ctb_solver_jobs_running " << solver_running.load() << "\n";
  o << "# HELP ctb_solver_jobs_queued Solver jobs waiting for a slot.\n# TYPE ctb_solver_jobs_queued gauge\n"
    << "ctb_solver_jobs_queued " << solver_queued.load() << "\n";
  o << "# HELP ctb_solver_jobs_rejected_total Solver jobs refused (queue full).\n"
       "# TYPE ctb_solver_jobs_rejected_total counter\n"
    << "ctb_solver_jobs_rejected_total " << solver_rejected.load() << "\n";
  o << "# HELP ctb_llm_calls_total LLM requests made.\n# TYPE ctb_llm_calls_total counter\n"
    << "ctb_llm_calls_total " << llm_calls_ << "\n";
  o << "# HELP ctb_llm_repairs_total Repair requests sent to the LLM.\n# TYPE ctb_llm_repairs_total counter\n"
    << "ctb_llm_repairs_total " << llm_repairs_ << "\n";
  return o.str();
}

}  // namespace ctb::app
