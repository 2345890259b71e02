#include "planner/replan/situation.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "planner/expr/expr_print.h"

namespace ctb::replan {

namespace {

constexpr long kMaxNowTicks = 100000000;  // keeps every time bound within the solver's integers
constexpr std::size_t kMaxEntries = 2000;

long Ticks(double seconds, long tps) { return std::lround(seconds * static_cast<double>(tps)); }

std::string Seconds(long ticks, long tps) {
  if (tps == 1) return std::to_string(ticks);
  return Json(static_cast<double>(ticks) / static_cast<double>(tps)).dump();
}

// One reported transition (executed, or planned before now) or observation.
struct Entry {
  long time = 0;
  int automaton = -1;
  int from = -1, to = -1;
  int transition = -1;  // -1: an observed jump
  std::optional<long> event;
  std::string pointer;
};

int FindTransition(const Automaton& a, int from, int to) {
  for (std::size_t t = 0; t < a.transitions.size(); ++t)
    if (a.transitions[t].from == from && a.transitions[t].to == to) return static_cast<int>(t);
  return -1;
}

// Reads {"automaton", "from", "to"} at ptr; the other allowed keys are checked by the caller.
bool ReadMove(const ObjectReader& r, const Domain& d, int& a, int& from, int& to,
              Diagnostics& diags) {
  auto an = r.String("automaton", true);
  auto fn = r.String("from", true);
  auto tn = r.String("to", true);
  if (!an || !fn || !tn) return false;
  a = d.AutomatonIndex(*an);
  if (a < 0) {
    diags.Error(r.Child("automaton"), "unknown automaton '" + *an + "'");
    return false;
  }
  const Automaton& au = d.automata[a];
  from = au.LocationIndex(*fn);
  to = au.LocationIndex(*tn);
  if (from < 0) diags.Error(r.Child("from"), "unknown location '" + *fn + "' of '" + au.name + "'");
  if (to < 0) diags.Error(r.Child("to"), "unknown location '" + *tn + "' of '" + au.name + "'");
  return from >= 0 && to >= 0;
}

std::optional<Entry> ReadEntry(const Json& j, const std::string& ptr, const Domain& d, long tps,
                               Diagnostics& diags) {
  ObjectReader r(j, ptr, diags);
  if (!r.valid()) return std::nullopt;
  r.CheckKeys({"time", "event", "automaton", "from", "to", "command", "executed", "observed"});
  Entry e;
  e.pointer = ptr;
  auto time = r.NonNegative("time", true);
  auto observed = r.Bool("observed", false);
  r.Bool("executed", false);
  if (const Json* c = r.Get("command"); c && !c->is_string() && !c->is_null())
    diags.Error(r.Child("command"), "command must be a string or null");
  if (const Json* ev = r.Get("event")) {
    if (!ev->is_number_integer() || ev->get<long>() < 0)
      diags.Error(r.Child("event"), "event must be a non-negative integer");
    else
      e.event = ev->get<long>();
  }
  if (!ReadMove(r, d, e.automaton, e.from, e.to, diags) || !time) return std::nullopt;
  e.time = Ticks(*time, tps);
  if (!observed.value_or(false)) {
    e.transition = FindTransition(d.automata[e.automaton], e.from, e.to);
    if (e.transition < 0) {
      const Automaton& au = d.automata[e.automaton];
      diags.Error(r.Child("to"), "'" + au.name + "' has no transition from '" +
                                     au.locations[e.from] + "' to '" + au.locations[e.to] + "'");
      return std::nullopt;
    }
  }
  return e;
}

std::optional<Error> Fail(const Diagnostics& diags) {
  return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid replanning request", diags);
}

}  // namespace

void BlockedDomains(const Domain& d, const std::vector<Blocked>& blocked, Domain& model,
                    Domain& analysis) {
  model = d;
  analysis = d;
  std::vector<std::set<int>> gone(d.automata.size());
  for (const auto& b : blocked)
    for (int t : b.transitions) {
      gone[b.automaton].insert(t);
      Transition& tr = model.automata[b.automaton].transitions[t];
      tr.guard = Expr{};
      tr.guard.op = Expr::Op::kFalse;
      tr.guard_text = "false";
      tr.guard_info = ExprInfo{};
    }
  for (std::size_t a = 0; a < d.automata.size(); ++a) {
    auto& ts = analysis.automata[a].transitions;
    std::vector<Transition> kept;
    for (std::size_t t = 0; t < ts.size(); ++t)
      if (!gone[a].count(static_cast<int>(t))) kept.push_back(ts[t]);
    ts = std::move(kept);
  }
}

namespace {

class Builder {
 public:
  Builder(const Domain& d, const StatePlan& sp, const ReplanRequest& req, Situation& out)
      : d_(d), sp_(sp), req_(req), s_(out) {}

