// Counting the solver processes a test started (minizinc, fzn-gecode), and no one else's: only
// descendants of this test process. The test binary makes itself a subreaper, so solvers
// orphaned by a server under test are reparented to it and still count.
#pragma once

#include <sys/prctl.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace ctb::testing {

inline const bool kSubreaper = [] {
  prctl(PR_SET_CHILD_SUBREAPER, 1);
  return true;
}();

struct Process {
  long pid = 0, ppid = 0;
  std::string comm;
};

// Every process /proc lists now (one that exits meanwhile is skipped).
inline std::vector<Process> Processes() {
  std::vector<Process> out;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("/proc", ec)) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(e.path() / "stat");
    std::string stat;
    std::getline(in, stat);
    auto open = stat.find('('), close = stat.rfind(')');
    if (open == std::string::npos || close == std::string::npos || close + 2 > stat.size()) continue;
    std::istringstream rest(stat.substr(close + 2));
    char state;
    Process p;
    rest >> state >> p.ppid;
    p.pid = std::stol(name);
    p.comm = stat.substr(open + 1, close - open - 1);
    out.push_back(std::move(p));
  }
  return out;
}

inline int SolverProcesses() {
  std::map<long, long> parent;
  std::map<long, std::string> comm;
  for (const Process& p : Processes()) {
    parent[p.pid] = p.ppid;
    comm[p.pid] = p.comm;
  }
  const long self = getpid();
  int n = 0;
  for (const auto& [pid, c] : comm) {
    if (c != "minizinc" && c != "fzn-gecode") continue;
    for (long p = parent[pid]; p > 1; p = parent.count(p) ? parent[p] : 0)
      if (p == self) {
        ++n;
        break;
      }
  }
  return n;
}

}  // namespace ctb::testing
