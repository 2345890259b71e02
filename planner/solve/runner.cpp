#include "planner/model/elapsed.h"
#include "planner/solve/runner.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

extern char** environ;

namespace ctb {

const char* RunStatusName(RunResult::Status s) {
  switch (s) {
    case RunResult::Status::kOptimal: return "optimal";
    case RunResult::Status::kFeasible: return "feasible";
    case RunResult::Status::kInfeasible: return "infeasible";
    case RunResult::Status::kUnknown: return "unknown";
    case RunResult::Status::kCancelled: return "cancelled";
    case RunResult::Status::kError: return "error";
  }
  return "error";
}

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr std::size_t kMaxStderr = 16 * 1024;
constexpr std::size_t kMaxLine = 64 * 1024 * 1024;
constexpr long kGraceMs = 1500;   // after the time limit, before SIGTERM
constexpr long kTermMs = 1000;    // after SIGTERM, before SIGKILL

// A temporary directory removed on destruction.
struct TempDir {
  std::string path;
  TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string templ = std::string(base && *base ? base : "/tmp") + "/ctb-job-XXXXXX";
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    if (mkdtemp(buf.data())) path = buf.data();
  }
  ~TempDir() {
    if (path.empty()) return;
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// Kills every process whose working directory is `dir` (solver processes minizinc started in
// groups of their own). Returns the pids signalled.
std::vector<pid_t> KillProcessesIn(const std::string& dir) {
  std::vector<pid_t> killed;
  std::error_code ec;
  fs::path target = fs::weakly_canonical(dir, ec);
  for (const auto& entry : fs::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::error_code ec2;
    fs::path cwd = fs::read_symlink(entry.path() / "cwd", ec2);
    if (ec2 || cwd != target) continue;
    pid_t pid = static_cast<pid_t>(std::stol(name));
    if (pid == getpid()) continue;
    kill(pid, SIGKILL);
    killed.push_back(pid);
  }
  return killed;
}

// Solver processes (fzn-*) that were reparented to us as subreaper when their minizinc died.
// Our own direct children are minizinc processes, so reaping these steals no job's status.
std::vector<pid_t> OrphanedSolvers() {
  std::vector<pid_t> out;
  std::error_code ec;
  const pid_t self = getpid();
  for (const auto& entry : fs::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(entry.path() / "stat");
    std::string stat;
    std::getline(in, stat);
    auto open = stat.find('('), close = stat.rfind(')');
    if (open == std::string::npos || close == std::string::npos) continue;
    std::string comm = stat.substr(open + 1, close - open - 1);
    std::istringstream rest(stat.substr(close + 2));
    char state;
    long ppid = 0;
    rest >> state >> ppid;
    if (ppid == self && comm.rfind("fzn-", 0) == 0) out.push_back(static_cast<pid_t>(std::stol(name)));
  }
  return out;
}

bool WriteFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  return static_cast<bool>(out);
}

void SetNonBlocking(int fd) { fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK); }

class LineHandler {
 public:
  LineHandler(RunResult& r, const RunRequest& req, Clock::time_point t0)
      : r_(r), req_(req), t0_(t0) {}

  void Feed(const char* data, std::size_t n) {
    buf_.append(data, n);
    std::size_t pos;
    while ((pos = buf_.find('\n')) != std::string::npos) {
      Handle(buf_.substr(0, pos));
      buf_.erase(0, pos + 1);
    }
    if (buf_.size() > kMaxLine) {  // a runaway line: drop it
      buf_.clear();
      overflow_ = true;
    }
  }
  void Finish() {
    if (!buf_.empty()) Handle(buf_);
    buf_.clear();
  }
  std::optional<std::string> status;
  bool error_message = false;
  bool timed_out = false;  // MiniZinc reported its own time limit as an error
  bool overflow_ = false;