  std::optional<Error> Run(Keep keep) {
    s_.tps = std::max(1L, std::lround(1.0 / d_.time_resolution));
    auto now = AsNonNegative(req_.now, "/now", diags_);
    if (!now) return Fail(diags_);
    now_ = Ticks(*now, s_.tps);
    if (now_ > kMaxNowTicks) {
      diags_.Error("/now", "now is beyond " + Seconds(kMaxNowTicks, s_.tps) + " s");
      return Fail(diags_);
    }
    s_.history.now = now_;
    ReadBlocked();
    ReadPrevious();
    std::vector<Entry> entries = HistoryEntries();
    if (!diags_.ok()) return Fail(diags_);
    DropHappenedFromBaseline(entries);
    BlockedDomains(d_, s_.blocked, s_.model_domain, s_.analysis_domain);
    Replay(entries);
    if (!diags_.ok()) return Fail(diags_);
    Observe();
    if (!diags_.ok()) return Fail(diags_);
    CatchUpOverdue();
    if (keep == Keep::kStarted) KeepStarted();
    for (const auto& f : s_.history.fired)
      s_.history_cost += d_.automata[f.automaton].transitions[f.transition].cost;
    return std::nullopt;
  }

 private:
  void ReadBlocked() {
    if (req_.blocked.is_null()) return;
    if (!req_.blocked.is_array()) {
      diags_.Error("/blocked", "blocked must be an array");
      return;
    }
    for (std::size_t k = 0; k < req_.blocked.size(); ++k) {
      const std::string ptr = "/blocked/" + std::to_string(k);
      ObjectReader r(req_.blocked[k], ptr, diags_);
      if (!r.valid()) continue;
      r.CheckKeys({"automaton", "from", "to"});
      Blocked b;
      int from = -1, to = -1;
      if (!ReadMove(r, d_, b.automaton, from, to, diags_)) continue;
      const Automaton& au = d_.automata[b.automaton];
      for (std::size_t t = 0; t < au.transitions.size(); ++t)
        if (au.transitions[t].from == from && au.transitions[t].to == to)
          b.transitions.push_back(static_cast<int>(t));
      if (b.transitions.empty()) {
        diags_.Error(r.Child("to"), "'" + au.name + "' has no transition from '" +
                                        au.locations[from] + "' to '" + au.locations[to] + "'");
        continue;
      }
      b.pointer = ptr;
      s_.blocked.push_back(b);
    }
  }

  // The previous plan's transitions: before now (the history when `executed` is absent) and at or
  // after now (the diff's baseline).
  void ReadPrevious() {
    if (req_.previous.is_null()) return;
    const std::string& base = req_.previous_pointer;
    ObjectReader r(req_.previous, base, diags_);
    if (!r.valid()) return;
    const Json* ts = r.Get("transitions");
    if (!ts || !ts->is_array()) {
      diags_.Error(r.Child("transitions"), "the plan being executed needs its transitions (an array)");
      return;
    }
    if (ts->size() > kMaxEntries) {
      diags_.Error(r.Child("transitions"), "too many transitions (at most " + std::to_string(kMaxEntries) + ")");
      return;
    }
    s_.have_previous = true;
    if (const Json* ev = r.Get("events"); ev && ev->is_array())
      for (const auto& e : *ev)
        if (e.is_number() && Ticks(e.get<double>(), s_.tps) >= now_) ++s_.previous_future_events;
    for (std::size_t k = 0; k < ts->size(); ++k) {
      auto e = ReadEntry((*ts)[k], r.Child("transitions") + "/" + std::to_string(k), d_, s_.tps, diags_);
      if (!e) continue;
      if (e->time < now_) {
        previous_before_.push_back(*e);
      } else if (e->transition >= 0) {
        s_.baseline.push_back({e->automaton, e->transition, e->time});
      }
    }
  }

