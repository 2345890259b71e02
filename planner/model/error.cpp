#include "planner/model/error.h"

namespace ctb {

int HttpStatus(ErrorCode code) {
  switch (code) {
    case ErrorCode::kInvalidInput: return 400;
    case ErrorCode::kNotFound: return 404;
    case ErrorCode::kTooLarge: return 413;
    case ErrorCode::kUnprocessable: return 422;
    case ErrorCode::kBusy: return 503;
    case ErrorCode::kUnavailable: return 503;
    case ErrorCode::kUpstreamFailed: return 502;
    case ErrorCode::kUpstreamTimeout: return 504;
    case ErrorCode::kInternal: return 500;
    case ErrorCode::kConflict: return 409;
    case ErrorCode::kUnauthenticated: return 401;
  }
  return 500;
}

const char* CodeName(ErrorCode code) {
  switch (code) {
    case ErrorCode::kInvalidInput: return "invalid_input";
    case ErrorCode::kNotFound: return "not_found";
    case ErrorCode::kTooLarge: return "too_large";
    case ErrorCode::kUnprocessable: return "unprocessable";
    case ErrorCode::kBusy: return "busy";
    case ErrorCode::kUnavailable: return "unavailable";
    case ErrorCode::kUpstreamFailed: return "upstream_failed";
    case ErrorCode::kUpstreamTimeout: return "upstream_timeout";
    case ErrorCode::kInternal: return "internal";
    case ErrorCode::kConflict: return "conflict";
    case ErrorCode::kUnauthenticated: return "unauthenticated";
  }
  return "internal";
}

std::string Diagnostic::ToString() const {
  std::string out = pointer.empty() ? "/" : pointer;
  out += ": ";
  if (offset) out += "offset " + std::to_string(*offset) + ": ";
  out += message;
  return out;
}

void Diagnostics::Error(std::string pointer, std::string message,
                        std::optional<std::size_t> offset) {
  errors_.push_back({std::move(pointer), offset, std::move(message)});
}

void Diagnostics::Warning(std::string pointer, std::string message,
                          std::optional<std::size_t> offset) {
  warnings_.push_back({std::move(pointer), offset, std::move(message)});
}

void Diagnostics::Append(const Diagnostics& other) {
  errors_.insert(errors_.end(), other.errors_.begin(), other.errors_.end());
  warnings_.insert(warnings_.end(), other.warnings_.begin(), other.warnings_.end());
}

Error Error::FromDiagnostics(ErrorCode code, std::string message, const Diagnostics& d) {
  return Error{code, std::move(message), d.errors()};
}

std::string Error::ToString() const {
  std::string out = message;
  for (const auto& d : details) out += "\n" + d.ToString();
  return out;
}

std::string PointerToken(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

std::string Echo(const std::string& s, std::size_t max) {
  if (s.size() <= max) return s;
  std::size_t cut = max;
  // Do not split a UTF-8 sequence: back up over continuation bytes.
  while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;
  return s.substr(0, cut) + "...";
}

}  // namespace ctb
