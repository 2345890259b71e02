// The broker address of `--mqtt-url` (contract section 14): mqtt://host[:port], port 1883 by
// default. No credentials, TLS or path: the broker is expected on a trusted network (loopback by
// default), as Debian's mosquitto serves it.
#pragma once

#include <string>
#include <variant>

namespace ctb::mqtt {

struct BrokerAddress {
  std::string host;  // a name, an IPv4 address, or an IPv6 address without its brackets
  int port = 1883;
};

// The address, or a message saying what is wrong with `url` (it quotes the URL).
std::variant<BrokerAddress, std::string> ParseMqttUrl(const std::string& url);

}  // namespace ctb::mqtt
