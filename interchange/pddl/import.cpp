// ImportPddl: read, analyze, ground, write, and check that the result loads.
#include "interchange/pddl/import.h"

#include "interchange/pddl/internal/writer.h"
#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb::pddl {

std::string Issue::ToString() const {
  std::string s = file.empty() ? std::string() : file + ":";
  if (line > 0) s += std::to_string(line) + ":" + std::to_string(column) + ":";
  if (!s.empty()) s += " ";
  if (!action.empty()) s += "action '" + action + "': ";
  return s + message;
}

namespace {

// The result must load as the contract says; an Issue per diagnostic otherwise (a bug of the
// import, or a limit of the format such as a guard longer than the expression limit).
bool CheckLoads(const Written& w, const std::string& file, std::vector<Issue>& issues) {
  Diagnostics diags;
  auto dom = LoadDomain(w.domain, diags);
  if (dom && !w.state_plan.is_null()) LoadStatePlan(w.state_plan, *dom, diags);
  for (const auto& e : diags.errors())
    issues.push_back(Issue{file, 0, 0, "", "the imported model does not load: " + e.ToString()});
  return diags.ok();
}

}  // namespace

std::variant<Imported, std::vector<Issue>> ImportPddl(const Source& domain,
                                                      const std::optional<Source>& problem,
                                                      const ImportOptions& options) {
  std::vector<Issue> issues;
  Imported out;
  auto de = ReadSExpr(domain.text, domain.file, issues);
  std::optional<DomainAst> d;
  if (de) d = ReadDomain(*de, domain.file, issues);
  std::optional<ProblemAst> p;
  if (problem) {
    auto pe = ReadSExpr(problem->text, problem->file, issues);
    if (pe) p = ReadProblem(*pe, problem->file, issues);
    if (p && d && !p->domain_name.empty() && p->domain_name != d->name)
      out.warnings.push_back(
          Issue{p->file, p->domain_pos.line, p->domain_pos.column, "",
                "the problem is for domain '" + p->domain_name + "', not '" + d->name + "'"});
  }
  if (!d || (problem && !p)) return issues;
  auto sv = AnalyzeStateVars(*d, p ? &*p : nullptr, issues, out.warnings);
  if (!sv) return issues;
  auto g = Ground(*d, *sv, p ? &*p : nullptr, options, issues, out.warnings);
  if (!g) return issues;
  if (p && p->goal && !options.keep_irrelevant) out.irrelevant_actions = DropIrrelevant(*sv, *p->goal, *g);
  auto w = WriteModel(*d, *sv, *g, p ? &*p : nullptr, options, issues);
  if (!w || !CheckLoads(*w, domain.file, issues)) return issues;
  out.warnings.insert(out.warnings.end(), w->warnings.begin(), w->warnings.end());
  out.actions = std::move(w->actions);
  out.domain = std::move(w->domain);
  out.state_plan = std::move(w->state_plan);
  out.ground_actions = g->actions.size();
  return out;
}

}  // namespace ctb::pddl
