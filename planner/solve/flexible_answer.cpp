#include "planner/solve/flexible_answer.h"

#include <chrono>
#include <cmath>

#include "planner/flexible/flexible.h"
#include "planner/network/check.h"
#include "planner/network/network_json.h"

namespace ctb::solve {

namespace {

// The links of a conflict in words: each link's source and bounds.
Json ConflictJson(const network::Network& net, const std::vector<int>& links) {
  Json out = Json::array();
  for (int i : links) {
    const auto& l = net.links[i];
    out.push_back({{"link", i},
                   {"kind", l.contingent ? "contingent" : "requirement"},
                   {"why", l.why},
                   {"lb", network::SecondsFromTicks(l.lb)},
                   {"ub", l.ub ? Json(network::SecondsFromTicks(*l.ub)) : Json()}});
  }
  return out;
}

}  // namespace

void AddFlexibility(Json& answer, const Trajectory& plan, const Domain& d, const StatePlan& sp,
                    const SolveOptions& o) {
  std::string why;
  auto f = flexible::DeriveNetwork(plan, d, sp, std::lround(1.0 / d.time_resolution), &why);
  if (!f) {
    answer["network"] = nullptr;
    answer["controllability"] = {{"note", why}};
    return;
  }
  answer["network"] = network::NetworkToJson(f->net);
  if (f->rigid) answer["network"]["rigid"] = f->rigid_reason;
  auto windows = flexible::Windows(f->net);
  answer["slack"] = windows ? flexible::SlackJson(*windows) : Json::array();
  const network::CheckResult check = network::CheckNetwork(f->net);
  Json c = {{"strong", check.strong}, {"dynamic", check.dynamic},
            {"ms", std::round(check.ms * 1000) / 1000}};
  Controllability asked = o.controllability;
  if (asked == Controllability::kAuto)
    asked = d.HasContingent() ? Controllability::kDynamic : Controllability::kNone;
  c["asked"] = ControllabilityName(asked);
  if (!check.dynamic) c["conflict"] = ConflictJson(f->net, check.conflict);
  const bool met = asked == Controllability::kNone ||
                   (asked == Controllability::kStrong ? check.strong : check.dynamic);
  if (!met) {
    // A plan of another kind is no answer to the request: say which rule it breaks. The search
    // among plans stops at the first (docs/uncertainty.md), so nothing is proven: unknown.
    c["met"] = false;
    answer["status"] = "unknown";
    answer["message"] = std::string("the plan found is not ") +
                        (asked == Controllability::kStrong ? "strongly" : "dynamically") +
                        " controllable: some outcome of its contingent durations breaks it";
  }
  answer["controllability"] = std::move(c);
}

}  // namespace ctb::solve