 private:
  void Handle(const std::string& line) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) return;
    Json j = Json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object()) return;
    std::string type = j.value("type", "");
    if (type == "solution") {
      const Json* out = nullptr;
      if (j.contains("output") && j["output"].is_object() && j["output"].contains("json"))
        out = &j["output"]["json"];
      if (!out) return;
      r_.best = *out;
      if (r_.solutions++ == 0) r_.first_solution_ms = MsSince(t0_);
      if (req_.on_solution) req_.on_solution(*out);
    } else if (type == "status") {
      status = j.value("status", "");
    } else if (type == "error") {
      // MiniZinc's own time limit, when it strikes in flattening under load, comes as an error
      // whose `what` is "time out": a time-out, not a rejected model (contract: feasible/unknown).
      const std::string what = j.value("what", "error");
      if (what.find("time out") != std::string::npos || what.find("timeout") != std::string::npos) {
        timed_out = true;
        return;
      }
      error_message = true;
      if (r_.error.empty()) r_.error = "the solver rejected the model (" + what + ")";
    } else if (type == "statistics" && j.contains("statistics") && j["statistics"].is_object()) {
      for (const auto& [k, v] : j["statistics"].items()) r_.statistics[k] = v;
    }
  }

  RunResult& r_;
  const RunRequest& req_;
  Clock::time_point t0_;
  std::string buf_;
};

}  // namespace

