// Fuzz target: the replanning request (planner/replan: ReadReplanRequest, CheckReplanRequest and
// what Replan decides before any solve). The first byte picks the problem ('0' presentation
// test1_cot, '1' search_rescue test2, '2' the presentation team with contingent durations and
// on_ten_then_off; any other byte by its value modulo 3); the rest is a POST /replan body
// (`now`, `executed`, `observed`, `blocked`, `trajectory`, `options.keep`). Checked: every error
// carries a JSON pointer; a request that passes the check builds a situation on which the
// prechecks (history broke a constraint, goal cut off) and the history bounds run without a fault.
#include <cstdint>

#include "planner/replan/precheck.h"
#include "planner/replan/replan.h"
#include "planner/replan/situation.h"
#include "tests/fuzz/fuzz_util.h"

namespace {

struct Problem {
  ctb::Domain domain;
  ctb::StatePlan plan;
};

Problem Load(const std::string& domain, const std::string& plan) {
  Problem p{ctb::fuzz::LoadShippedDomain(domain), {}};
  p.plan = ctb::fuzz::LoadShippedStatePlan(plan, p.domain);
  return p;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ctb;
  static const Problem problems[] = {
      Load("config/domains/presentation.json", "config/examples/presentation/test1_cot.json"),
      Load("config/domains/search_rescue.json", "config/examples/search_rescue/test2.json"),
      Load("config/uncertain/presentation.json", "config/uncertain/on_ten_then_off.json"),
  };
  if (size == 0) return 0;
  const Problem& p = problems[data[0] % 3];
  Diagnostics pd;
  std::optional<Json> body = ParseJsonStrict(fuzz::Text(data + 1, size - 1), pd);
  if (!body) return 0;

  ReplanRequest req;
  Keep keep = Keep::kNone;
  if (std::optional<Error> e = ReadReplanRequest(*body, req, &keep)) {
    fuzz::CheckError(*e);
    return 0;
  }
  if (std::optional<Error> e = CheckReplanRequest(p.domain, p.plan, req)) {
    fuzz::CheckError(*e);
    return 0;
  }
  // What Replan does next, short of solving.
  replan::Situation s;
  if (std::optional<Error> e = replan::BuildSituation(p.domain, p.plan, req, keep, s)) {
    fuzz::CheckError(*e);
    if (keep == Keep::kNone) fuzz::Fail("BuildSituation refused what CheckReplanRequest accepted");
    return 0;
  }
  (void)replan::BrokenByHistory(p.plan, s);
  (void)replan::GoalCutOff(p.domain, p.plan, s);
  (void)replan::HistoryBounds(p.plan, s);
  return 0;
}
