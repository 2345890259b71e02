// Small random planning problems for the differential and brute-force tests: random automata
// (commanded and automatic transitions, guards across automata), random episodes, temporal and
// shared-event constraints, goals (sometimes rewritten into equivalent forms an LLM writes) and
// objectives. Deterministic for a seed: a failing case is printed and can be replayed.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "planner/model/json_io.h"

namespace ctb::testing {

struct RandomProblem {
  Json domain;
  Json state_plan;
  std::string Describe() const {
    return "domain: " + domain.dump() + "\nstate plan: " + state_plan.dump();
  }
};

struct RandomShape {
  int min_automata = 1, max_automata = 3;
  int max_locations = 3;
  int max_duration = 4;   // transition lower durations drawn from 0..max_duration
  int max_bound = 8;      // episode and temporal bounds drawn from 0..max_bound
  bool cross_guards = true;   // guards reading another automaton's location
  bool rewrite = true;        // equivalent rewritings of the goal and maintenance
  bool shared_events = true;
  bool state_refs = true;     // conditions that read an episode's or a temporal constraint's state
};

class ProblemGenerator {
 public:
  explicit ProblemGenerator(unsigned seed, RandomShape shape = {}) : rng_(seed), shape_(shape) {}

  RandomProblem Next() {
    RandomProblem p;
    const int na = Int(shape_.min_automata, shape_.max_automata);
    names_.clear();
    locations_.clear();
    initial_.clear();
    Json automata = Json::array();
    for (int a = 0; a < na; ++a) {
      std::string name = std::string(1, static_cast<char>('a' + a));
      names_.push_back(name);
      int nl = Int(2, shape_.max_locations);
      std::vector<std::string> locs;
      for (int l = 0; l < nl; ++l) locs.push_back(name + "L" + std::to_string(l));
      locations_.push_back(locs);
      initial_.push_back(Int(0, nl - 1));
    }
    for (int a = 0; a < na; ++a) automata.push_back(Automaton(a));
    p.domain = {{"name", "random"}, {"description", "generated"}, {"automata", automata}};
    p.state_plan = StatePlan(na);
    return p;
  }

