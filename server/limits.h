// What the service refuses before a request reaches a route: malformed or oversized request heads,
// too many connections, clients too slow to send their request, and bodies that are not UTF-8.
//
// cpp-httplib 0.11 gives a connection a pool thread for as long as the client keeps it open and
// bounds each recv() only, so idle or slowloris sockets starve the pool, and /healthz with it.
// GuardedServer replaces its per-connection loop (the virtual process_and_close_socket) and
// keeps httplib's request parsing and routing (process_request):
//  - admission: at most `per_address` connections from one client address and `total` at once;
//    beyond, an immediate 503 (`too_many_connections`, Retry-After) and close;
//  - the request head must arrive completely within `head_timeout_ms` of its first byte (or of
//    the connection/keep-alive wait), and the body within `body_timeout_ms` of the head: a client
//    dripping bytes is closed (408), whatever its per-recv pace;
//  - the head is checked before httplib sees it: request line over 8 KiB -> 414, head over
//    16 KiB -> 431, Content-Length not a plain non-negative integer (or repeated with another
//    value) -> 400, beyond the body limit -> 413, Transfer-Encoding -> 411; all at once, JSON
//    errors as every other route.
// The pool must have more threads than `total` connections so a refusal never waits for a thread.
#pragma once

#include <httplib.h>
#include <sys/socket.h>

#include <atomic>
#include <cstddef>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

namespace ctb::server {

// The byte offset of the first byte that is not part of a well-formed UTF-8 sequence (overlong
// forms, surrogates and code points above U+10FFFF are ill-formed), or nullopt when all is valid.
std::optional<std::size_t> InvalidUtf8Offset(std::string_view s);

struct HeadRejection {
  int status = 400;
  std::string code;     // the JSON error code ("invalid_input", "uri_too_long", ...)
  std::string message;
};

inline constexpr std::size_t kMaxRequestLine = 8192;
inline constexpr std::size_t kMaxRequestHead = 16384;

// Checks a complete request head (request line and headers, up to the blank line). Never throws.
std::optional<HeadRejection> CheckRequestHead(std::string_view head, long max_body_bytes);

struct ConnectionLimits {
  int per_address = 32;
  int total = 192;
  long head_timeout_ms = 5000;
  long body_timeout_ms = 10000;
  long keep_alive_ms = 5000;
  long max_body_bytes = 1 << 20;
};

class GuardedServer : public httplib::Server {
 public:
  void SetLimits(const ConnectionLimits& l) { limits_ = l; }
  // cpp-httplib 0.11 listens with a backlog of 5: a burst of connections then waits for SYN
  // retransmits (1 s, 3 s, ...) before the accept loop even sees it. Call after bind_to_port():
  // listen() again on the bound socket raises the backlog (Linux).
  bool RaiseBacklog(int backlog = 1024) { return ::listen(svr_sock_, backlog) == 0; }
  long open_connections() const { return open_.load(); }
  long refused_connections() const { return refused_.load(); }
  long timed_out_requests() const { return timed_out_.load(); }

 private:
  bool process_and_close_socket(socket_t sock) override;
  bool Admit(const std::string& address);
  void Release(const std::string& address);

  ConnectionLimits limits_;
  std::mutex mu_;
  std::map<std::string, int> per_address_;
  int total_ = 0;
  std::atomic<long> open_{0}, refused_{0}, timed_out_{0};
};

}  // namespace ctb::server
