#include "app/ids.h"

#include <fcntl.h>
#include <sys/random.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <vector>

#include "planner/model/json_io.h"

namespace ctb::app {

namespace {

void FillRandom(unsigned char* p, std::size_t n) {
  std::size_t got = 0;
  while (got < n) {
    ssize_t r = getrandom(p + got, n - got, 0);
    if (r > 0) {
      got += static_cast<std::size_t>(r);
    } else if (r < 0 && errno == EINTR) {
      continue;
    } else {
      break;
    }
  }
  if (got == n) return;
  int fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC);
  while (fd >= 0 && got < n) {
    ssize_t r = read(fd, p + got, n - got);
    if (r <= 0 && errno != EINTR) break;
    if (r > 0) got += static_cast<std::size_t>(r);
  }
  if (fd >= 0) close(fd);
  if (got != n) std::abort();
}

}  // namespace

std::string RandomHex(std::size_t bytes) {
  std::vector<unsigned char> raw(bytes);
  FillRandom(raw.data(), bytes);
  static const char* kHex = "0123456789abcdef";
  std::string s;
  s.reserve(bytes * 2);
  for (unsigned char b : raw) {
    s += kHex[b >> 4];
    s += kHex[b & 15];
  }
  return s;
}

std::string LogText(const std::string& s) { return Json(s).dump(-1, ' ', false, Json::error_handler_t::replace); }

}  // namespace ctb::app
