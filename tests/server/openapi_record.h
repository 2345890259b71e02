// Recording every HTTP answer a black-box test receives, and checking them all against
// server/openapi.json once the test binary's tests are done (issue 13: the document cannot drift
// from the code). tests/server/openapi_check.py does the checking: JSON bodies against the
// schema of their route and status, text/event-stream bodies event by event (each event's data
// against the schema the document names for it in `x-events`).
#pragma once

#include <httplib.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "../planner/test_util.h"

namespace ctb::testing {

// Every answer a black-box test received, checked at the end of the test binary against
// server/openapi.json by tests/server/openapi_check.py (see OpenApiCheck below).
struct RecordedAnswer {
  std::string method, path, content_type, body;
  int status = 0;
};
inline std::mutex& AnswersMutex() {
  static std::mutex mu;
  return mu;
}
inline std::vector<RecordedAnswer>& Answers() {
  static std::vector<RecordedAnswer> all;
  return all;
}
inline void Record(const std::string& method, const std::string& path, int status, const std::string& content_type,
                   const std::string& body) {
  if (status == 0) return;
  std::lock_guard<std::mutex> lock(AnswersMutex());
  if (Answers().size() < 5000) Answers().push_back({method, path.substr(0, 200), content_type, body.substr(0, 1 << 20), status});
}
inline void Record(const std::string& method, const std::string& path, const httplib::Result& r) {
  if (r) Record(method, path, r->status, r->get_header_value("Content-Type"), r->body);
}

// Writes the answers as JSON lines and runs the checker; true when every answer conforms.
inline bool CheckAnswersAgainstOpenApi(std::string* output) {
  const std::string file = "/tmp/ctb-answers-" + std::to_string(getpid()) + ".jsonl";
  {
    std::ofstream out(file);
    std::lock_guard<std::mutex> lock(AnswersMutex());
    for (const auto& a : Answers())
      out << nlohmann::json({{"method", a.method}, {"path", a.path}, {"status", a.status},
                             {"content_type", a.content_type}, {"body", a.body}})
                 .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)
          << "\n";
  }
  const std::string cmd = "python3 " + SourceDir() + "/tests/server/openapi_check.py " + SourceDir() +
                          "/server/openapi.json " + file + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return false;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) output->append(buf, n);
  int rc = pclose(p);
  std::remove(file.c_str());
  return rc == 0;
}

// A test environment that checks all recorded answers once the tests are done.
class OpenApiCheck : public ::testing::Environment {
 public:
  void TearDown() override {
    std::string out;
    bool ok = CheckAnswersAgainstOpenApi(&out);
    EXPECT_TRUE(ok) << "answers that do not match server/openapi.json:\n" << out;
    std::fprintf(stderr, "openapi check: %s", out.c_str());
  }
};

// An httplib client whose Get/Post/Put/Delete (the forms the tests use) record their answers.
// The other overloads (a chunked content provider, ...) are httplib's own and record nothing.
class RecordingClient : public httplib::Client {
 public:
  using httplib::Client::Client;
  using httplib::Client::Delete;
  using httplib::Client::Get;
  using httplib::Client::Post;
  using httplib::Client::Put;
  httplib::Result Get(const std::string& path) { return Kept("GET", path, httplib::Client::Get(path)); }
  httplib::Result Get(const std::string& path, const httplib::Headers& h) {
    return Kept("GET", path, httplib::Client::Get(path, h));
  }
  httplib::Result Post(const std::string& path, const std::string& body, const std::string& type) {
    return Kept("POST", path, httplib::Client::Post(path, body, type));
  }
  httplib::Result Post(const std::string& path, const httplib::Headers& h, const std::string& body,
                       const std::string& type) {
    return Kept("POST", path, httplib::Client::Post(path, h, body, type));
  }
  httplib::Result Put(const std::string& path, const std::string& body, const std::string& type) {
    return Kept("PUT", path, httplib::Client::Put(path, body, type));
  }
  httplib::Result Delete(const std::string& path) { return Kept("DELETE", path, httplib::Client::Delete(path)); }

 private:
  static httplib::Result Kept(const char* method, const std::string& path, httplib::Result r) {
    Record(method, path, r);
    return r;
  }
};

}  // namespace ctb::testing