  // A planned transition at exactly now that the history lists has happened: it is not in the
  // future's baseline (the diff would call it dropped, and keep "started" would take it as next).
  void DropHappenedFromBaseline(const std::vector<Entry>& entries) {
    for (const Entry& e : entries) {
      if (e.time != now_ || e.transition < 0) continue;
      auto it = std::find_if(s_.baseline.begin(), s_.baseline.end(), [&](const Planned& p) {
        return p.automaton == e.automaton && p.transition == e.transition && p.time == e.time;
      });
      if (it != s_.baseline.end()) s_.baseline.erase(it);
    }
  }

  std::vector<Entry> HistoryEntries() {
    if (req_.executed.is_null()) {
      if (!s_.have_previous && diags_.ok())
        diags_.Error("/executed", "give what was executed, or the plan being executed ('" +
                                      req_.previous_pointer.substr(1) + "') to take it from");
      // An automaton observed in a location since a time did not take its planned transitions
      // after that time.
      std::vector<Entry> out;
      for (const Entry& e : previous_before_) {
        auto since = ObservedSince(e.automaton);
        if (!since || e.time <= *since) out.push_back(e);
      }
      return out;
    }
    std::vector<Entry> out;
    if (!req_.executed.is_array()) {
      diags_.Error("/executed", "executed must be an array");
      return out;
    }
    if (req_.executed.size() > kMaxEntries) {
      diags_.Error("/executed", "too many entries (at most " + std::to_string(kMaxEntries) + ")");
      return out;
    }
    for (std::size_t k = 0; k < req_.executed.size(); ++k) {
      const std::string ptr = "/executed/" + std::to_string(k);
      auto e = ReadEntry(req_.executed[k], ptr, d_, s_.tps, diags_);
      if (!e) continue;
      if (e->time > now_)
        diags_.Error(ptr + "/time", "after now (" + Seconds(now_, s_.tps) + " s): the history "
                                    "is what happened up to now");
      else if (!out.empty() && e->time < out.back().time)
        diags_.Error(ptr + "/time", "earlier than the entry before it: list the history in order");
      out.push_back(*e);
    }
    return out;
  }

  // The `since` an observation gives for automaton a (unchecked: Observe reports errors).
  std::optional<long> ObservedSince(int a) const {
    if (!req_.observed.is_object()) return std::nullopt;
    auto it = req_.observed.find(d_.automata[a].name);
    if (it == req_.observed.end() || !it->is_object()) return std::nullopt;
    auto s = it->find("since");
    if (s == it->end() || !s->is_number() || !std::isfinite(s->get<double>())) return std::nullopt;
    return Ticks(s->get<double>(), s_.tps);
  }

  void PushStage(long time) {
    History& h = s_.history;
    h.times.push_back(time);
    for (std::size_t a = 0; a < d_.automata.size(); ++a) {
      h.locations[a].push_back(loc_[a]);
      h.entry[a].push_back(entry_[a]);
    }
  }