RunResult RunMiniZinc(const RunRequest& req) {
  RunResult r;
  auto t0 = Clock::now();
  TempDir dir;
  if (dir.path.empty()) {
    r.error = "cannot create a temporary directory for the solver";
    return r;
  }
  const std::string model = dir.path + "/model.mzn", data = dir.path + "/data.json";
  // MiniZinc 2.6.4 cannot parse an empty JSON object as data: pass no data file then.
  const bool has_data = !(req.data.is_null() || (req.data.is_object() && req.data.empty()));
  if (!WriteFile(model, req.model) || (has_data && !WriteFile(data, req.data.dump()))) {
    r.error = "cannot write the solver's input files";
    return r;
  }
  // Make orphans of our children (fzn-gecode after minizinc dies) come back to us for reaping.
  prctl(PR_SET_CHILD_SUBREAPER, 1);

  std::vector<std::string> args = {req.minizinc, "--solver", req.solver, "--json-stream",
                                   "--output-mode", "json", "--output-objective", "-i", "-s",
                                   "--time-limit", std::to_string(std::max(1L, req.time_limit_ms))};
  if (req.threads > 1) {
    args.push_back("-p");
    args.push_back(std::to_string(req.threads));
  }
  args.push_back(model);
  if (has_data) args.push_back(data);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // Environment: ours with TMPDIR replaced.
  std::vector<std::string> env_store;
  for (char** e = environ; *e; ++e)
    if (std::strncmp(*e, "TMPDIR=", 7) != 0) env_store.emplace_back(*e);
  env_store.push_back("TMPDIR=" + dir.path);
  std::vector<char*> envp;
  for (auto& e : env_store) envp.push_back(e.data());
  envp.push_back(nullptr);

  int out_pipe[2], err_pipe[2];
  if (pipe2(out_pipe, O_CLOEXEC) != 0) {
    r.error = "cannot create pipes for the solver";
    return r;
  }
  if (pipe2(err_pipe, O_CLOEXEC) != 0) {
    close(out_pipe[0]);
    close(out_pipe[1]);
    r.error = "cannot create pipes for the solver";
    return r;
  }
  const rlim_t memory_limit = req.memory_limit_mb > 0
                                 ? static_cast<rlim_t>(req.memory_limit_mb) * 1024 * 1024
                                 : RLIM_INFINITY;
  pid_t pid = fork();
  if (pid < 0) {
    for (int fd : {out_pipe[0], out_pipe[1], err_pipe[0], err_pipe[1]}) close(fd);
    r.error = "cannot start the solver process";
    return r;
  }
  if (pid == 0) {  // child: async-signal-safe calls only
    setpgid(0, 0);
    if (memory_limit != RLIM_INFINITY) {
      rlimit rl{memory_limit, memory_limit};
      setrlimit(RLIMIT_AS, &rl);
    }
    int devnull = open("/dev/null", O_RDONLY);
    if (devnull >= 0) dup2(devnull, 0);
    dup2(out_pipe[1], 1);
    dup2(err_pipe[1], 2);
    if (chdir(dir.path.c_str()) != 0) _exit(126);
    // execvpe searches PATH for a bare name.
    execvpe(argv[0], argv.data(), envp.data());
    _exit(127);
  }
  close(out_pipe[1]);
  close(err_pipe[1]);
  SetNonBlocking(out_pipe[0]);
  SetNonBlocking(err_pipe[0]);

  LineHandler lines(r, req, t0);
  const long term_at = req.time_limit_ms + kGraceMs;
  bool out_open = true, err_open = true, termed = false, exited = false, exited_unsignalled = false;
  long term_time = 0;
  int wstatus = 0;
  char buf[65536];
  while (out_open || err_open || !exited) {
    long now = MsSince(t0);
    bool cancelled = req.cancel && req.cancel->load();
    if (!termed && (now >= term_at || cancelled)) {
      kill(pid, SIGTERM);
      termed = true;
      term_time = now;
      r.killed = true;
    } else if (termed && now >= term_time + kTermMs) {
      kill(pid, SIGKILL);
      kill(-pid, SIGKILL);
      KillProcessesIn(dir.path);
    }
    if (!exited) {
      pid_t w = waitpid(pid, &wstatus, WNOHANG);
      if (w == pid || (w < 0 && errno == ECHILD)) {
        exited = true;
        exited_unsignalled = w == pid && !termed;
      }
    }
    if (exited && !out_open && !err_open) break;
    if (exited && termed && now >= term_time + 2 * kTermMs) break;  // pipes held by orphans
    std::vector<pollfd> fds;
    if (out_open) fds.push_back({out_pipe[0], POLLIN, 0});
    if (err_open) fds.push_back({err_pipe[0], POLLIN, 0});
    if (fds.empty()) {
      usleep(20000);
      continue;
    }
    poll(fds.data(), fds.size(), 50);
    for (const auto& p : fds) {
      if (!(p.revents & (POLLIN | POLLHUP | POLLERR))) continue;
      ssize_t n = read(p.fd, buf, sizeof buf);
      bool is_out = p.fd == out_pipe[0];
      if (n > 0) {
        if (is_out) lines.Feed(buf, static_cast<std::size_t>(n));
        else if (r.solver_stderr.size() < kMaxStderr)
          r.solver_stderr.append(buf, std::min<std::size_t>(n, kMaxStderr - r.solver_stderr.size()));
      } else if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) {
        (is_out ? out_open : err_open) = false;
      }
    }
  }
  close(out_pipe[0]);
  close(err_pipe[0]);
  // Anything left in the job directory (an orphaned fzn-gecode) is killed, and reaped if it
  // came back to us as subreaper. Only those pids: other jobs' children are not ours to reap.
  std::vector<pid_t> leftovers = KillProcessesIn(dir.path);
  // A killed solver is reparented to us (subreaper) only once minizinc is gone: keep reaping
  // until its /proc entry disappears (bounded), so no zombie outlives the job.
  for (int i = 0; i < 200 && !leftovers.empty(); ++i) {
    for (auto it = leftovers.begin(); it != leftovers.end();) {
      waitpid(*it, nullptr, WNOHANG);
      std::error_code ec;
      bool gone = !fs::exists("/proc/" + std::to_string(*it), ec);
      it = gone ? leftovers.erase(it) : it + 1;
    }
    if (!leftovers.empty()) usleep(10000);
  }
  // A solver that died after its minizinc (SIGTERM forwarded) turns into a zombie reparented to
  // us; its cwd is no longer readable, so reap it by parentage.
  for (int i = 0; i < 50; ++i) {
    auto orphans = OrphanedSolvers();
    if (orphans.empty()) break;
    for (pid_t p : orphans) {
      if (waitpid(p, nullptr, WNOHANG) == 0 && i > 20) kill(p, SIGKILL);
    }
    usleep(10000);
  }
  lines.Finish();
  r.elapsed_ms = MsSince(t0);

  const bool cancelled = req.cancel && req.cancel->load();
  const std::string st = lines.status.value_or("");
  const bool oom = r.solver_stderr.find("bad_alloc") != std::string::npos ||
                   r.solver_stderr.find("out of memory") != std::string::npos ||
                   r.solver_stderr.find("Cannot allocate memory") != std::string::npos;
  if (exited_unsignalled && WIFSIGNALED(wstatus)) {
    // Killed by someone else (an operator, the OOM killer) or crashed: an error, never "unknown".
    r.signal = WTERMSIG(wstatus);
    r.status = RunResult::Status::kError;
    const char* name = sigabbrev_np(r.signal);
    r.error = "the solver process was killed by signal " + std::to_string(r.signal) + " (SIG" +
              (name ? name : "?") + ")";
    r.out_of_memory = oom;
    if (oom) r.error += " after running out of memory";
    spdlog::error("{}", Json({{"event", "solver_crashed"}, {"signal", r.signal},
                              {"elapsed_ms", r.elapsed_ms}, {"stderr", r.solver_stderr}})
                            .dump(-1, ' ', false, Json::error_handler_t::replace));
    return r;
  }
  if (oom && r.solutions == 0 && !cancelled) {
    r.status = RunResult::Status::kError;
    r.out_of_memory = true;
    r.error = "the solver ran out of memory (limit " + std::to_string(req.memory_limit_mb) + " MiB)";
    spdlog::error("{}", Json({{"event", "solver_out_of_memory"}, {"limit_mb", req.memory_limit_mb},
                              {"elapsed_ms", r.elapsed_ms}})
                            .dump());
    return r;
  }
  if (st == "OPTIMAL_SOLUTION" || st == "ALL_SOLUTIONS") {
    r.status = RunResult::Status::kOptimal;
  } else if (st == "UNSATISFIABLE") {
    r.status = RunResult::Status::kInfeasible;
  } else if (lines.timed_out && !lines.error_message) {
    r.status = r.solutions > 0 ? (cancelled ? RunResult::Status::kCancelled : RunResult::Status::kFeasible)
                               : (cancelled ? RunResult::Status::kCancelled : RunResult::Status::kUnknown);
  } else if (st == "ERROR" || lines.error_message) {
    r.status = RunResult::Status::kError;
    if (r.error.empty()) r.error = "the solver reported an error";
  } else if (r.solutions > 0) {
    r.status = cancelled ? RunResult::Status::kCancelled : RunResult::Status::kFeasible;
  } else if (cancelled) {
    r.status = RunResult::Status::kCancelled;
  } else if (st == "UNKNOWN" || r.killed) {
    r.status = RunResult::Status::kUnknown;
  } else if (WIFEXITED(wstatus) && WEXITSTATUS(wstatus) == 127) {
    r.status = RunResult::Status::kError;
    r.error = "cannot run '" + req.minizinc + "': is MiniZinc installed?";
  } else if (exited && WIFEXITED(wstatus) && WEXITSTATUS(wstatus) != 0) {
    r.status = RunResult::Status::kError;
    r.error = "the solver exited with status " + std::to_string(WEXITSTATUS(wstatus));
  } else {
    r.status = RunResult::Status::kUnknown;
  }
  return r;
}

bool MiniZincAvailable(const std::string& minizinc) {
  RunRequest req;
  req.minizinc = minizinc;
  req.model = "var 0..1: x; solve satisfy;";
  req.data = Json::object();
  req.time_limit_ms = 5000;
  RunResult r = RunMiniZinc(req);
  return r.status == RunResult::Status::kOptimal || r.status == RunResult::Status::kFeasible;
}

}  // namespace ctb
