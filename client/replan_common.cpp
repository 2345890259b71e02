#include "client/replan_common.h"

#include <iostream>

#include "planner/model/catalog.h"

namespace ctb::cli {

std::variant<LoadedProblem, Error> LoadProblem(const std::string& domain,
                                               const std::string& config_dir,
                                               const std::string& file) {
  Diagnostics dd;
  auto d = LoadDomainByNameOrPath(domain, config_dir.empty() ? DefaultConfigDir() : config_dir, dd);
  if (!d) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid domain", dd);
  Diagnostics diags;
  auto json = ReadJsonFile(file, diags);
  std::optional<StatePlan> sp;
  if (json) sp = LoadStatePlan(*json, *d, diags);
  for (const auto& w : diags.warnings()) std::cerr << "warning: " << w.ToString() << "\n";
  if (!sp) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid state plan " + file, diags);
  return LoadedProblem{std::move(*d), std::move(*sp)};
}

}  // namespace ctb::cli
