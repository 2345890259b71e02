// Unsatisfiable cores: one model with a literal per part, checks under subsets of the literals,
// a deletion filter over the core.
#include "planner/model/elapsed.h"
#include "planner/smt/z3_core.h"

#include <algorithm>
#include <chrono>

#include "planner/smt/z3_model.h"
#include "planner/smt/z3_watchdog.h"

namespace ctb::smt {

namespace {

using Clock = std::chrono::steady_clock;

// The literals of the model: parts not listed always hold (the literal `true`).
PartLiterals Literals(Model& m, const std::vector<CorePart>& parts, Exprs& listed) {
  PartLiterals lit{m.True(), m.True(), Exprs(m.sp.episodes.size(), m.True()),
                   Exprs(m.sp.temporals.size(), m.True()), Exprs(m.sp.events.size(), m.True())};
  for (std::size_t i = 0; i < parts.size(); ++i) {
    z3::expr b = m.Bool("PART_" + std::to_string(i));
    listed.push_back(b);
    const CorePart& p = parts[i];
    switch (p.kind) {
      case CorePart::Kind::kGoal:
        lit.goal = b;
        break;
      case CorePart::Kind::kMaintenance:
        lit.maintenance = b;
        break;
      case CorePart::Kind::kEpisode:
        lit.episodes.at(p.index) = b;
        break;
      case CorePart::Kind::kTemporal:
        lit.temporals.at(p.index) = b;
        break;
      case CorePart::Kind::kEvent:
        lit.events.at(p.index) = b;
        break;
    }
  }
  return lit;
}

class CoreSearch {
 public:
  CoreSearch(Model& m, z3::solver& s, const Exprs& lits, const CoreOptions& o, CoreResult& r)
      : m_(m), s_(s), lits_(lits), o_(o), r_(r) {}

  void Run() {
    std::vector<int> all;
    for (int i = 0; i < static_cast<int>(lits_.size()); ++i) all.push_back(i);
    std::vector<int> core = all;
    r_.feasible = o_.feasible;
    const z3::check_result first = o_.known_infeasible ? z3::unsat : Check(all, &core);
    if (first == z3::sat) {
      r_.status = CoreResult::Status::kFeasible;
      return;
    }
    if (first != z3::unsat) {
      r_.status = CoreResult::Status::kUnknown;
      return;
    }
    // Deletion filter: each part of the core, left out; the rest's own core replaces the core.
    r_.minimal = true;
    for (int p : std::vector<int>(core)) {
      if (!std::binary_search(core.begin(), core.end(), p)) continue;  // gone with a smaller core
      std::vector<int> rest;
      for (int x : core)
        if (x != p) rest.push_back(x);
      std::vector<int> smaller;
      const z3::check_result c = Check(rest, &smaller);
      if (c == z3::unsat) {
        core = smaller;
      } else if (c == z3::sat) {
        if (rest.size() >= r_.consistent.size()) r_.consistent = rest;
      } else {
        r_.minimal = false;
      }
    }
    r_.core = core;
    r_.status = CoreResult::Status::kInfeasible;
  }

 private:
  // Whether the parts `on` (sorted) have a plan; when not, their core (sorted) goes to `core`.
  z3::check_result Check(const std::vector<int>& on, std::vector<int>* core) {
    for (const auto& f : r_.feasible)
      if (std::includes(f.begin(), f.end(), on.begin(), on.end())) return z3::sat;
    if (o_.known_core) {
      if (auto k = o_.known_core(on)) {
        *core = *k;
        std::sort(core->begin(), core->end());
        return z3::unsat;
      }
    }
    if (o_.limits.cancel && o_.limits.cancel->load()) return z3::unknown;
    z3::expr_vector assume(m_.z);
    for (int i : on) assume.push_back(lits_[i]);
    ++r_.checks;
    const z3::check_result c = s_.check(assume);
    if (c == z3::sat) {
      r_.feasible.push_back(on);
    } else if (c == z3::unsat) {
      core->clear();
      z3::expr_vector uc = s_.unsat_core();
      for (unsigned k = 0; k < uc.size(); ++k)
        for (int i : on)
          if (z3::eq(uc[k], lits_[i])) core->push_back(i);
      std::sort(core->begin(), core->end());
      core->erase(std::unique(core->begin(), core->end()), core->end());
    }
    return c;
  }

  Model& m_;
  z3::solver& s_;
  const Exprs& lits_;
  const CoreOptions& o_;
  CoreResult& r_;
};

}  // namespace

CoreResult FindCoreWithZ3(const ModelSpec& spec, const std::vector<CorePart>& parts,
                          const CoreOptions& options) {
  CoreResult r;
  const Clock::time_point t0 = Clock::now();
  if (!spec.d || !spec.sp || !spec.info) {
    r.error = "the z3 engine needs the problem, not only a model text";
    return r;
  }
  try {
    z3::context z;
    Model m(z, spec);
    Exprs lits;
    m.parts = Literals(m, parts, lits);
    AddAutomata(m);
    AddStatePlan(m);
    AddObjective(m);
    z3::solver s(z);
    s.add(m.constraints);
    // Cores come from the assumptions; z3's own core minimisation is left off (the deletion
    // filter below proves minimality with plans).
    r.build_ms = MsSince(t0);
    Watchdog dog(z, t0 + std::chrono::milliseconds(std::max(1L, options.limits.time_limit_ms)),
                 options.limits.cancel);
    CoreSearch(m, s, lits, options, r).Run();
    if (dog.Fired() && r.status != CoreResult::Status::kInfeasible)
      r.status = CoreResult::Status::kUnknown;
  } catch (const z3::exception& ex) {
    r = CoreResult{};
    r.error = std::string("z3 failed: ") + ex.msg();
  } catch (const std::exception& ex) {
    r = CoreResult{};
    r.error = std::string("z3 engine failed: ") + ex.what();
  }
  r.elapsed_ms = MsSince(t0);
  return r;
}

}  // namespace ctb::smt