  // Groups the entries into events (same time, no automaton twice, same `event` when given) and
  // replays them from the initial state; each must start where its automaton is.
  void Replay(const std::vector<Entry>& entries) {
    const std::size_t na = d_.automata.size();
    History& h = s_.history;
    h.locations.assign(na, {});
    h.entry.assign(na, {});
    loc_ = sp_.initial;
    entry_.assign(na, 0);
    PushStage(0);
    std::set<int> moved;
    std::optional<long> event_field;
    std::vector<int> group_loc = loc_, group_cmd(na, 0);  // the stage before the current event
    for (std::size_t i = 0; i < entries.size(); ++i) {
      const Entry& e = entries[i];
      const bool same = i > 0 && e.time == entries[i - 1].time && !moved.count(e.automaton) &&
                        !(e.event && event_field && *e.event != *event_field) &&
                        (e.event || !NeedsItsOwnEvent(e, group_loc, group_cmd));
      if (!same) {
        if (i > 0) PushStage(entries[i - 1].time);
        moved.clear();
        event_field = e.event;
        group_loc = loc_;
        group_cmd.assign(na, 0);
      }
      if (e.transition >= 0 && d_.automata[e.automaton].transitions[e.transition].commanded)
        group_cmd[e.automaton] = d_.automata[e.automaton].transitions[e.transition].command;
      const int k = static_cast<int>(h.times.size());  // this entry's event index
      const Automaton& au = d_.automata[e.automaton];
      if (loc_[e.automaton] != e.from) {
        diags_.Error(e.pointer + "/from", "'" + au.name + "' is in '" + au.locations[loc_[e.automaton]] +
                                              "' at t = " + Seconds(e.time, s_.tps) +
                                              " s by the history before this entry, not in '" +
                                              au.locations[e.from] + "'");
        return;
      }
      moved.insert(e.automaton);
      if (e.transition >= 0)
        h.fired.push_back({k, e.automaton, e.transition});
      else
        h.jumps.push_back({k, e.automaton, e.from, e.to});
      loc_[e.automaton] = e.to;
      entry_[e.automaton] = e.time;
    }
    if (!entries.empty()) PushStage(entries.back().time);
    auto order = [](const auto& x, const auto& y) {
      return x.event != y.event ? x.event < y.event : x.automaton < y.automaton;
    };
    std::sort(h.fired.begin(), h.fired.end(), order);
    std::sort(h.jumps.begin(), h.jumps.end(), order);
  }

  // Entries at one time without `event` indices are grouped in the listed order: an entry joins
  // the current event unless its guard fails on the stage before that event and holds on the
  // stage after the entries listed before it (assembly: arm 2 picks B once block A has left B,
  // at the same time). So every guard holds wherever the listed order obeys the model.
  bool NeedsItsOwnEvent(const Entry& e, const std::vector<int>& group_loc,
                        const std::vector<int>& group_cmd) const {
    if (e.transition < 0) return false;
    const Transition& t = d_.automata[e.automaton].transitions[e.transition];
    auto holds = [&](const std::vector<int>& loc, std::vector<int> cmd) {
      if (t.commanded) cmd[e.automaton] = t.command;
      return Evaluate(t.guard, [&](const Expr& atom) {
        return atom.var_kind == VarKind::kLocation ? loc[atom.target] : cmd[atom.target];
      });
    };
    return !holds(group_loc, group_cmd) &&
           holds(loc_, std::vector<int>(d_.automata.size(), 0));
  }

  // Observations that differ from the history: one event at now.
  void Observe() {
    if (req_.observed.is_null()) return;
    if (!req_.observed.is_object()) {
      diags_.Error("/observed", "observed must be an object: automaton -> {location, since}");
      return;
    }
    std::vector<ObservedJump> jumps;
    std::vector<long> since_of(d_.automata.size());
    const int k = static_cast<int>(s_.history.times.size());
    for (const auto& [name, v] : req_.observed.items()) {
      const std::string ptr = "/observed/" + PointerToken(name);
      const int a = d_.AutomatonIndex(name);
      if (a < 0) {
        diags_.Error(ptr, "unknown automaton '" + name + "'");
        continue;
      }
      ObjectReader r(v, ptr, diags_);
      if (!r.valid()) continue;
      r.CheckKeys({"location", "since"});
      auto ln = r.String("location", true);
      auto since = r.NonNegative("since", false);
      if (!ln) continue;
      const int l = d_.automata[a].LocationIndex(*ln);
      if (l < 0) {
        diags_.Error(r.Child("location"), "unknown location '" + *ln + "' of '" + name + "'");
        continue;
      }
      long s = since ? Ticks(*since, s_.tps) : (l == loc_[a] ? entry_[a] : now_);
      if (s > now_) {
        diags_.Error(r.Child("since"), "after now (" + Seconds(now_, s_.tps) + " s)");
        continue;
      }
      if (l == loc_[a] && s == entry_[a]) continue;  // as the history has it
      jumps.push_back({k, a, loc_[a], l});
      since_of[a] = s;
    }
    if (jumps.empty() || !diags_.ok()) return;
    for (const auto& j : jumps) {
      loc_[j.automaton] = j.to;
      entry_[j.automaton] = since_of[j.automaton];
      s_.history.jumps.push_back(j);
    }
    PushStage(now_);
  }

