// Small random problems of the search-and-rescue kind for the assignment bound on cost
// (analyze/assignment_cost.h): agents of random costs that can each serve several clauses of the
// goal ("person p rescued by agent a or agent b"), a gate that opens only while some agent stands
// at its spot, and ways to the persons that need the gate open. Variations the bound must not be
// fooled by: a clause that shares a fact with another (one agent in one place serves both), an
// agent that starts at the gate's spot (the help costs nothing), a way round the gate (no help
// needed), a spot that is itself a person's place, zero-cost moves, an episode that makes an agent
// visit a place, and persons left to chance. Deterministic for a seed.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "planner/model/json_io.h"
#include "random_problem.h"

namespace ctb::testing {

struct TeamShape {
  int max_agents = 3, max_persons = 2;
  int max_duration = 2;
  bool tiny = false;  // every way at most one step long (plans of 3 events), for the enumeration
};

class TeamProblemGenerator {
 public:
  explicit TeamProblemGenerator(unsigned seed, TeamShape shape = {}) : rng_(seed), shape_(shape) {}

  RandomProblem Next() {
    na_ = Int(2, shape_.max_agents);
    np_ = Int(1, shape_.max_persons);
    around_ = Chance(0.25);
    Json automata = Json::array();
    for (int a = 0; a < na_; ++a) automata.push_back(Agent(a));
    automata.push_back(Gate());
    RandomProblem p;
    p.domain = {{"name", "teams"}, {"description", "generated"}, {"automata", automata}};
    p.state_plan = Plan();
    return p;
  }

 private:
  int Int(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  bool Chance(double p) { return std::bernoulli_distribution(p)(rng_); }
  static std::string A(int a) { return "a" + std::to_string(a); }
  static std::string G(int p) { return "g" + std::to_string(p); }

  Json Move(const std::string& from, const std::string& to, const std::string& guard, int cost) {
    Json t = {{"from", from}, {"to", to}, {"cost", cost}};
    if (!guard.empty()) t["guard"] = guard;
    const int lo = Int(0, shape_.max_duration);
    if (lo > 0) t["duration"] = {lo, nullptr};
    return t;
  }

  Json Agent(int a) {
    Json locs = Json::array({"s", "spot", "m"}), cmds = Json::array({"toSpot", "toM"});
    Json ts = Json::array();
    const int rate = Int(0, 3);  // the agent's running cost
    const std::string open = "gatel[i]==open", u = A(a) + "u[i]==";
    ts.push_back(Move("s", "spot", u + "toSpot", Int(0, 2)));
    for (int p = 0; p < np_; ++p) {
      locs.push_back(G(p));
      cmds.push_back("to" + G(p));
      const int leg = rate * Int(1, 3);
      ts.push_back(Move("s", G(p), open + " /\\ " + u + "to" + G(p), leg));
      if (!shape_.tiny || Chance(0.5))
        ts.push_back(Move("spot", G(p), open + " /\\ " + u + "to" + G(p), leg + Int(0, 1)));
      if (Chance(0.3)) ts.push_back(Move(G(p), "spot", u + "toSpot", Int(0, 1)));
    }
    if (around_) {  // the long way, no gate
      ts.push_back(Move("s", "m", u + "toM", rate));
      for (int p = 0; p < np_; ++p) ts.push_back(Move("m", G(p), u + "to" + G(p), rate * Int(1, 3)));
    }
    return {{"name", A(a)}, {"locations", locs}, {"commands", cmds}, {"transitions", ts}};
  }

  Json Gate() {
    std::string any;
    for (int a = 0; a < na_; ++a) any += (a ? " \\/ " : "") + A(a) + "l[i]==spot";
    if (Chance(0.2)) any += " \\/ " + A(0) + "l[i]==" + G(0);  // a person's place opens it too
    return {{"name", "gate"},
            {"locations", {"closed", "open"}},
            {"commands", Json::array()},
            {"transitions", {Move("closed", "open", any, Int(0, 2))}}};
  }

  Json Plan() {
    Json init = {{"gate", "closed"}};
    for (int a = 0; a < na_; ++a) init[A(a)] = Chance(0.15) ? "spot" : "s";
    std::string goal;
    for (int p = 0; p < np_; ++p) {
      std::string clause;
      for (int a = 0; a < na_; ++a)
        if (Chance(0.75) || (a == na_ - 1 && clause.empty()))
          clause += (clause.empty() ? "" : " \\/ ") + A(a) + "l[i+1]==" + G(p);
      if (p > 0 && Chance(0.2)) clause += " \\/ " + A(0) + "l[i+1]==" + G(0);  // shared fact
      goal += (goal.empty() ? "(" : " /\\ (") + clause + ")";
    }
    Json episodes = Json::object();
    if (!shape_.tiny && Chance(0.2))
      episodes["Visit"] = {{"accepting_constraint", A(Int(0, na_ - 1)) + "l[i]==spot"},
                           {"lower_bound", 0}, {"upper_bound", 20}};
    static const char* const kObjectives[] = {"cost", "cost", "cost_then_makespan", "makespan"};
    return {{"initial_state", init},
            {"end_state", {{"maintenance_constraint", "true"}, {"goal_constraint", goal}}},
            {"constraints", {{"episodes", episodes}, {"temporal", Json::object()}, {"event", Json::object()}}},
            {"objective", kObjectives[Int(0, 3)]}};
  }

  std::mt19937 rng_;
  TeamShape shape_;
  int na_ = 2, np_ = 1;
  bool around_ = false;
};

}  // namespace ctb::testing
