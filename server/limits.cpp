#include "server/limits.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <nlohmann/json.hpp>

#include "app/ids.h"

namespace ctb::server {

std::optional<std::size_t> InvalidUtf8Offset(std::string_view s) {
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  const std::size_t n = s.size();
  std::size_t i = 0;
  while (i < n) {
    unsigned char c = p[i];
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t len;
    unsigned char lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
    if (c >= 0xC2 && c <= 0xDF) {
      len = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      len = 3;
      if (c == 0xE0) lo = 0xA0;          // overlong
      if (c == 0xED) hi = 0x9F;          // surrogates
    } else if (c >= 0xF0 && c <= 0xF4) {
      len = 4;
      if (c == 0xF0) lo = 0x90;          // overlong
      if (c == 0xF4) hi = 0x8F;          // above U+10FFFF
    } else {
      return i;
    }
    if (i + len > n) return i;
    if (p[i + 1] < lo || p[i + 1] > hi) return i;
    for (std::size_t k = 2; k < len; ++k)
      if ((p[i + k] & 0xC0) != 0x80) return i;
    i += len;
  }
  return std::nullopt;
}

namespace {

std::string Lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

}  // namespace

std::optional<HeadRejection> CheckRequestHead(std::string_view head, long max_body_bytes) {
  auto eol = head.find('\n');
  std::string_view line = head.substr(0, eol);
  if (line.size() > kMaxRequestLine)
    return HeadRejection{414, "uri_too_long",
                         "request line longer than " + std::to_string(kMaxRequestLine) + " bytes"};
  if (head.size() > kMaxRequestHead)
    return HeadRejection{431, "headers_too_large",
                         "request head longer than " + std::to_string(kMaxRequestHead) + " bytes"};
  std::optional<unsigned long long> length;
  std::size_t pos = eol == std::string_view::npos ? head.size() : eol + 1;
  while (pos < head.size()) {
    auto next = head.find('\n', pos);
    std::string_view h = head.substr(pos, next == std::string_view::npos ? head.size() - pos : next - pos);
    pos = next == std::string_view::npos ? head.size() : next + 1;
    auto colon = h.find(':');
    if (colon == std::string_view::npos) continue;  // httplib decides about malformed lines
    const std::string name = Lower(Trim(h.substr(0, colon)));
    const std::string_view value = Trim(h.substr(colon + 1));
    if (name == "transfer-encoding")
      return HeadRejection{411, "length_required",
                           "chunked request bodies are not accepted; send Content-Length"};
    if (name != "content-length") continue;
    if (value.empty() || value.size() > 18 ||
        !std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return HeadRejection{400, "invalid_input",
                           "Content-Length must be a non-negative integer of at most 18 digits"};
    unsigned long long v = std::stoull(std::string(value));  // digits only, < 10^18: no throw
    if (length && *length != v)
      return HeadRejection{400, "invalid_input", "conflicting Content-Length headers"};
    length = v;
  }
  if (length && *length > static_cast<unsigned long long>(max_body_bytes))
    return HeadRejection{413, "too_large",
                         "request body larger than " + std::to_string(max_body_bytes) + " bytes"};
  return std::nullopt;
}

namespace {

using Clock = std::chrono::steady_clock;

long MsUntil(Clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(t - Clock::now()).count();
}

// poll() for one event, bounded by `ms`; true when the socket is ready (or has an error pending,
// which the next recv/send reports).
bool WaitFor(int sock, short events, long ms) {
  if (ms <= 0) return false;
  pollfd p{sock, events, 0};
  int r;
  do {
    r = poll(&p, 1, static_cast<int>(std::min<long>(ms, 1 << 30)));
  } while (r < 0 && errno == EINTR);
  return r > 0;
}

std::pair<std::string, int> Address(int sock, bool peer) {
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  int rc = peer ? getpeername(sock, reinterpret_cast<sockaddr*>(&a), &len)
                : getsockname(sock, reinterpret_cast<sockaddr*>(&a), &len);
  if (rc != 0) return {"", 0};
  char host[NI_MAXHOST] = {0}, serv[NI_MAXSERV] = {0};
  if (getnameinfo(reinterpret_cast<sockaddr*>(&a), len, host, sizeof host, serv, sizeof serv,
                  NI_NUMERICHOST | NI_NUMERICSERV) != 0)
    return {"", 0};
  return {host, std::atoi(serv)};
}

// The connection's receive buffer, shared by the head reader and the stream given to httplib so
// bytes read ahead (the start of a body, a pipelined request) are never lost.
struct Conn {
  int sock;
  std::string buf;
  std::size_t off = 0;

  std::size_t buffered() const { return buf.size() - off; }
  void Compact() {
    if (off > 0 && off == buf.size()) {
      buf.clear();
      off = 0;
    } else if (off > 65536) {
      buf.erase(0, off);
      off = 0;
    }
  }
  // One recv() of up to 16 KiB into the buffer once the socket is readable before `deadline`.
  // > 0: bytes read; 0: peer closed; -1: error or deadline.
  ssize_t Fill(Clock::time_point deadline, long per_read_ms) {
    if (!WaitFor(sock, POLLIN, std::min(MsUntil(deadline), per_read_ms))) return -1;
    char tmp[16384];
    ssize_t n;
    do {
      n = recv(sock, tmp, sizeof tmp, 0);
    } while (n < 0 && errno == EINTR);
    if (n > 0) buf.append(tmp, static_cast<std::size_t>(n));
    return n;
  }
};

enum class HeadResult { kOk, kClosed, kTimeout, kTooLarge };

// Reads until the blank line ending a request head; the head is buf[off, off + *head_len).
HeadResult ReadHead(Conn& c, Clock::time_point deadline, std::size_t* head_len) {
  std::size_t scanned = 0;
  for (;;) {
    std::string_view v(c.buf.data() + c.off, c.buffered());
    // Leading empty lines before a request line are allowed (RFC 9112 2.2).
    while (!v.empty() && (v.front() == '\r' || v.front() == '\n')) {
      ++c.off;
      v.remove_prefix(1);
      scanned = 0;
    }
    std::size_t from = scanned > 3 ? scanned - 3 : 0;
    auto crlf = v.find("\r\n\r\n", from), lf = v.find("\n\n", from);
    auto end = std::min(crlf == std::string_view::npos ? v.npos : crlf + 4,
                        lf == std::string_view::npos ? v.npos : lf + 2);
    if (end != std::string_view::npos) {
      *head_len = end;
      return HeadResult::kOk;
    }
    scanned = v.size();
    auto first_eol = v.find('\n');
    if ((first_eol == v.npos && v.size() > kMaxRequestLine) || v.size() > kMaxRequestHead) {
      *head_len = v.size();
      return HeadResult::kTooLarge;
    }
    ssize_t n = c.Fill(deadline, MsUntil(deadline));
    if (n == 0) return HeadResult::kClosed;
    if (n < 0) return MsUntil(deadline) <= 0 ? HeadResult::kTimeout : HeadResult::kClosed;
  }
}

// The stream httplib's process_request reads the request from and writes the answer to. Reads
// fail once `read_deadline` has passed, whatever the client's pace.
class DeadlineStream : public httplib::Stream {
 public:
  DeadlineStream(Conn& c, Clock::time_point read_deadline, long write_timeout_ms)
      : c_(c), read_deadline_(read_deadline), write_timeout_ms_(write_timeout_ms) {}

  bool is_readable() const override {
    return c_.buffered() > 0 || WaitFor(c_.sock, POLLIN, MsUntil(read_deadline_));
  }
  bool is_writable() const override {
    pollfd p{c_.sock, POLLOUT, 0};
    int r;
    do {
      r = poll(&p, 1, static_cast<int>(write_timeout_ms_));
    } while (r < 0 && errno == EINTR);
    return r > 0 && !(p.revents & (POLLERR | POLLHUP | POLLNVAL));
  }
  ssize_t read(char* ptr, size_t size) override {
    if (c_.buffered() == 0) {
      c_.Compact();
      ssize_t n = c_.Fill(read_deadline_, MsUntil(read_deadline_));
      if (n <= 0) {
        if (n < 0 && MsUntil(read_deadline_) <= 0) timed_out = true;
        return n;
      }
    }
    std::size_t k = std::min(size, c_.buffered());
    std::copy_n(c_.buf.data() + c_.off, k, ptr);
    c_.off += k;
    return static_cast<ssize_t>(k);
  }
  ssize_t write(const char* ptr, size_t size) override {
    if (!is_writable()) return -1;
    ssize_t n;
    do {
      n = send(c_.sock, ptr, size, MSG_NOSIGNAL);
    } while (n < 0 && errno == EINTR);
    return n;
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    std::tie(ip, port) = Address(c_.sock, true);
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    std::tie(ip, port) = Address(c_.sock, false);
  }
  socket_t socket() const override { return c_.sock; }

  bool timed_out = false;

 private:
  Conn& c_;
  Clock::time_point read_deadline_;
  long write_timeout_ms_;
};

const char* Reason(int status) {
  switch (status) {
    case 400: return "Bad Request";
    case 408: return "Request Timeout";
    case 411: return "Length Required";
    case 413: return "Payload Too Large";
    case 414: return "URI Too Long";
    case 431: return "Request Header Fields Too Large";
    case 503: return "Service Unavailable";
  }
  return "Error";
}

// Answers with a JSON error and closes: the write half is shut first and unread input drained
// briefly, so the client reads the answer instead of a reset.
void RefuseAndClose(int sock, int status, const std::string& code, const std::string& message) {
  const std::string body =
      nlohmann::json({{"error", {{"code", code}, {"message", message}}}}).dump();
  std::string out = "HTTP/1.1 " + std::to_string(status) + " " + Reason(status) +
                    "\r\nContent-Type: application/json\r\nContent-Length: " +
                    std::to_string(body.size()) + "\r\nConnection: close\r\nX-Request-Id: " +
                    app::RandomHex(8) + "\r\n" + (status == 503 ? "Retry-After: 1\r\n" : "") + "\r\n" + body;
  std::size_t sent = 0;
  while (sent < out.size() && WaitFor(sock, POLLOUT, 1000)) {
    ssize_t n = send(sock, out.data() + sent, out.size() - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n <= 0 && errno != EINTR && errno != EAGAIN) break;
    if (n > 0) sent += static_cast<std::size_t>(n);
  }
  shutdown(sock, SHUT_WR);
  auto until = Clock::now() + std::chrono::milliseconds(100);
  char tmp[4096];
  std::size_t drained = 0;
  while (drained < (1 << 20) && WaitFor(sock, POLLIN, MsUntil(until))) {
    ssize_t n = recv(sock, tmp, sizeof tmp, MSG_DONTWAIT);
    if (n <= 0) break;
    drained += static_cast<std::size_t>(n);
  }
}

}  // namespace

bool GuardedServer::Admit(const std::string& address) {
  std::lock_guard<std::mutex> lock(mu_);
  int& mine = per_address_[address];
  if (total_ >= limits_.total || mine >= limits_.per_address) {
    if (mine == 0) per_address_.erase(address);
    return false;
  }
  ++mine;
  ++total_;
  open_ = total_;
  return true;
}

void GuardedServer::Release(const std::string& address) {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = per_address_.find(address);
  if (it != per_address_.end() && --it->second <= 0) per_address_.erase(it);
  open_ = --total_;
}

bool GuardedServer::process_and_close_socket(socket_t sock) {
  const std::string address = Address(sock, true).first;
  bool ret = false;
  if (!Admit(address)) {
    ++refused_;
    RefuseAndClose(sock, 503, "too_many_connections",
                   "too many connections from this address or in total; retry later");
  } else {
    Conn c{sock};
    std::size_t left = keep_alive_max_count_;
    bool first = true;
    while (svr_sock_ != INVALID_SOCKET && left > 0) {
      // Waiting for a request: the head timeout for the first, the keep-alive time after.
      const long wait_ms = first ? limits_.head_timeout_ms : limits_.keep_alive_ms;
      if (c.buffered() == 0 && !WaitFor(sock, POLLIN, wait_ms)) {
        if (first) ++timed_out_;
        break;
      }
      first = false;
      const auto head_deadline = Clock::now() + std::chrono::milliseconds(limits_.head_timeout_ms);
      std::size_t head_len = 0;
      HeadResult h = ReadHead(c, head_deadline, &head_len);
      if (h == HeadResult::kClosed) break;
      if (h == HeadResult::kTimeout) {
        ++timed_out_;
        RefuseAndClose(sock, 408, "timeout", "the request head did not arrive in time");
        break;
      }
      std::string_view head(c.buf.data() + c.off, head_len);
      std::optional<HeadRejection> rejection;
      if (h == HeadResult::kTooLarge) {
        auto eol = head.find('\n');
        rejection = eol == head.npos || eol > kMaxRequestLine
                        ? HeadRejection{414, "uri_too_long", "request line longer than " +
                                                                 std::to_string(kMaxRequestLine) + " bytes"}
                        : HeadRejection{431, "headers_too_large", "request head longer than " +
                                                                      std::to_string(kMaxRequestHead) + " bytes"};
      } else {
        rejection = CheckRequestHead(head, limits_.max_body_bytes);
      }
      if (rejection) {
        RefuseAndClose(sock, rejection->status, rejection->code, rejection->message);
        break;
      }
      DeadlineStream strm(c, Clock::now() + std::chrono::milliseconds(limits_.body_timeout_ms),
                          write_timeout_sec_ * 1000 + write_timeout_usec_ / 1000);
      bool closed = false;
      ret = process_request(strm, left == 1, closed, nullptr);
      if (strm.timed_out) ++timed_out_;
      if (!ret || closed) break;
      --left;
      c.Compact();
    }
    Release(address);
  }
  shutdown(sock, SHUT_RDWR);
  close(sock);
  return ret;
}

}  // namespace ctb::server
