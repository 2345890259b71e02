// Core::CheckNetwork (contract section 13): a bare temporal network checked by planner/network.
#include "app/core.h"
#include "planner/network/network_json.h"

namespace ctb::app {
namespace {

// Counts before parsing, so that an oversized body costs no more than reading its arrays' sizes.
std::optional<Error> TooLarge(const Json& body) {
  auto over = [](const char* name, const char* field, std::size_t limit,
                 std::size_t actual) -> Error {
    Error e{ErrorCode::kTooLarge,
            std::string("the network has more ") + field + " than " + std::to_string(limit),
            {{std::string("/") + field, std::nullopt, "at most " + std::to_string(limit)}}};
    e.limit = Limit{name, static_cast<long>(limit), static_cast<long>(actual)};
    return e;
  };
  if (!body.is_object()) return std::nullopt;
  if (auto it = body.find("points");
      it != body.end() && it->is_array() && it->size() > kMaxNetworkPoints) {
    return over("max_network_points", "points", kMaxNetworkPoints, it->size());
  }
  if (auto it = body.find("links");
      it != body.end() && it->is_array() && it->size() > kMaxNetworkLinks) {
    return over("max_network_links", "links", kMaxNetworkLinks, it->size());
  }
  return std::nullopt;
}

}  // namespace

std::variant<Json, Error> CheckNetworkBody(const Json& body) {
  if (std::optional<Error> e = TooLarge(body)) return *e;
  Diagnostics d;
  std::optional<network::Network> net = network::ParseCheckBody(body, d);
  if (!net) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid network", d);
  return network::CheckResultToJson(network::CheckNetwork(*net));
}

std::variant<Json, Error> Core::CheckNetwork(const Json& body) { return CheckNetworkBody(body); }

}  // namespace ctb::app
