// PDDL import through the core (issue 31 item 2, issue 32 item 5): the same for the CLI, HTTP
// (POST /domains/import-pddl) and gRPC (ImportPddl).
#include <algorithm>

#include "app/core.h"
#include "app/core_impl.h"
#include "interchange/pddl/import.h"

namespace ctb::app {

namespace {

constexpr std::size_t kMaxGroundActions = 20000;

// The byte offset of a 1-based line and column in `text` (nullopt when either is unknown).
std::optional<std::size_t> OffsetOf(const std::string& text, int line, int column) {
  if (line <= 0) return std::nullopt;
  std::size_t at = 0;
  for (int l = 1; l < line; ++l) {
    at = text.find('\n', at);
    if (at == std::string::npos) return std::nullopt;
    ++at;
  }
  return std::min(text.size(), at + static_cast<std::size_t>(std::max(column, 1) - 1));
}

const char* kDomainFile = "domain.pddl";
const char* kProblemFile = "problem.pddl";

Error ImportFailed(const std::vector<pddl::Issue>& issues, const PddlImportCall& call) {
  Error e{ErrorCode::kInvalidInput, "the PDDL could not be imported: " + issues.front().ToString(), {}};
  for (const auto& i : issues) {
    const bool in_problem = i.file == kProblemFile;
    e.details.push_back({in_problem ? "/problem" : "/domain",
                         OffsetOf(in_problem ? call.problem : call.domain, i.line, i.column), i.ToString()});
  }
  return e;
}

Json IssueJson(const pddl::Issue& i) {
  Json j = {{"line", i.line}, {"column", i.column}, {"message", i.message}};
  if (!i.action.empty()) j["action"] = i.action;
  if (!i.file.empty()) j["file"] = i.file;
  return j;
}

}  // namespace

Json PddlImportAnswer::ToJson() const {
  return {{"action_model", action_model}, {"state_plan", state_plan}, {"warnings", warnings},
          {"ground_actions", ground_actions}, {"actions", actions}, {"stored", stored}};
}

std::variant<PddlImportAnswer, Error> Core::ImportPddl(const PddlImportCall& call) {
  if (call.domain.empty()) return Bad("missing the PDDL domain text", "/domain");
  pddl::ImportOptions options;
  options.name = call.name;
  options.max_ground_actions =
      static_cast<std::size_t>(std::clamp<long>(impl_->cfg.budget.max_transitions, 1, kMaxGroundActions));
  std::optional<pddl::Source> problem;
  if (!call.problem.empty()) problem = pddl::Source{kProblemFile, call.problem};
  auto imported = pddl::ImportPddl({kDomainFile, call.domain}, problem, options);
  if (auto* issues = std::get_if<std::vector<pddl::Issue>>(&imported)) return ImportFailed(*issues, call);
  auto& im = std::get<pddl::Imported>(imported);
  // Held to the request budget like any inline model.
  DomainRef ref;
  ref.action_model = im.domain;
  auto loaded = impl_->ResolveDomain(ref);
  if (auto* e = std::get_if<Error>(&loaded)) return *e;
  PddlImportAnswer a;
  a.action_model = std::move(im.domain);
  a.state_plan = std::move(im.state_plan);
  for (const auto& w : im.warnings) a.warnings.push_back(IssueJson(w));
  a.ground_actions = im.ground_actions;
  for (const auto& p : im.actions)
    a.actions.push_back({{"command", p.command}, {"automaton", p.automaton}, {"pddl", p.pddl}, {"durative", p.durative}});
  if (call.store) {
    auto created = CreateDomain(a.action_model);
    if (auto* e = std::get_if<Error>(&created)) return *e;
    a.stored = true;
  }
  return a;
}

}  // namespace ctb::app
