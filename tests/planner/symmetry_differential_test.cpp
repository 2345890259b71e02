// Symmetry breaking (issue 18, lever 4) against the plain models: small random problems built
// symmetric on purpose (copies of one automaton, alone or in units with a helper each, a shared
// automaton that reads them all, state plans that treat every copy alike, and sometimes a twist
// that breaks the symmetry), solved with and without the ordering of interchangeable automata.
// Statuses and optimal objective values must agree and every plan must verify; a failure prints
// the case so it can be replayed with `ctburton solve`.
#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <random>
#include <string>

#include "planner/analyze/symmetry.h"
#include "planner/solve/solve.h"
#include "random_problem.h"
#include "test_util.h"

namespace ctb {
// A namespace of its own: the test executable's unity build puts files with same-named
// helpers side by side.
namespace symmetry_differential_test {
namespace {

constexpr int kMaxHorizon = 7;

// One transition of the copies' template; "{k}" in guards stands for the copy's number.
struct TransitionSpec {
  int from = 0, to = 0;
  std::string guard;
  int lo = 0;
  int hi = -1;   // -1: unbounded; -2: no duration given
  int cost = 0;  // 0: not given
  bool automatic = false;
};

class SymmetricGenerator {
 public:
  explicit SymmetricGenerator(unsigned seed) : rng_(seed) {}

  testing::RandomProblem Next() {
    m_ = Int(2, 3);
    nl_ = Int(2, 3);
    helper_ = Chance(0.4);
    shared_ = Chance(0.6);
    // A twist that breaks the symmetry: 1 a goal on one copy, 2 that copy slower, 3 episodes on
    // that copy only; the first or the last (which an ordering would favour differently).
    twist_ = Chance(0.5) ? Int(1, 3) : 0;
    odd_ = Chance(0.5) ? 1 : m_;
    MakeTemplate();
    Json automata = Json::array();
    for (int k = 1; k <= m_; ++k) {
      automata.push_back(Copy(k));
      if (helper_) automata.push_back(Helper(k));
    }
    if (shared_) automata.push_back(Shared());
    testing::RandomProblem p;
    p.domain = {{"name", "symmetric"}, {"description", "generated"}, {"automata", automata}};
    p.state_plan = Plan();
    return p;
  }

