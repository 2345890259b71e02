// A `ctburton serve` child process on a free loopback port, for black-box tests, with what a
// hostile-input test needs besides: the server's pid, its peak RSS (VmHWM from /proc) and raw
// sockets, optionally from another loopback source address (127.0.0.2) so per-address limits
// aimed at an attacker on 127.0.0.1 do not apply to the observer.
#pragma once

#include <arpa/inet.h>
#include <fcntl.h>
#include <httplib.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <mutex>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "../planner/test_util.h"
#include "../process_count.h"
#include "openapi_record.h"

namespace ctb::testing {

inline const bool kHarnessIgnoresSigpipe = [] {
  signal(SIGPIPE, SIG_IGN);
  return true;
}();

inline int FreeLoopbackPort() {
  int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
  int port = ntohs(a.sin_port);
  close(s);
  return port;
}

// A TCP connection to 127.0.0.1:port from `source` (another 127/8 address is still loopback).
// Returns -1 on failure.
inline int ConnectFrom(int port, const char* source = "127.0.0.1") {
  int s = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in src{};
  src.sin_family = AF_INET;
  inet_pton(AF_INET, source, &src.sin_addr);
  if (bind(s, reinterpret_cast<sockaddr*>(&src), sizeof src) != 0) {
    close(s);
    return -1;
  }
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    close(s);
    return -1;
  }
  return s;
}

inline bool SendAll(int s, const std::string& data) {
  std::size_t off = 0;
  while (off < data.size()) {
    ssize_t n = send(s, data.data() + off, data.size() - off, MSG_NOSIGNAL);
    if (n <= 0) return false;
    off += static_cast<std::size_t>(n);
  }
  return true;
}

// Reads until the peer closes or `ms` pass; returns what arrived.
inline std::string ReadAll(int s, long ms) {
  std::string out;
  auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
  char buf[8192];
  for (;;) {
    long left = std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now()).count();
    if (left <= 0) break;
    pollfd p{s, POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(left)) <= 0) break;
    ssize_t n = recv(s, buf, sizeof buf, 0);
    if (n <= 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  return out;
}

// A raw HTTP exchange on a fresh connection: status (0 when none arrived within ms) and body.
struct RawAnswer {
  int status = 0;
  std::string body;
  long ms = 0;
};
inline RawAnswer RawRequest(int port, const std::string& request, long ms = 5000,
                            const char* source = "127.0.0.1") {
  RawAnswer a;
  auto t0 = std::chrono::steady_clock::now();
  int s = ConnectFrom(port, source);
  if (s < 0) return a;
  SendAll(s, request);
  std::string text = ReadAll(s, ms);
  close(s);
  a.ms = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0).count();
  if (text.rfind("HTTP/1.1 ", 0) == 0) a.status = std::atoi(text.c_str() + 9);
  auto blank = text.find("\r\n\r\n");
  if (blank != std::string::npos) a.body = text.substr(blank + 4);
  std::string content_type;
  {
    std::string head = text.substr(0, blank == std::string::npos ? 0 : blank);
    std::string lower = head;
    for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    auto at = lower.find("\r\ncontent-type:");
    if (at != std::string::npos) {
      auto end = head.find("\r\n", at + 2);
      content_type = head.substr(at + 15, end - at - 15);
      while (!content_type.empty() && content_type.front() == ' ') content_type.erase(0, 1);
    }
  }
  const auto sp1 = request.find(' '), sp2 = request.find(' ', sp1 + 1);
  if (sp1 != std::string::npos && sp2 != std::string::npos)
    Record(request.substr(0, sp1), request.substr(sp1 + 1, sp2 - sp1 - 1), a.status, content_type, a.body);
  return a;
}

// GET /healthz from `source` with a deadline; the status, or 0.
inline RawAnswer Health(int port, const char* source = "127.0.0.2", long ms = 2000) {
  return RawRequest(port, "GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n", ms, source);
}