 private:
  int Int(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  bool Chance(double p) { return std::bernoulli_distribution(p)(rng_); }
  const std::string& Loc(int a, int l) const { return locations_[a][l]; }
  std::string RandomLoc(int a) { return Loc(a, Int(0, static_cast<int>(locations_[a].size()) - 1)); }

  Json Automaton(int a) {
    const std::string& n = names_[a];
    const int nl = static_cast<int>(locations_[a].size());
    Json transitions = Json::array();
    Json commands = Json::array();
    int ncmd = 0;
    // A ring through every location (so every location is reachable), plus a chord or two.
    std::vector<std::pair<int, int>> edges;
    for (int l = 0; l < nl; ++l) edges.emplace_back(l, (l + 1) % nl);
    if (nl > 2 && Chance(0.5)) edges.emplace_back(Int(0, nl - 1), Int(0, nl - 1));
    std::vector<std::pair<int, int>> seen;
    for (auto [from, to] : edges) {
      if (from == to) continue;
      bool dup = false;
      for (auto& s : seen) dup = dup || s == std::make_pair(from, to);
      if (dup) continue;
      seen.emplace_back(from, to);
      Json t = {{"from", Loc(a, from)}, {"to", Loc(a, to)}};
      std::string guard;
      // Two automatic transitions out of one location could both be enabled; keep at most one
      // automatic transition per source location, the rest commanded.
      bool automatic = Chance(0.35) && !HasAutomaticFrom(transitions, Loc(a, from));
      if (!automatic) {
        std::string cmd = n + "C" + std::to_string(ncmd++);
        commands.push_back(cmd);
        guard = n + "u[i]==" + cmd;
      }
      if (shape_.cross_guards && names_.size() > 1 && Chance(0.25)) {
        int b = Int(0, static_cast<int>(names_.size()) - 1);
        if (b != a) guard += (guard.empty() ? "" : " /\\ ") + names_[b] + "l[i]==" + RandomLoc(b);
      }
      if (!guard.empty()) t["guard"] = guard;
      int lo = Int(0, shape_.max_duration);
      if (automatic && lo == 0) lo = 1;  // an automatic zero-duration loop would never rest
      if (lo > 0 || Chance(0.3)) {
        Json hi = Chance(0.5) ? Json(nullptr) : Json(lo + Int(0, 3));
        t["duration"] = {lo, hi};
      }
      if (Chance(0.4)) t["cost"] = Int(1, 3);
      transitions.push_back(t);
    }
    return {{"name", n}, {"locations", locations_[a]}, {"commands", commands},
            {"transitions", transitions}};
  }

  static bool HasAutomaticFrom(const Json& transitions, const std::string& from) {
    for (const auto& t : transitions)
      if (t["from"] == from && !t.contains("guard")) return true;
    return false;
  }

  std::string StateAtom(int a, bool next) {
    return names_[a] + "l[" + (next ? "i+1" : "i") + "]==" + RandomLoc(a);
  }

  std::string Rewrite(const std::string& g) {
    if (!shape_.rewrite || !Chance(0.3)) return g;
    switch (Int(0, 4)) {
      case 0: return "not not (" + g + ")";
      case 1: return "true -> (" + g + ")";
      case 2: return "(" + g + ") \\/ false";
      case 3: return "(true) /\\ (" + g + ")";
      default: return "(" + g + ") /\\ (" + names_[0] + "l[i+1]==" + Loc(0, 0) + " \\/ " +
                      names_[0] + "l[i+1]!=" + Loc(0, 0) + ")";
    }
  }

  Json StatePlan(int na) {
    Json init = Json::object();
    for (int a = 0; a < na; ++a) init[names_[a]] = Loc(a, initial_[a]);
    // Goal: a location for some automata.
    std::string goal;
    for (int a = 0; a < na; ++a)
      if (Chance(0.7) || (a == na - 1 && goal.empty()))
        goal += (goal.empty() ? "" : " /\\ ") + StateAtom(a, true);
    std::string maintenance = "true";
    if (Chance(0.15)) {
      int a = Int(0, na - 1);
      maintenance = names_[a] + "l[i]!=" + RandomLoc(a);
    } else if (shape_.rewrite && Chance(0.2)) {
      maintenance = Chance(0.5) ? "(true) /\\ (true)" : "not not true";
    }
    Json episodes = Json::object(), temporal = Json::object(), events = Json::object();
    const int ne = Chance(0.5) ? Int(1, 2) : 0;
    for (int p = 0; p < ne; ++p) {
      int a = Int(0, na - 1);
      std::string loc = RandomLoc(a);
      std::string accepting = Chance(0.1) ? "true" : names_[a] + "l[i]==" + loc;
      int lo = Int(0, shape_.max_bound), hi = lo + Int(0, 3);
      Json ep = {{"accepting_constraint", accepting}, {"lower_bound", lo}, {"upper_bound", hi}};
      if (accepting != "true") ep["state_constraint"] = names_[a] + "l[i]==" + loc;
      episodes["E" + std::to_string(p)] = ep;
    }
    const int nq = Chance(0.5) ? Int(1, 2) : 0;
    for (int q = 0; q < nq; ++q) {
      int a = Int(0, na - 1), b = Int(0, na - 1);
      std::string e1 = Chance(0.5) ? names_[a] + "l[i]==" + RandomLoc(a) + " /\\ " +
                                         names_[a] + "l[i+1]==" + RandomLoc(a)
                                   : StateAtom(a, true);
      std::string e2 = StateAtom(b, true);
      // The thesis' form: the second event needs the constraint active; or an event after an
      // episode's end.
      if (shape_.state_refs && Chance(0.25))
        e2 += " /\\ temporalAcceptConstraint_Traj_T" + std::to_string(q) + "[i]==tempActive";
      if (shape_.state_refs && ne > 0 && Chance(0.15))
        e1 += " /\\ epAcceptAutomatonTraj_E0[i]==epAccepted";
      int lo = Int(0, shape_.max_bound), hi = lo + Int(0, 4);
      temporal["T" + std::to_string(q)] = {{"accepting_event1_constraint", e1},
                                           {"accepting_event2_constraint", e2},
                                           {"lower_bound", lo}, {"upper_bound", hi}};
    }
    if (shape_.shared_events && ne > 0 && nq > 0 && Chance(0.3))
      events["S"] = Json::array({"E0.end", "T0.event1"});
    static const char* const kObjectives[] = {"cost", "makespan", "cost_then_makespan"};
    return {{"initial_state", init},
            {"end_state", {{"maintenance_constraint", maintenance},
                           {"goal_constraint", Rewrite(goal)}}},
            {"constraints", {{"episodes", episodes}, {"temporal", temporal}, {"event", events}}},
            {"objective", kObjectives[Int(0, 2)]}};
  }

  std::mt19937 rng_;
  RandomShape shape_;
  std::vector<std::string> names_;
  std::vector<std::vector<std::string>> locations_;
  std::vector<int> initial_;
};

// Near-miss impossible requests (issue 20) made from a state plan: every deadline made earlier
// (each temporal constraint's upper bound at every value from its own down to 0), every episode
// made longer (its lower and upper bounds raised by 1..`raise`), and every location forbidden on
// every stage by the maintenance constraint. A test keeps those that a proof route calls
// infeasible and checks them against the others; the one unit between the least refuted and the
// greatest allowed bound is where an unsound rule shows.
struct NearMiss {
  std::string what;  // "T0/upper_bound=3", "E1 longer by 2", "maintenance al[i]!=aL1"
  std::string pointer;  // the bound or part changed
  Json state_plan;
};

inline std::vector<NearMiss> NearMissVariants(const Json& domain, const Json& state_plan,
                                              int raise = 6) {
  std::vector<NearMiss> out;
  const Json& c = state_plan["constraints"];
  for (const auto& [name, t] : c["temporal"].items()) {
    for (int u = t["upper_bound"].get<int>() - 1; u >= 0; --u) {
      Json sp = state_plan;
      Json& x = sp["constraints"]["temporal"][name];
      x["upper_bound"] = u;
      if (x["lower_bound"].get<int>() > u) x["lower_bound"] = u;
      out.push_back({name + "/upper_bound=" + std::to_string(u),
                     "/constraints/temporal/" + name + "/upper_bound", sp});
    }
  }
  for (const auto& [name, e] : c["episodes"].items()) {
    for (int k = 1; k <= raise; ++k) {
      Json sp = state_plan;
      Json& x = sp["constraints"]["episodes"][name];
      x["lower_bound"] = e["lower_bound"].get<int>() + k;
      x["upper_bound"] = e["upper_bound"].get<int>() + k;
      out.push_back({name + " longer by " + std::to_string(k),
                     "/constraints/episodes/" + name + "/lower_bound", sp});
    }
  }
  if (state_plan["end_state"]["maintenance_constraint"] == "true") {
    for (const auto& a : domain["automata"])
      for (const auto& l : a["locations"]) {
        Json sp = state_plan;
        const std::string m = a["name"].get<std::string>() + "l[i]!=" + l.get<std::string>();
        sp["end_state"]["maintenance_constraint"] = m;
        out.push_back({"maintenance " + m, "/end_state/maintenance_constraint", sp});
      }
  }
  return out;
}

// Either-order near misses (issue 20, the time network's split on the order of two events): two
// deadlines from the start that conflict only together. From the problem's initial state (every
// automaton where it starts: both constraints active at e[0]), temporal constraint First ends
// when automaton a reaches X and Second when a is in W and b in Y (X != W, neither end holding
// at the start): whichever comes first, a must then travel between X and W. One base per choice
// of X, W and Y; the test sets both upper bounds (the `upper_bound`s of First and Second) on a
// grid and keeps the loosest pairs a proof route refutes only by splitting on the order.
inline std::vector<NearMiss> EitherOrderBases(const Json& domain, const Json& state_plan) {
  std::vector<NearMiss> out;
  const Json& automata = domain["automata"];
  if (automata.size() < 2) return out;
  const Json& init = state_plan["initial_state"];
  const std::string a = automata[0]["name"], b = automata[1]["name"];
  std::string start;
  for (const auto& x : automata) {
    const std::string n = x["name"];
    start += (start.empty() ? "" : " /\\ ") + n + "l[i]==" + init[n].get<std::string>();
  }
  for (const auto& x : automata[0]["locations"])
    for (const auto& w : automata[0]["locations"])
      for (const auto& y : automata[1]["locations"]) {
        if (x == w || x == init[a] || y == init[b]) continue;
        const std::string xs = x, ws = w, ys = y;
        Json sp = {{"initial_state", init},
                   {"end_state", {{"maintenance_constraint", "true"}, {"goal_constraint", "true"}}},
                   {"constraints",
                    {{"episodes", Json::object()},
                     {"event", Json::object()},
                     {"temporal",
                      {{"First", {{"accepting_event1_constraint", start},
                                  {"accepting_event2_constraint", a + "l[i+1]==" + xs},
                                  {"lower_bound", 0}, {"upper_bound", 0}}},
                       {"Second", {{"accepting_event1_constraint", start},
                                   {"accepting_event2_constraint",
                                    a + "l[i+1]==" + ws + " /\\ " + b + "l[i+1]==" + ys},
                                   {"lower_bound", 0}, {"upper_bound", 0}}}}}}}};
        out.push_back({a + " to " + xs + "; " + a + " in " + ws + " and " + b + " in " + ys,
                       "/constraints/temporal", sp});
      }
  return out;
}

}  // namespace ctb::testing
