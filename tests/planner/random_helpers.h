// Small random problems of the assembly kind for the workload bound (analyze/workload.h):
// helpers (arms) that take an item, hold it and drop it somewhere, then come back; items that
// move only while a helper holds or drops them. Random durations, costs, sizes, and variations
// the bound must not be fooled by: an item that can also move by itself (no helper), an item
// whose pick needs a second helper, a helper location two items read, take-and-hold in one step,
// a push that moves an item several positions in one visit of the helper, an item that rides
// along with another in the same arm,
// helpers the goal leaves free, a pick that waits for another item to leave. Deterministic for
// a seed.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "planner/model/json_io.h"
#include "random_problem.h"

namespace ctb::testing {

struct HelperShape {
  int max_helpers = 2, max_items = 2, max_positions = 3;
  int max_duration = 2;
  double direct = 0.3;  // chance that a pick goes home -> hold in one command
  double push = 0.3;    // chance that helpers can also push an item along several positions
  double ride = 0.3;    // chance that an item also rides along with item 0 (one visit, two items)
};

class HelperProblemGenerator {
 public:
  explicit HelperProblemGenerator(unsigned seed, HelperShape shape = {}) : rng_(seed), shape_(shape) {}

  RandomProblem Next() {
    nh_ = Int(1, shape_.max_helpers);
    ni_ = Int(1, shape_.max_items);
    np_ = Int(2, shape_.max_positions);
    direct_.assign(ni_, false);
    push_.assign(ni_, false);
    for (int x = 0; x < ni_; ++x) {
      direct_[x] = Chance(shape_.direct);  // home -> hold in one command
      push_[x] = Chance(shape_.push);      // a helper in push<x> slides item x along, step by step
    }
    Json automata = Json::array();
    for (int k = 0; k < nh_; ++k) automata.push_back(Helper(k));
    for (int x = 0; x < ni_; ++x) automata.push_back(Item(x));
    RandomProblem p;
    p.domain = {{"name", "helpers"}, {"description", "generated"}, {"automata", automata}};
    p.state_plan = Plan();
    return p;
  }

