// `ctburton network check FILE`: a bare temporal network (contract section 13) checked locally,
// with the answer of POST /networks/check.
#include <iostream>
#include <memory>
#include <string>

#include "app/core.h"
#include "client/commands.h"
#include "planner/model/json_io.h"

namespace ctb::cli {
namespace {

struct NetworkOptions {
  std::string file;
};

int RunCheck(const NetworkOptions& o) {
  Diagnostics d;
  ParseLimits limits;
  limits.max_bytes = std::size_t{64} << 20;  // a local file: larger than the server's 4 MiB
  std::optional<Json> body = ReadJsonFile(o.file, d, limits);
  if (!body) {
    PrintError(Error::FromDiagnostics(ErrorCode::kInvalidInput, "cannot read " + o.file, d));
    return 1;
  }
  auto r = app::CheckNetworkBody(*body);
  if (auto* e = std::get_if<Error>(&r)) {
    PrintError(*e);
    return ExitCodeFor(e->code);
  }
  std::cout << std::get<Json>(r).dump() << "\n";
  return 0;
}

}  // namespace

Runner AddNetwork(CLI::App& app) {
  auto o = std::make_shared<NetworkOptions>();
  CLI::App* sub = app.add_subcommand("network", "Temporal networks with uncertainty");
  sub->require_subcommand(1);
  CLI::App* check = sub->add_subcommand(
      "check", "Check a network's consistency and strong/dynamic controllability");
  check->add_option("FILE", o->file, "{\"points\": [...], \"links\": [...]} as JSON")->required();
  return [o, check]() { return check->parsed() ? RunCheck(*o) : -1; };
}

}  // namespace ctb::cli
