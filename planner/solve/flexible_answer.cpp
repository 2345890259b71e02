#include "planner/solve/flexible_answer.h"

#include <cmath>
#include <functional>

#include "planner/flexible/dispatch.h"
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

// Relaxations of a conflict (contract section 13), each on this plan's network and checked
// before it is offered: for a requirement of the state plan, the least later upper bound that
// makes the network dynamically controllable; for a contingent duration, the widest range
// [lo, x] (its longest outcome earlier) that does. Whole seconds; monotone, so a binary search.
Json Relaxations(const flexible::FlexiblePlan& f, const Domain& d, const std::vector<int>& conflict) {
  const network::Network& net = f.net;
  using network::Ticks;
  const Ticks second = network::kTicksPerSecond;
  Ticks spread = second;
  for (const auto& l : net.links)
    if (l.contingent) spread += *l.ub - l.lb;
  const Ticks steps = (spread + second - 1) / second;
  Json out = Json::array();
  auto seconds = [](Ticks t) { return network::SecondsFromTicks(t); };
  for (int li : conflict) {
    const network::Link& l = net.links[li];
    // A bound of the state plan (an episode's or temporal constraint's link): its `why` is their
    // pointer and it bounds something; the derivation's own orders and ties never are.
    const bool requirement = !l.contingent && !l.why.empty() && l.why[0] == '/' &&
                             (l.lb != 0 || l.ub.has_value());
    if (!requirement && !l.contingent) continue;
    auto dc_with = [&](Ticks lb, std::optional<Ticks> ub) {
      network::Network n = net;
      n.links[li].lb = lb;
      n.links[li].ub = ub;
      return network::IsDynamicallyControllable(n);
    };
    // The least k whole seconds (1..max) for which change(k) is controllable; 0 when none.
    auto least = [&](Ticks max, const std::function<bool(Ticks)>& ok) -> Ticks {
      if (max < 1 || !ok(max)) return 0;
      Ticks no = 0, yes = max;
      while (yes - no > 1) {
        const Ticks mid = (no + yes) / 2;
        (ok(mid) ? yes : no) = mid;
      }
      return yes;
    };
    auto offer = [&](const char* kind, Json from, Json to, const std::string& text) {
      Json r = {{"why", l.why}, {"kind", kind}, {"from", std::move(from)},
                {"to", std::move(to)}, {"text", l.why + ": " + text}};
      if (l.contingent) {  // which transition's duration
        const Automaton& a = d.automata[f.point_automaton[l.to]];
        const Transition& tr = a.transitions[f.point_transition[l.to]];
        r["transition"] = {{"automaton", a.name}, {"from", a.locations[tr.from]},
                           {"to", a.locations[tr.to]}};
      }
      out.push_back(std::move(r));
    };
    if (requirement && l.ub) {  // a later upper bound
      if (Ticks k = least(steps, [&](Ticks k) { return dc_with(l.lb, *l.ub + k * second); }))
        offer("later_upper_bound", seconds(*l.ub), seconds(*l.ub + k * second),
              "an upper bound of " + Json(seconds(*l.ub + k * second)).dump() + " s instead of " +
                  Json(seconds(*l.ub)).dump() + " s");
    }
    if (requirement && l.lb > -spread) {  // an earlier lower bound
      if (Ticks k = least(steps, [&](Ticks k) { return dc_with(l.lb - k * second, l.ub); }))
        offer("earlier_lower_bound", seconds(l.lb), seconds(l.lb - k * second),
              "a lower bound of " + Json(seconds(l.lb - k * second)).dump() + " s instead of " +
                  Json(seconds(l.lb)).dump() + " s");
    }
    if (l.contingent) {  // a narrower uncertain duration, from above or from below
      const Ticks width = (*l.ub - l.lb) / second;
      if (Ticks k = least(width, [&](Ticks k) { return dc_with(l.lb, *l.ub - k * second); }))
        offer("narrower_duration", Json::array({seconds(l.lb), seconds(*l.ub)}),
              Json::array({seconds(l.lb), seconds(*l.ub - k * second)}),
              "at most " + Json(seconds(*l.ub - k * second)).dump() + " s instead of " +
                  Json(seconds(*l.ub)).dump() + " s");
      if (Ticks k = least(width, [&](Ticks k) { return dc_with(l.lb + k * second, l.ub); }))
        offer("narrower_duration", Json::array({seconds(l.lb), seconds(*l.ub)}),
              Json::array({seconds(l.lb + k * second), seconds(*l.ub)}),
              "at least " + Json(seconds(l.lb + k * second)).dump() + " s instead of " +
                  Json(seconds(l.lb)).dump() + " s");
    }
  }
  return out;
}