  // An automaton still in a location the model says it must have left before now: an automatic
  // transition whose guard held and whose lower bound passed (a warm-up running past its
  // duration), or a clock beyond the upper bound of an automatic or controllable transition. It
  // is still there at now (the answer shows its stay as an observation at now), its clock is
  // taken as at most that upper bound, and the transition fires at now, the earliest moment the
  // future has.
  void CatchUpOverdue() {
    History& h = s_.history;
    const long last = h.times.back();
    std::vector<int> late;
    for (std::size_t a = 0; a < d_.automata.size(); ++a) {
      const Automaton& au = s_.model_domain.automata[a];
      bool due = false;
      for (const Transition& t : au.transitions) {
        if (t.from != loc_[a] || t.commanded || !t.guard_info.commands_read.empty()) continue;
        const bool holds = Evaluate(t.guard, [&](const Expr& atom) {
          return atom.var_kind == VarKind::kLocation ? loc_[atom.target] : 0;
        });
        if (!holds) continue;
        if (t.duration.hi && now_ - entry_[a] > Ticks(*t.duration.hi, s_.tps)) {
          entry_[a] = now_ - Ticks(*t.duration.hi, s_.tps);
          due = true;
        }
        if (!t.controllable && std::max(last, entry_[a] + Ticks(t.duration.lo, s_.tps)) < now_)
          due = true;
      }
      if (due) late.push_back(static_cast<int>(a));
    }
    if (late.empty()) return;
    if (last < now_) {
      const int k = static_cast<int>(h.times.size());
      for (int a : late) h.jumps.push_back({k, a, loc_[a], loc_[a]});
      PushStage(now_);
      return;
    }
    // The last event is at now already: its stage takes the clocks, and the stays are shown there.
    const int k = h.events();
    for (int a : late) {
      h.entry[a][k] = entry_[a];
      bool moved = false;
      for (const auto& j : h.jumps) moved = moved || (j.event == k && j.automaton == a);
      for (const auto& f : h.fired) moved = moved || (f.event == k && f.automaton == a);
      if (!moved) h.jumps.push_back({k, a, loc_[a], loc_[a]});
    }
    std::sort(h.jumps.begin(), h.jumps.end(), [](const auto& x, const auto& y) {
      return x.event != y.event ? x.event < y.event : x.automaton < y.automaton;
    });
  }

  // keep "started": an automaton whose stay began before now goes on with the transition the
  // previous plan had it take next from there (unless that one is blocked).
  void KeepStarted() {
    for (std::size_t a = 0; a < d_.automata.size(); ++a) {
      if (entry_[a] >= now_) continue;
      const Planned* next = nullptr;
      for (const auto& p : s_.baseline)
        if (p.automaton == static_cast<int>(a) && (!next || p.time < next->time)) next = &p;
      if (!next) continue;
      const Transition& t = s_.model_domain.automata[a].transitions[next->transition];
      if (t.from != loc_[a] || t.guard.op == Expr::Op::kFalse) continue;
      s_.history.keep_next.emplace_back(static_cast<int>(a), next->transition);
    }
  }

  const Domain& d_;
  const StatePlan& sp_;
  const ReplanRequest& req_;
  Situation& s_;
  Diagnostics diags_;
  long now_ = 0;
  std::vector<Entry> previous_before_;
  std::vector<int> loc_;
  std::vector<long> entry_;
};

}  // namespace

std::optional<Error> BuildSituation(const Domain& d, const StatePlan& sp, const ReplanRequest& req,
                                    Keep keep, Situation& out) {
  return Builder(d, sp, req, out).Run(keep);
}

}  // namespace ctb::replan
