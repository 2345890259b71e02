// `ctburton domain check|expand|draw|draft|import-pddl`: action models as files (docs/domains.md).
#include <fstream>
#include <sstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "client/commands.h"
#include "client/local_core.h"
#include "interchange/pddl/import.h"
#include "planner/diagram/diagram.h"
#include "planner/model/catalog.h"
#include "planner/model/templates.h"
#include "translator/text.h"

namespace ctb::cli {

namespace {

struct DomainOptions {
  std::string file;
  std::string config_dir;
  std::vector<std::string> set;  // NAME=VALUE parameter overrides
  std::string out;
  std::string description;
  int max_repairs = -1;
  std::string problem;         // import-pddl: the PDDL problem file
  std::string state_plan_out;  // import-pddl: where the problem's state plan goes
  std::string name;            // import-pddl: the domain's name
};

// Reads FILE (a path) or a shipped domain NAME, expands it with the overrides, loads it. Prints
// the errors and returns 1 (bad input) on failure.
int Load(const DomainOptions& o, Expansion& x, std::optional<Domain>& d) {
  std::string path = o.file;
  if (path.find('/') == std::string::npos && path.find(".json") == std::string::npos)
    path = (o.config_dir.empty() ? DefaultConfigDir() : o.config_dir) + "/domains/" + path + ".json";
  Diagnostics diags;
  auto j = ReadJsonFile(path, diags);
  ExpandOptions eo;
  for (const auto& s : o.set) {
    auto eq = s.find('=');
    long v = 0;
    bool ok = eq != std::string::npos && eq > 0;
    if (ok) {
      try {
        std::size_t used = 0;
        v = std::stol(s.substr(eq + 1), &used);
        ok = used == s.size() - eq - 1;
      } catch (const std::exception&) {
        ok = false;
      }
    }
    if (!ok) {
      std::cerr << "error: --set wants NAME=INTEGER, got '" << s << "'\n";
      return 2;
    }
    eo.parameters[s.substr(0, eq)] = v;
  }
  if (j) d = LoadDomain(*j, diags, eo, &x);
  if (!diags.ok()) {
    std::cout << "invalid: " << o.file << "\n";
    for (const auto& e : diags.errors()) std::cout << ValidUtf8(e.ToString()) << "\n";
    return 1;
  }
  for (const auto& w : diags.warnings()) std::cerr << "warning: " << ValidUtf8(w.ToString()) << "\n";
  return 0;
}

int Write(const DomainOptions& o, const std::string& text) {
  if (o.out.empty() || o.out == "-") {
    std::cout << text;
    return 0;
  }
  std::ofstream f(o.out, std::ios::binary);
  f << text;
  if (!f) {
    std::cerr << "error: cannot write '" << o.out << "'\n";
    return 3;
  }
  return 0;
}

int RunCheck(const DomainOptions& o) {
  Expansion x;
  std::optional<Domain> d;
  if (int rc = Load(o, x, d)) return rc;
  std::size_t locations = 0, transitions = 0;
  for (const auto& a : d->automata) {
    locations += a.locations.size();
    transitions += a.transitions.size();
  }
  std::cout << "valid: " << d->name << " (" << d->automata.size() << " automata, " << locations
            << " locations, " << transitions << " transitions"
            << (x.had_templates ? ", from templates" : "") << ")\n";
  return 0;
}

int RunExpand(const DomainOptions& o) {
  Expansion x;
  std::optional<Domain> d;
  if (int rc = Load(o, x, d)) return rc;
  return Write(o, PrettyText(x.document) + "\n");
}

int RunDraw(const DomainOptions& o) {
  Expansion x;
  std::optional<Domain> d;
  if (int rc = Load(o, x, d)) return rc;
  return Write(o, DomainSvg(*d));
}

// `domain draft "words"`: the application core's draft (as POST /domains/draft), with the LLM from
// the environment; the action model also to --out.
int RunDraft(const DomainOptions& o) {
  auto opened = OpenLocalCore(o.config_dir, /*with_llm=*/true, o.max_repairs);
  if (auto* e = std::get_if<Error>(&opened)) return Fail(*e);
  auto r = std::get<std::unique_ptr<app::Core>>(opened)->DraftDomain(o.description, {});
  if (auto* e = std::get_if<Error>(&r)) return Fail(RelativeTo(*e, "/action_model"));
  const Json& draft = std::get<app::DraftAnswer>(r).document;
  if (!o.out.empty() && o.out != "-") {
    std::ofstream f(o.out, std::ios::binary);
    f << PrettyText(draft.value("action_model", Json())) << "\n";
    if (!f) {
      std::cerr << "error: cannot write '" << o.out << "'\n";
      return 3;
    }
  }
  std::cout << PrettyText(draft) << "\n";
  return 0;
}

std::optional<std::string> ReadText(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return std::nullopt;
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// The core names the texts domain.pddl and problem.pddl; the user's files are named here instead.
std::string Renamed(std::string text, const DomainOptions& o) {
  for (const auto& [core_name, user] : {std::pair<std::string, std::string>{"domain.pddl", o.file}, {"problem.pddl", o.problem}})
    if (text.rfind(core_name + ":", 0) == 0) return user + text.substr(core_name.size());
  return text;
}

// A warning of the answer ({"file"?, "line", "column", "action"?, "message"}) as the importer says it.
std::string WarningText(const Json& w) {
  pddl::Issue i;
  i.file = w.value("file", "");
  i.line = w.value("line", 0);
  i.column = w.value("column", 0);
  i.action = w.value("action", "");
  i.message = w.value("message", "");
  return i.ToString();
}

// `domain import-pddl DOMAIN.pddl [PROBLEM.pddl]`: the action model on stdout (or --out), the
// state plan of the problem to --state-plan-out; issues to stderr, exit 1.
int RunImportPddl(const DomainOptions& o) {
  if (!o.state_plan_out.empty() && o.problem.empty()) {
    std::cerr << "error: --state-plan-out needs a PROBLEM file\n";
    return 2;
  }
  app::PddlImportCall call;
  call.name = o.name;
  for (const std::string* path : {&o.file, &o.problem}) {
    if (path->empty()) continue;
    auto text = ReadText(*path);
    if (!text) {
      std::cerr << "error: cannot read '" << *path << "'\n";
      return 1;
    }
    (path == &o.file ? call.domain : call.problem) = std::move(*text);
  }
  auto core = OpenLocalCore(o.config_dir, false);
  if (auto* e = std::get_if<Error>(&core)) {
    std::cerr << "error: " << ValidUtf8(e->ToString()) << "\n";
    return 1;
  }
  auto r = std::get<std::unique_ptr<app::Core>>(core)->ImportPddl(call);
  if (auto* e = std::get_if<Error>(&r)) {
    // Each problem as FILE:LINE:COLUMN: ..., the files named as the user gave them.
    for (const auto& d : e->details)
      std::cerr << "error: " << ValidUtf8(Renamed(d.message, o)) << "\n";
    if (e->details.empty()) std::cerr << "error: " << ValidUtf8(e->message) << "\n";
    return 1;
  }
  const app::PddlImportAnswer& im = std::get<app::PddlImportAnswer>(r);
  for (const auto& w : im.warnings)
    std::cerr << "warning: " << ValidUtf8(Renamed(WarningText(w), o)) << "\n";
  auto dump = [](const Json& j) { return PrettyText(j) + "\n"; };
  if (int rc = Write(o, dump(im.action_model))) return rc;
  if (!o.state_plan_out.empty()) {
    DomainOptions sp = o;
    sp.out = o.state_plan_out;
    if (int rc = Write(sp, dump(im.state_plan))) return rc;
  }
  if (!o.out.empty() && o.out != "-") {
    std::size_t locations = 0, transitions = 0;
    for (const auto& a : im.action_model["automata"]) {
      locations += a["locations"].size();
      transitions += a["transitions"].size();
    }
    std::cout << "imported: " << im.action_model["name"].get<std::string>() << " ("
              << im.action_model["automata"].size() << " automata, " << locations << " locations, "
              << transitions << " transitions from " << im.ground_actions << " ground actions)\n";
  }
  return 0;
}

}  // namespace

Runner AddDomain(CLI::App& app) {
  auto o = std::make_shared<DomainOptions>();
  CLI::App* dom = app.add_subcommand("domain", "Check, expand, draw, draft or import an action model");
  dom->require_subcommand(1);
  auto file_cmd = [&](const char* name, const char* help) {
    CLI::App* sub = dom->add_subcommand(name, help);
    sub->add_option("file", o->file, "Domain JSON file (templates allowed) or a shipped name")
        ->required();
    sub->add_option("--set", o->set, "Override a template parameter: NAME=INTEGER (repeatable)");
    sub->add_option("--config-dir", o->config_dir, "Configuration directory");
    return sub;
  };
  CLI::App* check = file_cmd("check", "Check a domain; located errors, exit 1 when invalid");
  CLI::App* expand = file_cmd("expand", "Print the domain with its templates expanded");
  expand->add_option("-o,--out", o->out, "Write to this file instead of stdout");
  CLI::App* draw = file_cmd("draw", "Draw the domain's automata as SVG");
  draw->add_option("-o,--out", o->out, "Write to this file instead of stdout");
  CLI::App* draft = dom->add_subcommand("draft", "Draft an action model from a description (LLM)");
  draft->add_option("description", o->description, "The team in plain words")->required();
  draft->add_option("-o,--out", o->out, "Also write the drafted action model to this file");
  draft->add_option("--max-repairs", o->max_repairs, "Repair requests (default CTB_LLM_MAX_REPAIRS)");
  CLI::App* import = dom->add_subcommand(
      "import-pddl", "Import a PDDL 2.1 temporal domain (and problem) as an action model");
  import->add_option("domain", o->file, "PDDL domain file")->required();
  import->add_option("problem", o->problem, "PDDL problem file: its objects and :init ground the domain");
  import->add_option("-o,--out", o->out, "Write the action model to this file instead of stdout");
  import->add_option("--state-plan-out", o->state_plan_out,
                     "Write the problem's initial state and goal as a state plan to this file");
  import->add_option("--name", o->name, "The domain's name (default: the PDDL domain's)");
  return [o, dom, check, expand, draw, draft, import]() {
    if (!dom->parsed()) return -1;
    if (check->parsed()) return RunCheck(*o);
    if (expand->parsed()) return RunExpand(*o);
    if (draw->parsed()) return RunDraw(*o);
    if (draft->parsed()) return RunDraft(*o);
    if (import->parsed()) return RunImportPddl(*o);
    return 2;
  };
}

}  // namespace ctb::cli