class ServerProcess {
 public:
  explicit ServerProcess(nlohmann::json config = nlohmann::json::object(),
                         std::vector<std::string> extra_args = {},
                         std::vector<std::pair<std::string, std::string>> env = {},
                         std::string log_path = "") {
    // The port is free when picked but another test's process may take it before the server
    // binds (tests run in parallel): a server that exits before it answers is started again on
    // another port.
    for (int attempt = 0; attempt < 3; ++attempt) {
      port_ = FreeLoopbackPort();
      std::string cfg_path;
      if (!config.empty()) {
        cfg_path = "/tmp/ctb-harness-" + std::to_string(getpid()) + "-" + std::to_string(port_) + ".json";
        std::ofstream(cfg_path) << config.dump();
      }
      pid_ = fork();
      if (pid_ == 0) Exec(cfg_path, extra_args, env, log_path);
      for (int i = 0; i < 400; ++i) {
        if (Health(port_, "127.0.0.1", 500).status == 200) return;
        int status = 0;
        if (waitpid(pid_, &status, WNOHANG) == pid_) {
          pid_ = -1;
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(25));
      }
      if (pid_ > 0) break;  // running but not answering: no second try
    }
    ADD_FAILURE() << "server did not start";
  }
  ~ServerProcess() {
    if (pid_ > 0 && Stop(5000) < 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  httplib::Client Client(long read_timeout_s = 60) const {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(read_timeout_s, 0);
    return c;
  }
  // SIGTERM; the exit status, or -1 when it did not exit within wait_ms.
  int Stop(long wait_ms) {
    kill(pid_, SIGTERM);
    for (long t = 0; t < wait_ms; t += 20) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }
  // SIGKILL, reaped.
  void Kill() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
  bool Alive() const {
    if (pid_ <= 0) return false;
    int status = 0;
    return waitpid(pid_, &status, WNOHANG) == 0;
  }
  // The server's peak resident set in MiB (VmHWM), -1 when unreadable.
  long PeakRssMb() const { return StatusField("VmHWM:"); }
  long RssMb() const { return StatusField("VmRSS:"); }
  // Children of the server whose command name is `comm`.
  std::vector<pid_t> Children(const std::string& comm) const {
    std::vector<pid_t> out;
    for (const auto& p : Processes())
      if (p.ppid == pid_ && p.comm == comm) out.push_back(static_cast<pid_t>(p.pid));
    return out;
  }

 private:
  long StatusField(const char* field) const {
    std::ifstream in("/proc/" + std::to_string(pid_) + "/status");
    std::string line;
    while (std::getline(in, line))
      if (line.rfind(field, 0) == 0) return std::atol(line.c_str() + std::strlen(field)) / 1024;
    return -1;
  }
  // In the child: the server's environment, output and arguments; never returns.
  [[noreturn]] void Exec(const std::string& cfg_path, std::vector<std::string> extra_args,
                         const std::vector<std::pair<std::string, std::string>>& env, const std::string& log_path) {
    for (const char* v : {"CTB_LLM_BASE_URL", "CTB_LLM_REPLAY", "CTB_LLM_RECORD", "CTB_LLM_API_KEY"}) unsetenv(v);
    setenv("CTB_DATA_DIR", ("/tmp/ctb-harness-data-" + std::to_string(getpid())).c_str(), 1);
    for (auto& [k, v] : env) setenv(k.c_str(), v.c_str(), 1);
    setenv("CTB_CONFIG_DIR", (SourceDir() + "/config").c_str(), 1);
    setenv("CTB_PROMPTS_DIR", (SourceDir() + "/prompts").c_str(), 1);
    int devnull = open("/dev/null", O_WRONLY);
    dup2(devnull, 1);
    if (!log_path.empty()) {
      int log = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(log, 2);
    }
    std::vector<std::string> args = {CTB_BINARY, "serve", "--port", std::to_string(port_)};
    if (!cfg_path.empty()) {
      args.push_back("--config");
      args.push_back(cfg_path);
    }
    for (auto& a : extra_args) args.push_back(a);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(CTB_BINARY, argv.data());
    _exit(127);
  }

  int port_ = 0;
  pid_t pid_ = -1;
};

// --- other processes: redis-server, nginx, a replica (the replica and gRPC suites) ---

inline bool Executable(const char* path) { return access(path, X_OK) == 0; }

inline pid_t Spawn(const std::vector<std::string>& args, const std::string& log) {
  pid_t pid = fork();
  if (pid == 0) {
    int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

// SIGTERM, then SIGKILL after 5 s; `pid` is set to -1 so that stopping twice is harmless (a
// reaped pid may already be another process's).
inline void StopChild(pid_t& pid) {
  if (pid <= 0) return;
  kill(pid, SIGTERM);
  for (int i = 0; i < 250; ++i) {
    if (waitpid(pid, nullptr, WNOHANG) == pid) {
      pid = -1;
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  pid = -1;
}

// Stops the child `pid` names when the scope ends, however the test leaves it (an ASSERT that
// returns early must not leave a redis-server running).
class StopAtExit {
 public:
  explicit StopAtExit(pid_t& pid) : pid_(pid) {}
  ~StopAtExit() { StopChild(pid_); }
  StopAtExit(const StopAtExit&) = delete;
  StopAtExit& operator=(const StopAtExit&) = delete;

 private:
  pid_t& pid_;
};

inline bool WaitForPort(int port, long ms) {
  for (long t = 0; t < ms; t += 25) {
    int s = ConnectFrom(port);
    if (s >= 0) {
      close(s);
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  return false;
}

// A fresh directory under /tmp for one test's data (a data dir, redis' dir), open to everyone
// (the server may drop privileges).
inline std::string TempDir(const std::string& tag) {
  std::string d = "/tmp/ctb-" + tag + "-" + std::to_string(getpid()) + "-" +
                  std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
  std::filesystem::create_directories(d);
  chmod(d.c_str(), 0777);
  return d;
}

}  // namespace ctb::testing
