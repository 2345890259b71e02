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

namespace ctb::testing {

inline const bool kSubreaper = [] {
  prctl(PR_SET_CHILD_SUBREAPER, 1);
  return true;
}();

inline int SolverProcesses() {
  std::map<long, long> parent;
  std::map<long, std::string> comm;
  for (const auto& e : std::filesystem::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(e.path() / "stat");
    std::string stat;
    std::getline(in, stat);
    auto open = stat.find('('), close = stat.rfind(')');
    if (open == std::string::npos || close == std::string::npos) continue;
    std::istringstream rest(stat.substr(close + 2));
    char state;
    long ppid = 0;
    rest >> state >> ppid;
    long pid = std::stol(name);
    parent[pid] = ppid;
    comm[pid] = stat.substr(open + 1, close - open - 1);
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
