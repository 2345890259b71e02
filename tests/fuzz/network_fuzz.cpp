// Fuzz target: the temporal-network file of contract section 13 (planner/network/network_json.h)
// as POST /networks/check reads it: parsed strictly, the point and link counts capped as the
// core caps them, parsed into a network, then checked (consistency, strong and dynamic
// controllability). Checked: every error carries a JSON pointer; the checks agree with each
// other (strong or dynamic implies consistent, strong implies dynamic); a conflict names links
// of the network.
#include <cstdint>

#include "planner/network/check.h"
#include "planner/network/network_json.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ctb;
  Diagnostics pd;
  std::optional<Json> body = ParseJsonStrict(fuzz::Text(data, size), pd);
  if (!body) return 0;
  Diagnostics diags;
  std::optional<network::Network> net = network::ParseCheckBody(*body, diags);
  fuzz::CheckDiagnostics(diags);
  if (!net) {
    if (diags.ok()) fuzz::Fail("ParseCheckBody failed without an error");
    return 0;
  }
  if (!diags.ok()) fuzz::Fail("ParseCheckBody returned a network with errors");
  const network::CheckResult r = network::CheckNetwork(*net);
  if ((r.strong || r.dynamic) && !r.consistent) fuzz::Fail("controllable but not consistent");
  if (r.strong && !r.dynamic) fuzz::Fail("strongly but not dynamically controllable");
  const Json out = network::CheckResultToJson(r);
  if (out.contains("conflict")) {
    const std::size_t links = net->links.size();
    for (const auto& k : out["conflict"])
      if (!k.is_number_integer() || k.get<long>() < 0 || k.get<std::size_t>() >= links)
        fuzz::Fail("a conflict names a link the network does not have");
  }
  return 0;
}
