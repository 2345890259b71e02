// Fuzz target: the domain loader with templates (planner/model/domain.h, templates.h). The input
// is an action model as POST /domains receives it: parsed strictly, checked against the request
// budget (app/budget.h), then loaded (templates expanded first). Checked: every error carries a
// JSON pointer; a loaded domain serialises (DomainToJson) to a document that loads again and
// serialises to the same JSON.
#include <cstdint>

#include "app/budget.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ctb;
  Diagnostics pd;
  std::optional<Json> doc = ParseJsonStrict(fuzz::Text(data, size), pd);
  fuzz::CheckDiagnostics(pd);
  if (!doc) {
    if (pd.ok()) fuzz::Fail("ParseJsonStrict failed without an error");
    return 0;
  }
  if (app::CheckActionModel(*doc, app::ModelBudget{}, "")) return 0;  // 413, as the service

  Diagnostics diags;
  std::optional<Domain> dom = LoadDomain(*doc, diags);
  fuzz::CheckDiagnostics(diags);
  if (!dom) {
    if (diags.ok()) fuzz::Fail("LoadDomain failed without an error");
    return 0;
  }
  const Json out = DomainToJson(*dom);
  Diagnostics d2;
  std::optional<Domain> again = LoadDomain(out, d2);
  if (!again) {
    for (const auto& e : d2.errors()) std::fprintf(stderr, "%s\n", e.ToString().c_str());
    fuzz::Fail("DomainToJson gave a document that does not load");
  }
  if (DomainToJson(*again) != out) fuzz::Fail("DomainToJson is not stable under reloading");
  return 0;
}
