#include "server/log_context.h"

#include <spdlog/pattern_formatter.h>
#include <spdlog/spdlog.h>

namespace ctb::server {

namespace {

thread_local std::string g_request_id;

class RequestIdFlag : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg&, const std::tm&, spdlog::memory_buf_t& dest) override {
    dest.append(g_request_id.data(), g_request_id.data() + g_request_id.size());
  }
  std::unique_ptr<custom_flag_formatter> clone() const override {
    return std::make_unique<RequestIdFlag>();
  }
};

}  // namespace

void SetThreadRequestId(const std::string& id) { g_request_id = id; }
const std::string& ThreadRequestId() { return g_request_id; }

void InstallJsonLogPattern() {
  auto f = std::make_unique<spdlog::pattern_formatter>();
  // Request ids are [A-Za-z0-9._-] only (checked on input), so they need no JSON escaping.
  f->add_flag<RequestIdFlag>('*').set_pattern(
      R"({"ts":"%Y-%m-%dT%H:%M:%S.%e","level":"%l","request_id":"%*","log":%v})");
  spdlog::set_formatter(std::move(f));
}

}  // namespace ctb::server
