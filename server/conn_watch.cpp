#include "server/conn_watch.h"

#include <fstream>
#include <sstream>
#include <string>

namespace ctb::server {

namespace {

// "0100007F:1F90" -> 0x1F90; -1 for anything else. Never throws: it runs in a watcher thread,
// where an exception would terminate the server.
int PortOf(const std::string& addr) {
  auto colon = addr.rfind(':');
  if (colon == std::string::npos || colon + 1 >= addr.size() || addr.size() - colon - 1 > 4) return -1;
  int port = 0;
  for (std::size_t i = colon + 1; i < addr.size(); ++i) {
    const char c = addr[i];
    int v = c >= '0' && c <= '9' ? c - '0' : c >= 'A' && c <= 'F' ? c - 'A' + 10 : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
    if (v < 0) return -1;
    port = port * 16 + v;
  }
  return port;
}

// 1: established, 0: listed in another state, -1: not listed.
int StateIn(const char* table, int local_port, int remote_port) {
  std::ifstream in(table);
  std::string line;
  std::getline(in, line);  // header
  int found = -1;
  while (std::getline(in, line)) {
    std::istringstream f(line);
    std::string sl, local, remote, state;
    if (!(f >> sl >> local >> remote >> state)) continue;
    if (PortOf(local) != local_port || PortOf(remote) != remote_port) continue;
    if (state == "01") return 1;
    found = 0;
  }
  return found;
}

}  // namespace

bool ClientConnected(int local_port, int remote_port) {
  if (local_port <= 0 || remote_port <= 0) return true;  // unknown: never cancel on a guess
  int v4 = StateIn("/proc/net/tcp", local_port, remote_port);
  if (v4 == 1) return true;
  int v6 = StateIn("/proc/net/tcp6", local_port, remote_port);
  if (v6 == 1) return true;
  return false;
}

}  // namespace ctb::server
