// Learned durations (contract section 14): how long each transition's stay took in the
// executions of a domain, and a revision of the domain that admits what was seen.
#include <algorithm>
#include <cmath>
#include <map>

#include "app/core_impl.h"
#include "app/executions.h"

namespace ctb::app {

namespace {

struct Seen {
  long count = 0;
  double min = 0, max = 0, sum = 0;
};

using Key = std::tuple<std::string, std::string, std::string>;  // automaton, from, to

// Every stay in the histories: the time from entering `from` (0 for where it started) to the
// transition out of it.
std::map<Key, Seen> Stays(const std::vector<Json>& histories) {
  std::map<Key, Seen> out;
  for (const Json& h : histories) {
    std::map<std::string, double> entered;
    std::vector<Json> entries(h.begin(), h.end());
    std::stable_sort(entries.begin(), entries.end(),
                     [](const Json& a, const Json& b) { return a.value("time", 0.0) < b.value("time", 0.0); });
    for (const Json& e : entries) {
      const std::string a = e.value("automaton", "");
      const double t = e.value("time", 0.0);
      const double d = t - (entered.count(a) ? entered[a] : 0.0);
      entered[a] = t;
      Seen& s = out[{a, e.value("from", ""), e.value("to", "")}];
      s.min = s.count ? std::min(s.min, d) : d;
      s.max = s.count ? std::max(s.max, d) : d;
      s.sum += d;
      ++s.count;
    }
  }
  return out;
}

// The domain (plain automata) with every automatic transition's bounds widened to what was seen,
// and marked contingent where what was seen spreads; checked like any domain, without the
// contingent marks the loader refuses (a guard, another way out), or null when even that fails.
Json Suggest(const Domain& d, Json doc, const std::map<Key, Seen>& seen) {
  bool changed = false;
  for (bool contingent : {true, false}) {
    Json out = doc;
    changed = false;
    for (std::size_t ai = 0; ai < d.automata.size(); ++ai) {
      const Automaton& a = d.automata[ai];
      for (std::size_t ti = 0; ti < a.transitions.size(); ++ti) {
        const Transition& tr = a.transitions[ti];
        auto it = seen.find({a.name, a.locations[tr.from], a.locations[tr.to]});
        if (tr.commanded || it == seen.end()) continue;  // a command's timing is the planner's
        // Widened, never narrowed: an unbounded stay stays unbounded.
        const double res = d.time_resolution;
        const double lo = std::floor(std::min(tr.duration.lo, it->second.min) / res) * res;
        std::optional<double> hi = tr.duration.hi;
        if (hi) hi = std::ceil(std::max(*hi, it->second.max) / res) * res;
        Json& t = out["automata"][ai]["transitions"][ti];
        if (lo != tr.duration.lo || hi != tr.duration.hi) {
          t["duration"] = {lo, hi ? Json(*hi) : Json()};
          changed = true;
        }
        if (contingent && hi && !tr.contingent && it->second.max > it->second.min) {
          t["contingent"] = true;
          changed = true;
        }
      }
    }
    Diagnostics diags;
    if (LoadDomain(out, diags)) return changed ? out : Json();
  }
  return Json();
}

}  // namespace

std::variant<Json, Error> Core::DomainDurations(const std::string& name) {
  auto dom = impl_->NamedDomain(name);
  if (auto* e = std::get_if<Error>(&dom)) return *e;
  const Domain& d = *std::get<std::shared_ptr<const Domain>>(dom);
  auto histories = impl_->executions->Histories(name);
  if (auto* e = std::get_if<Error>(&histories)) return *e;
  const auto seen = Stays(std::get<std::vector<Json>>(histories));
  Json rows = Json::array();
  for (const auto& [k, s] : seen)
    rows.push_back({{"automaton", std::get<0>(k)}, {"from", std::get<1>(k)}, {"to", std::get<2>(k)},
                    {"count", s.count}, {"min", s.min}, {"max", s.max},
                    {"mean", std::round(s.sum / static_cast<double>(s.count) * 1000) / 1000}});
  auto plain = GetDomain(name, /*as_written=*/false);
  Json suggested = std::holds_alternative<Json>(plain) ? Suggest(d, std::get<Json>(plain), seen) : Json();
  return Json{{"transitions", rows}, {"suggested", suggested}};
}

}  // namespace ctb::app