 private:
  int Int(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  bool Chance(double p) { return std::bernoulli_distribution(p)(rng_); }
  static std::string Loc(int l) { return "p" + std::to_string(l); }
  std::string R(int k) const { return "r" + std::to_string(k); }

  void MakeTemplate() {
    specs_.clear();
    std::vector<std::pair<int, int>> edges;
    for (int l = 0; l < nl_; ++l) edges.emplace_back(l, (l + 1) % nl_);
    if (nl_ > 2 && Chance(0.5)) edges.emplace_back(0, 2);
    int ncmd = 0;
    for (auto [from, to] : edges) {
      TransitionSpec t;
      t.from = from;
      t.to = to;
      // At most one automatic transition out of a location (two could both be enabled).
      t.automatic = Chance(0.25);
      for (const auto& s : specs_) t.automatic = t.automatic && !(s.from == from && s.automatic);
      if (!t.automatic) t.guard = "r{k}u[i]==c" + std::to_string(ncmd++);
      if (helper_ && Chance(0.4))
        t.guard += (t.guard.empty() ? "" : " /\\ ") + std::string("h{k}l[i]==q") +
                   std::to_string(Int(0, 1));
      if (shared_ && Chance(0.25))
        t.guard +=
            (t.guard.empty() ? "" : " /\\ ") + std::string("sl[i]==s") + std::to_string(Int(0, 1));
      t.lo = Int(0, 3);
      if (t.automatic && t.lo == 0) t.lo = 1;
      t.hi = t.lo > 0 || Chance(0.3) ? (Chance(0.5) ? -1 : t.lo + Int(0, 2)) : -2;
      if (Chance(0.4)) t.cost = Int(1, 3);
      specs_.push_back(t);
    }
    commands_ = ncmd;
  }

  static std::string Instance(std::string s, int k) {
    for (std::size_t at; (at = s.find("{k}")) != std::string::npos;)
      s.replace(at, 3, std::to_string(k));
    return s;
  }

  Json Copy(int k) const {
    Json locations = Json::array(), commands = Json::array(), transitions = Json::array();
    for (int l = 0; l < nl_; ++l) locations.push_back(Loc(l));
    for (int c = 0; c < commands_; ++c) commands.push_back("c" + std::to_string(c));
    for (std::size_t i = 0; i < specs_.size(); ++i) {
      const TransitionSpec& s = specs_[i];
      Json t = {{"from", Loc(s.from)}, {"to", Loc(s.to)}};
      if (!s.guard.empty()) t["guard"] = Instance(s.guard, k);
      int lo = s.lo;
      if (twist_ == 2 && k == odd_ && i == 0) lo += 1;  // slower
      if (s.hi != -2 || lo != s.lo)
        t["duration"] = {lo, s.hi == -1 ? Json(nullptr) : Json(std::max(s.hi, lo))};
      if (s.cost > 0) t["cost"] = s.cost;
      transitions.push_back(t);
    }
    return {{"name", R(k)},
            {"locations", locations},
            {"commands", commands},
            {"transitions", transitions}};
  }

  Json Helper(int k) const {
    const std::string h = "h" + std::to_string(k);
    return {{"name", h},
            {"locations", {"q0", "q1"}},
            {"commands", {"d0", "d1"}},
            {"transitions",
             {{{"from", "q0"}, {"to", "q1"}, {"guard", h + "u[i]==d0"}, {"duration", {1, 2}}},
              {{"from", "q1"}, {"to", "q0"}, {"guard", h + "u[i]==d1"}}}}};
  }

  // s moves to s1 one second after some copy is at p1, and back on command.
  Json Shared() const {
    std::string any;
    for (int k = 1; k <= m_; ++k) any += (k > 1 ? " \\/ " : "") + R(k) + "l[i]==p1";
    return {{"name", "s"},
            {"locations", {"s0", "s1"}},
            {"commands", {"back"}},
            {"transitions",
             {{{"from", "s0"}, {"to", "s1"}, {"guard", any}, {"duration", {1, 1}}},
              {{"from", "s1"}, {"to", "s0"}, {"guard", "su[i]==back"}}}}};
  }

  std::string All(const std::string& op, const std::string& loc, const std::string& idx) const {
    std::string s;
    for (int k = 1; k <= m_; ++k) s += (k > 1 ? op : "") + R(k) + "l[" + idx + "]==" + loc;
    return s;
  }

  std::string Goal(int start) {
    const std::string x = Loc(Int(0, nl_ - 1)), y = Loc(Int(0, nl_ - 1));
    std::string g;
    switch (Int(0, 3)) {
      case 0: g = All(" /\\ ", x, "i+1"); break;
      case 1: g = All(" \\/ ", x, "i+1"); break;
      case 2:
        g = m_ == 2 ? "(r1l[i+1]==" + x + " /\\ r2l[i+1]==" + y + ") \\/ (r2l[i+1]==" + x +
                          " /\\ r1l[i+1]==" + y + ")"
                    : "(" + All(" \\/ ", x, "i+1") + ") /\\ (" + All(" \\/ ", y, "i+1") + ")";
        break;
      default: g = "(" + All(" \\/ ", x, "i+1") + ") /\\ " + (shared_ ? "sl[i+1]==s1" : "true");
    }
    // One copy alone must leave its start: the others may idle, so an ordering that wrongly
    // favoured one copy would cost moves.
    if (twist_ == 1) g = R(odd_) + "l[i+1]==" + Loc((start + 1) % nl_);
    return g;
  }

  Json Plan() {
    Json init = Json::object();
    const int start = Int(0, nl_ - 1);
    for (int k = 1; k <= m_; ++k) {
      init[R(k)] = Loc(start);
      if (helper_) init["h" + std::to_string(k)] = "q0";
    }
    if (shared_) init["s"] = "s0";
    Json episodes = Json::object(), temporal = Json::object(), events = Json::object();
    // Episodes stay where no automatic transition leaves (else most would be impossible).
    std::vector<int> calm;
    for (int l = 0; l < nl_; ++l) {
      bool leaves = false;
      for (const auto& t : specs_) leaves = leaves || (t.from == l && t.automatic);
      if (!leaves) calm.push_back(l);
    }
    const bool per_copy_episodes = !calm.empty() && twist_ != 1 && Chance(0.4);
    const bool per_copy_temporals = twist_ != 1 && Chance(m_ == 2 ? 0.35 : 0.15);
    const std::string ex =
        calm.empty() ? "p0" : Loc(calm[Int(0, static_cast<int>(calm.size()) - 1)]);
    const std::string e1 = Loc(Int(0, nl_ - 1)), e2 = Loc(Int(0, nl_ - 1));
    const int elo = Int(0, 2), ehi = elo + Int(1, 4), tlo = Int(0, 4), thi = tlo + Int(0, 5);
    const bool self_ref = Chance(0.3);
    for (int k = 1; k <= m_; ++k) {
      const std::string K = std::to_string(k), r = R(k);
      if (per_copy_episodes && (twist_ != 3 || k == odd_))
        episodes["Stay" + K] = {{"accepting_constraint", r + "l[i]==" + ex},
                                {"state_constraint", r + "l[i]==" + ex},
                                {"lower_bound", elo},
                                {"upper_bound", ehi}};
      if (per_copy_temporals && (twist_ != 3 || k == odd_)) {
        std::string second = r + "l[i+1]==" + e2;
        if (self_ref) second += " /\\ temporalAcceptConstraint_Traj_Go" + K + "[i]==tempActive";
        temporal["Go" + K] = {
            {"accepting_event1_constraint", r + "l[i]!=" + e1 + " /\\ " + r + "l[i+1]==" + e1},
            {"accepting_event2_constraint", second},
            {"lower_bound", tlo},
            {"upper_bound", thi}};
      }
      if (per_copy_episodes && per_copy_temporals && twist_ != 3 && Chance(0.3) && k == 1)
        events["Tie"] = Json::array({"Stay1.end", "Go1.event1"});
    }
    if (events.contains("Tie"))  // tie every copy alike (or, with a twist, the first only)
      for (int k = 2; k <= m_ && twist_ == 0; ++k)
        events["Tie" + std::to_string(k)] = Json::array(
            {"Stay" + std::to_string(k) + ".end", "Go" + std::to_string(k) + ".event1"});
    if (!calm.empty() && twist_ != 1 && Chance(0.2)) {
      const std::string y = Loc(calm[Int(0, static_cast<int>(calm.size()) - 1)]);
      episodes["Together"] = {{"accepting_constraint", All(" /\\ ", y, "i")},
                              {"state_constraint", All(" /\\ ", y, "i")},
                              {"lower_bound", Int(0, 2)},
                              {"upper_bound", 6}};
    }
    static const char* const kObjectives[] = {"cost", "makespan", "cost_then_makespan"};
    return {{"initial_state", init},
            {"end_state", {{"maintenance_constraint", "true"}, {"goal_constraint", Goal(start)}}},
            {"constraints", {{"episodes", episodes}, {"temporal", temporal}, {"event", events}}},
            {"objective", kObjectives[Int(0, 2)]}};
  }

  std::mt19937 rng_;
  int m_ = 2, nl_ = 2, commands_ = 0, twist_ = 0, odd_ = 1;
  bool helper_ = false, shared_ = false;
  std::vector<TransitionSpec> specs_;
};

struct Outcome {
  std::string status;
  Json value;
  std::string error;
};

Outcome Run(const Domain& d, const StatePlan& sp, SolveOptions o) {
  o.time_limit_ms = 60000;
  o.max_horizon = kMaxHorizon;
  auto r = SolveDocument(d, sp, o);
  if (auto* e = std::get_if<Error>(&r)) return {"error", nullptr, e->ToString()};
  const Json& t = std::get<Json>(r);
  if ((t["status"] == "optimal" || t["status"] == "feasible") && t["verified"] != true)
    return {"error", nullptr, "plan not verified"};
  return {t["status"], t["objective"]["value"], ""};
}

// Seeds [first, first + count). Returns how many problems had an orbit.
int CheckRange(unsigned first, int count) {
  int symmetric = 0;
  for (unsigned seed = first; seed < first + static_cast<unsigned>(count); ++seed) {
    testing::RandomProblem p = SymmetricGenerator(seed).Next();
    Diagnostics diags;
    auto d = LoadDomain(p.domain, diags);
    auto sp = d ? LoadStatePlan(p.state_plan, *d, diags) : std::nullopt;
    if (!sp) {
      ADD_FAILURE() << "seed " << seed << ": does not load: " << testing::AllErrors(diags)
                    << p.Describe();
      continue;
    }
    const int symmetric_before = symmetric;
    if (!FindSymmetries(*d, *sp).empty()) ++symmetric;
    SolveOptions plain;  // the exact engine alone, no symmetry: the reference
    plain.decompose = false;
    plain.static_analysis = false;
    plain.search = "g_first";
    plain.first_plan_ms = 0;
    plain.symmetry = false;
    SolveOptions ordered = plain;
    ordered.symmetry = true;
    SolveOptions fixed = ordered;  // one horizon, the other strategy
    fixed.horizon = kMaxHorizon;
    fixed.search = "tc_first";
    SolveOptions full;  // the default pipeline: first-plan incumbent, split, portfolio
    const std::vector<std::pair<const char*, SolveOptions>> configs = {
        {"plain", plain},
        {"ordered", ordered},
        {"ordered, fixed horizon", fixed},
        {"default", full}};
    std::vector<Outcome> out;
    for (const auto& [name, o] : configs) out.push_back(Run(*d, *sp, o));
    std::cout << "seed " << seed << ": " << (symmetric_before < symmetric ? "orbit" : "none")
              << ", " << out[0].status << " " << out[0].value.dump() << "\n";
    if (std::getenv("CTB_SYM_DUMP")) std::cout << p.Describe() << "\n";
    for (std::size_t i = 0; i < out.size(); ++i) {
      EXPECT_NE(out[i].status, "error")
          << "seed " << seed << " " << configs[i].first << ": " << out[i].error << "\n"
          << p.Describe();
      EXPECT_TRUE(out[i].status == "optimal" || out[i].status == "infeasible")
          << "seed " << seed << " " << configs[i].first << " undecided: " << out[i].status;
      if (i == 0) continue;
      EXPECT_EQ(out[i].status, out[0].status)
          << "seed " << seed << ": " << configs[i].first << " vs plain\n"
          << p.Describe();
      if (out[i].status == "optimal" && out[0].status == "optimal")
        EXPECT_EQ(out[i].value, out[0].value)
            << "seed " << seed << ": " << configs[i].first << " vs plain\n"
            << p.Describe();
    }
  }
  return symmetric;
}

// 12 problems (three shards of 20 until session 42, two until session 43, one until later that
// session: the suite has to fit its 15 minutes), about three in four symmetric; the others check that nothing is ordered
// when a twist breaks the symmetry (with the state plan's checks left out of the detection, the
// twists of seeds 9 and others come out wrong).
TEST(SymmetryDifferential, Seeds0To11) { EXPECT_GE(CheckRange(0, 12), 6); }

}  // namespace
}  // namespace symmetry_differential_test
}  // namespace ctb
