// Fuzz target: the state-plan loader (planner/model/state_plan.h). The first byte picks the
// domain ('0' presentation, '1' search_rescue, '2' assembly, '3' the presentation team with
// contingent durations; any other byte by its value modulo 4); the rest is a state plan as
// /solve receives it: parsed strictly, checked against the budget, loaded. Checked: every error
// carries a JSON pointer; a loaded plan serialises (StatePlanToJson) to a document that loads
// again to the same JSON.
#include <cstdint>

#include "app/budget.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ctb;
  static const Domain domains[] = {
      fuzz::LoadShippedDomain("config/domains/presentation.json"),
      fuzz::LoadShippedDomain("config/domains/search_rescue.json"),
      fuzz::LoadShippedDomain("config/domains/assembly.json"),
      fuzz::LoadShippedDomain("config/uncertain/presentation.json"),
  };
  if (size == 0) return 0;
  const Domain& dom = domains[data[0] % 4];
  Diagnostics pd;
  std::optional<Json> doc = ParseJsonStrict(fuzz::Text(data + 1, size - 1), pd);
  fuzz::CheckDiagnostics(pd);
  if (!doc) return 0;
  if (app::CheckStatePlan(*doc, app::ModelBudget{}, "/state_plan")) return 0;

  Diagnostics diags;
  std::optional<StatePlan> sp = LoadStatePlan(*doc, dom, diags);
  fuzz::CheckDiagnostics(diags);
  if (!sp) {
    if (diags.ok()) fuzz::Fail("LoadStatePlan failed without an error");
    return 0;
  }
  const Json out = StatePlanToJson(*sp, dom);
  Diagnostics d2;
  std::optional<StatePlan> again = LoadStatePlan(out, dom, d2);
  if (!again) {
    for (const auto& e : d2.errors()) std::fprintf(stderr, "%s\n", e.ToString().c_str());
    fuzz::Fail("StatePlanToJson gave a document that does not load");
  }
  if (StatePlanToJson(*again, dom) != out) fuzz::Fail("StatePlanToJson is not stable under reloading");
  return 0;
}