constexpr int kRiskSamples = 2000;

// Where contingent transitions carry distributions: the chance that the dispatched plan meets
// every link. A dynamically controllable plan always does (its dispatcher never fails): 1,
// exactly. Otherwise the plan started at its own times, estimated over kRiskSamples draws.
std::optional<Json> SuccessProbability(const flexible::FlexiblePlan& f, const Domain& d,
                                       const Trajectory& plan, bool dynamic) {
  bool any = false;
  for (const auto& a : d.automata)
    for (const auto& t : a.transitions) any = any || (t.contingent && t.distribution);
  if (!any) return std::nullopt;
  if (dynamic) return Json{{"value", 1.0}, {"samples", 0}};
  const std::vector<network::Ticks> planned = flexible::PlanTimes(f, plan);
  flexible::DispatchOptions o;
  o.dynamic = false;
  o.sampling = flexible::Sampling::kDistribution;
  std::mt19937 rng(1);
  int met = 0;
  for (int i = 0; i < kRiskSamples; ++i) met += flexible::Execute(f, d, planned, o, rng).met ? 1 : 0;
  return Json{{"value", static_cast<double>(met) / kRiskSamples}, {"samples", kRiskSamples}};
}

}  // namespace

Controllability Asked(const Domain& d, const SolveOptions& o) {
  if (o.controllability != Controllability::kAuto) return o.controllability;
  return d.HasContingent() ? Controllability::kDynamic : Controllability::kNone;
}

FlexibleOutcome AddFlexibility(SolveResult& answer, const Trajectory& plan, const Domain& d,
                               const StatePlan& sp, const SolveOptions& o) {
  FlexibleOutcome outcome;
  std::string why;
  auto f = flexible::DeriveNetwork(plan, d, sp, std::lround(1.0 / d.time_resolution), &why);
  if (!f) {
    answer.network = Json();
    answer.controllability = Json{{"note", why}};
    return outcome;
  }
  answer.network = network::NetworkToJson(f->net);
  if (f->rigid) (*answer.network)["rigid"] = f->rigid_reason;
  auto windows = flexible::Windows(f->net);
  answer.slack = windows ? flexible::SlackJson(*windows) : Json::array();
  const network::CheckResult check = network::CheckNetwork(f->net);
  Json c = {{"strong", check.strong}, {"dynamic", check.dynamic},
            {"ms", std::round(check.ms * 1000) / 1000}};
  const Controllability asked = Asked(d, o);
  c["asked"] = ControllabilityName(asked);
  if (!check.dynamic) {
    c["conflict"] = ConflictJson(f->net, check.conflict);
    c["relaxations"] = Relaxations(*f, d, check.conflict);
    outcome.conflict = check.conflict;
  }
  bool met = asked == Controllability::kNone ||
             (asked == Controllability::kStrong ? check.strong : check.dynamic);
  // The chance under the dispatch the asked kind means: reacting (dynamic) or fixed times (strong).
  const bool reacting = asked != Controllability::kStrong && check.dynamic;
  if (auto p = SuccessProbability(*f, d, plan, reacting ? true : check.strong)) {
    c["success_probability"] = *p;
    if (!met && o.risk_bound && 1.0 - (*p)["value"].get<double>() <= *o.risk_bound) {
      met = true;  // not controllable, but it fails no more often than the caller accepts
      c["accepted_at_risk"] = *o.risk_bound;
    }
  }
  if (!met) {
    // A plan of another kind is no answer to the request: say which rule it breaks. The search
    // among plans stops at the first (docs/uncertainty.md), so nothing is proven: unknown.
    c["met"] = false;
    answer.status = Termination::kUnknown;
    answer.message = std::string("the plan found is not ") +
                        (asked == Controllability::kStrong ? "strongly" : "dynamically") +
                        " controllable: some outcome of its contingent durations breaks it";
  }
  answer.controllability = std::move(c);
  outcome.met = met;
  outcome.plan = std::move(f);
  return outcome;
}

}  // namespace ctb::solve
