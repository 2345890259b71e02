// Fuzz target: the PDDL 2.1 reader and importer (interchange/pddl/import.h), as `ctburton domain
// import-pddl` and `ctburton solve` run it on a user's files. The input is a domain file,
// optionally followed by a line ";;@@ problem" and a problem file. Checked: the import never
// crashes; issues carry a message and lines within the text; an imported model loads with
// LoadDomain and its state plan (with a problem) with LoadStatePlan, as import.h promises.
#include <cstdint>

#include "interchange/pddl/import.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ctb;
  const std::string_view text = fuzz::Text(data, size);
  static const std::string_view kSep = "\n;;@@ problem\n";
  pddl::Source domain{"domain.pddl", std::string(text)};
  std::optional<pddl::Source> problem;
  if (std::size_t at = text.find(kSep); at != std::string_view::npos) {
    domain.text = std::string(text.substr(0, at));
    problem = pddl::Source{"problem.pddl", std::string(text.substr(at + kSep.size()))};
  }
  pddl::ImportOptions o;
  o.max_ground_actions = 2000;  // a smaller cap than the CLI's keeps executions fast
  auto r = pddl::ImportPddl(domain, problem, o);
  if (auto* issues = std::get_if<std::vector<pddl::Issue>>(&r)) {
    if (issues->empty()) fuzz::Fail("an import failed without an issue");
    for (const auto& i : *issues) {
      if (i.message.empty()) fuzz::Fail("an issue without a message");
      if (i.line < 0 || i.column < 0) fuzz::Fail("an issue at a negative line or column");
      (void)i.ToString();
    }
    return 0;
  }
  const pddl::Imported& m = std::get<pddl::Imported>(r);
  Diagnostics diags;
  std::optional<Domain> dom = LoadDomain(m.domain, diags);
  if (!dom) {
    for (const auto& e : diags.errors()) std::fprintf(stderr, "%s\n", e.ToString().c_str());
    fuzz::Fail("an imported action model does not load");
  }
  if (!m.state_plan.is_null()) {
    Diagnostics sd;
    if (!LoadStatePlan(m.state_plan, *dom, sd)) {
      for (const auto& e : sd.errors()) std::fprintf(stderr, "%s\n", e.ToString().c_str());
      fuzz::Fail("an imported state plan does not load");
    }
  }
  return 0;
}
