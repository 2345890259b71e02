// The model writer's class (internal to ctb_pddl, shared by writer.cpp, which compiles the ground
// actions, and writer_model.cpp, which adds timed initial literals, over-all protections, the "run"
// automata, the goal and the JSON). Not thread-safe: one Writer per import.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "interchange/pddl/internal/writer.h"
#include "planner/expr/expr.h"

namespace ctb::pddl::writer_impl {

std::string Join(const std::vector<std::string>& parts, const std::string& sep);
std::vector<std::string> Split(const std::string& s);

// Makes names unique within one namespace: "x", then "x_2", "x_3", ...
class NameSet {
 public:
  std::string Take(const std::string& base) {
    std::string n = base;
    for (int k = 2; taken_.count(n); ++k) n = base + "_" + std::to_string(k);
    taken_.insert(n);
    return n;
  }
  void Reserve(const std::string& n) { taken_.insert(n); }
  bool Has(const std::string& n) const { return taken_.count(n) > 0; }

 private:
  std::set<std::string> taken_;
};

class Writer {
 public:
  Writer(const DomainAst& d, const StateVars& sv, const Grounded& g, const ProblemAst* p,
         const ImportOptions& o, std::vector<Issue>& issues)
      : d_(d), sv_(sv), g_(g), p_(p), o_(o), issues_(issues) {}

  std::optional<Written> Run();

 private:
  // Beyond this many characters a transition's over-all protection is written coarsely.
  static constexpr std::size_t kExactProtection = 3000;
  // Beyond this many atoms (either way) a read is written coarsely (Expand).
  static constexpr std::size_t kListedReads = 24;
  // The expression language's limit (contract section 4).
  static constexpr std::size_t kMaxExpressionChars = kMaxExprLength;

  struct Loc {
    std::string name;
    std::string value;  // the value the variable has while here
    bool step = false;
  };
  struct Trans {
    int var = -1, from = -1, to = -1;
    std::vector<std::string> guard;
    std::optional<std::pair<double, std::optional<double>>> duration;
    int cost = 0;
    int action = -1;     // -1: a timed initial literal
    bool start = false;  // the action's start (else its end)
    int copy_of = -1;    // a run automaton's copy of this transition
  };
  // A ground action's plan: per changed variable its source values and their step locations.
  struct Plan {
    std::vector<const VarUse*> changed, at_end, read_start, read_end;
    std::map<const VarUse*, std::vector<std::string>> sources;
    std::map<const VarUse*, std::set<std::string>> idle;  // sources it keeps its value from
  };

  int VarIndex(const VarKey& k) const {
    auto it = var_index_.find(k);
    return it == var_index_.end() ? -1 : it->second;
  }
  void NameAutomata();
  std::string ValueName(const VarKey& k, const std::string& value) const;
  void BaseLocations();
  int LocOf(int var, const std::string& value, const std::string& step_name);
  // The variable has (has not) the value: its locations with it, or only its base locations (where
  // no action runs, as the goal also requires).
  std::string Accept(int var, const std::string& value, const std::string& index,
                     bool base_only = false) const;
  std::string Refuse(int var, const std::string& value, const std::string& index,
                     bool base_only = false) const;
  std::string Expand(const std::string& atom);
  std::string InLocs(int var, const std::vector<int>& locs, const std::string& index) const;
  void Command(int var, std::size_t action);
  std::optional<Plan> MakePlan(std::size_t x);
  static bool IdleSource(const VarUse& u, const std::string& s);
  std::string NotAllIdle(const Plan& plan, const VarUse* u, const std::string& source);
  std::vector<std::string> Reads(const VarUse& u, int first, int last, std::size_t x);
  void WriteAction(std::size_t x);
  void WarnRepeatedStretch(const VarUse& u, std::size_t x);
  void Timelines();
  void Protect();
  void WriteProtections();
  void ProtectPartners(const std::vector<std::string>& text);
  std::string ProtectText(const std::map<int, std::set<int>>& running, bool coarse) const;
  void AddRun(int m);
  void RunTransitions(int m);
  double Resolution();
  Json Duration(double v) const;
  Json Automata();
  std::string Unfinished(std::size_t budget);
  std::optional<std::string> GoalText(const Goal& goal);

  const DomainAst& d_;
  const StateVars& sv_;
  const Grounded& g_;
  const ProblemAst* p_;
  const ImportOptions& o_;
  std::vector<Issue>& issues_;
  std::map<VarKey, int> var_index_;
  // Per automaton: the state variables' (indexed as g_.variables), then the "run" automata.
  std::vector<std::string> automaton_;
  std::vector<std::vector<Loc>> locs_;
  std::vector<NameSet> loc_names_;
  std::vector<std::vector<std::string>> commands_;
  std::vector<std::string> cmd_;                // per ground action
  std::vector<int> timing_;                     // per ground action: var or -1
  std::vector<std::vector<int>> timing_steps_;  // per ground action
  std::vector<std::vector<std::pair<int, const VarUse*>>> over_all_;  // per action: protected
  std::vector<std::set<int>> touches_;  // per action: variables changed
  std::vector<Trans> trans_;
  std::vector<int> run_;  // per automaton: its "run" automaton (busy while it
                          // times an action), -1
  std::vector<std::map<int, std::set<int>>> protect_;  // per transition: timing automaton -> steps
  // Per (action, variable, at its start): the locations the variable may be in when that event
  // happens (its sources at the start, its steps at the end).
  std::map<std::tuple<int, int, bool>, std::vector<int>> event_sources_;
  NameSet automaton_names_;
  int coarse_ = 0;        // transitions with coarse protections
  int coarse_reads_ = 0;  // reads written as "at rest with the value" (Expand)
  double resolution_ = 1;
  std::vector<Issue> warnings_;
  std::set<int> warned_stretch_;  // timed atoms warned about by WarnRepeatedStretch
};

}  // namespace ctb::pddl::writer_impl
