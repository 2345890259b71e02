// Identifiers the service hands out (session and request ids) and how it echoes ids it was given.
#pragma once

#include <cstddef>
#include <string>

#include "planner/model/error.h"

namespace ctb::app {

// `bytes` random bytes from the kernel's CSPRNG (getrandom(2)), as lower-case hex. 16 bytes (128
// bits) for session ids. Blocks only before the kernel's pool is initialised; never throws (on a
// failing getrandom it reads /dev/urandom, and aborts the process if that fails too: an id that
// is not random is worse than no service).
std::string RandomHex(std::size_t bytes = 16);

// A client-supplied string cut for echoing in messages (planner/model/error.h).
using ::ctb::Echo;

// Text as one JSON string, for a log line (the log's format holds a JSON value: server/log_context.cpp).
std::string LogText(const std::string& s);

}  // namespace ctb::app
