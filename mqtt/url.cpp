#include "mqtt/url.h"

#include <cctype>

namespace ctb::mqtt {

std::variant<BrokerAddress, std::string> ParseMqttUrl(const std::string& url) {
  // The URL as it may be shown: a password in it is never echoed.
  std::string shown = url;
  if (auto at = shown.find('@'); at != std::string::npos) {
    auto start = shown.find("://");
    start = start == std::string::npos ? 0 : start + 3;
    if (start <= at) shown.replace(start, at - start, "***");
  }
  auto bad = [&](const std::string& why) {
    return "invalid MQTT URL '" + shown + "': " + why + " (expected mqtt://host[:port], e.g. mqtt://127.0.0.1:1883)";
  };
  const std::string scheme = "mqtt://";
  if (url.rfind(scheme, 0) != 0) {
    if (url.rfind("mqtts://", 0) == 0) return bad("TLS (mqtts) is not supported");
    return bad("the scheme must be mqtt://");
  }
  std::string rest = url.substr(scheme.size());
  if (!rest.empty() && rest.back() == '/') rest.pop_back();
  if (rest.find('@') != std::string::npos) return bad("credentials are not supported");
  if (rest.find_first_of("/?#") != std::string::npos) return bad("a path, query or fragment is not allowed");
  BrokerAddress a;
  std::string port;
  if (!rest.empty() && rest.front() == '[') {  // [IPv6]:port
    auto close = rest.find(']');
    if (close == std::string::npos) return bad("unclosed '[' in the host");
    a.host = rest.substr(1, close - 1);
    std::string after = rest.substr(close + 1);
    if (!after.empty()) {
      if (after.front() != ':') return bad("unexpected text after the host");
      port = after.substr(1);
      if (port.empty()) return bad("empty port");
    }
  } else {
    auto colon = rest.rfind(':');
    if (colon != std::string::npos) {
      if (rest.find(':') != colon) return bad("an IPv6 host must be written in brackets");
      port = rest.substr(colon + 1);
      if (port.empty()) return bad("empty port");
      a.host = rest.substr(0, colon);
    } else {
      a.host = rest;
    }
  }
  if (a.host.empty()) return bad("no host");
  for (char c : a.host)
    if (std::isspace(static_cast<unsigned char>(c)) || std::iscntrl(static_cast<unsigned char>(c)))
      return bad("the host contains a space or a control character");
  if (!port.empty()) {
    if (port.size() > 5) return bad("the port must be 1..65535");
    long p = 0;
    for (char c : port) {
      if (!std::isdigit(static_cast<unsigned char>(c))) return bad("the port must be a number");
      p = p * 10 + (c - '0');
    }
    if (p < 1 || p > 65535) return bad("the port must be 1..65535");
    a.port = static_cast<int>(p);
  }
  return a;
}

}  // namespace ctb::mqtt