 private:
  int Int(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  bool Chance(double p) { return std::bernoulli_distribution(p)(rng_); }
  static std::string H(int k) { return "h" + std::to_string(k); }
  static std::string I(int x) { return "i" + std::to_string(x); }
  static std::string P(int q) { return "p" + std::to_string(q); }
  static std::string In(int k) { return "in" + std::to_string(k); }
  static std::string Take(int x) { return "take" + std::to_string(x); }
  static std::string Hold(int x) { return "hold" + std::to_string(x); }
  static std::string Drop(int x, int q) { return "drop" + std::to_string(x) + "at" + std::to_string(q); }

  Json Timed(Json t, int lo) {
    if (lo > 0 || Chance(0.2)) t["duration"] = {lo, nullptr};
    if (Chance(0.3)) t["cost"] = Int(1, 2);
    return t;
  }

  Json Helper(int k) {
    Json locs = Json::array({"home"}), cmds = Json::array(), ts = Json::array();
    const std::string u = H(k) + "u[i]==";
    for (int x = 0; x < ni_; ++x) {
      std::string free;  // the item is in no helper
      for (int j = 0; j < nh_; ++j) free += " /\\ " + I(x) + "l[i]!=" + In(j);
      if (ni_ > 1 && Chance(0.3))  // waits until another item has left a position
        free += " /\\ " + I((x + 1) % ni_) + "l[i]!=" + P(Int(0, np_ - 1));
      cmds.push_back("pick" + std::to_string(x));
      if (!direct_[x]) {
        locs.push_back(Take(x));
        ts.push_back(Timed({{"from", "home"}, {"to", Take(x)}, {"guard", u + "pick" + std::to_string(x) + free}}, Int(0, 1)));
        ts.push_back(Timed({{"from", Take(x)}, {"to", Hold(x)}}, Int(1, shape_.max_duration)));
      } else {
        ts.push_back(Timed({{"from", "home"}, {"to", Hold(x)}, {"guard", u + "pick" + std::to_string(x) + free}},
                           Int(0, shape_.max_duration)));
      }
      locs.push_back(Hold(x));
      for (int q = 0; q < np_; ++q) {
        const std::string c = "put" + std::to_string(x) + "at" + std::to_string(q);
        cmds.push_back(c);
        locs.push_back(Drop(x, q));
        ts.push_back(Timed({{"from", Hold(x)}, {"to", Drop(x, q)}, {"guard", u + c}}, Int(0, 1)));
        ts.push_back(Timed({{"from", Drop(x, q)}, {"to", "home"}}, Int(1, shape_.max_duration)));
      }
      if (push_[x]) {  // one visit to push<x> may move x by several positions
        const std::string c = "push" + std::to_string(x);
        cmds.push_back(c);
        locs.push_back(c);
        ts.push_back(Timed({{"from", "home"}, {"to", c}, {"guard", u + c}}, Int(0, 1)));
        ts.push_back(Timed({{"from", c}, {"to", "home"}}, Int(1, shape_.max_duration)));
      }
    }
    return {{"name", H(k)}, {"locations", locs}, {"commands", cmds}, {"transitions", ts}};
  }

  Json Item(int x) {
    Json locs = Json::array(), ts = Json::array();
    for (int q = 0; q < np_; ++q) locs.push_back(P(q));
    for (int k = 0; k < nh_; ++k) locs.push_back(In(k));
    // Sometimes the pick also needs another helper somewhere, or reads a location that another
    // item's pick reads too.
    std::string extra;
    if (nh_ > 1 && Chance(0.15)) extra = " /\\ " + H(Int(0, nh_ - 1)) + "l[i]==home";
    if (ni_ > 1 && Chance(0.15)) extra = " \\/ " + H(0) + "l[i]==" + Hold((x + 1) % ni_);
    for (int k = 0; k < nh_; ++k)
      for (int q = 0; q < np_; ++q) {
        std::string take = H(k) + "l[i]==" + Hold(x);
        if (!extra.empty() && Chance(0.5)) take = "(" + take + extra + ")";
        ts.push_back({{"from", P(q)}, {"to", In(k)}, {"guard", take}});
        ts.push_back({{"from", In(k)}, {"to", P(q)}, {"guard", H(k) + "l[i]==" + Drop(x, q)}});
      }
    if (x > 0 && Chance(shape_.ride))  // lifted and dropped with item 0, in the same arm
      for (int k = 0; k < nh_; ++k)
        for (int q = 0; q < np_; ++q) {
          ts.push_back({{"from", P(q)}, {"to", In(k)}, {"guard", H(k) + "l[i]==" + Hold(0)}});
          ts.push_back({{"from", In(k)}, {"to", P(q)}, {"guard", H(k) + "l[i]==" + Drop(0, q)}});
        }
    if (push_[x])
      for (int k = 0; k < nh_; ++k)
        for (int q = 0; q + 1 < np_; ++q)
          ts.push_back({{"from", P(q)}, {"to", P(q + 1)}, {"guard", H(k) + "l[i]==push" + std::to_string(x)}});
    if (Chance(0.2))  // a slow way of its own, no helper
      ts.push_back({{"from", P(0)}, {"to", P(np_ - 1)}, {"duration", {Int(2, 5), nullptr}}});
    return {{"name", I(x)}, {"locations", locs}, {"commands", Json::array()}, {"transitions", ts}};
  }

  Json Plan() {
    Json init = Json::object();
    std::string goal;
    for (int k = 0; k < nh_; ++k) {
      init[H(k)] = "home";
      if (Chance(0.8)) goal += (goal.empty() ? "" : " /\\ ") + H(k) + "l[i+1]==home";
    }
    for (int x = 0; x < ni_; ++x) {
      const int from = Int(0, np_ - 1);
      int to = Int(0, np_ - 1);
      if (x == 0 && to == from) to = (from + 1) % np_;  // some work to do
      init[I(x)] = P(from);
      goal += (goal.empty() ? "" : " /\\ ") + I(x) + "l[i+1]==" + P(to);
    }
    static const char* const kObjectives[] = {"cost", "makespan", "cost_then_makespan"};
    return {{"initial_state", init},
            {"end_state", {{"maintenance_constraint", "true"}, {"goal_constraint", goal}}},
            {"objective", kObjectives[Int(0, 2)]}};
  }

  std::mt19937 rng_;
  HelperShape shape_;
  int nh_ = 1, ni_ = 1, np_ = 2;
  std::vector<bool> direct_, push_;
};

}  // namespace ctb::testing
