// Core: domains through the API (contract section 12). Shipped domains (config/domains, loaded
// at start) and stored ones (app/domain_store.h, created through the API) share one namespace;
// every use case that takes a domain name resolves it here.
#include <spdlog/spdlog.h>

#include <regex>

#include "app/core.h"
#include "app/core_impl.h"
#include "app/ids.h"
#include "planner/diagram/diagram.h"
#include "planner/model/templates.h"
#include "translator/draft.h"

namespace ctb::app {

namespace {

Error Unknown(const std::string& name) {
  return Error{ErrorCode::kNotFound, "unknown domain '" + Echo(name) + "'",
               {{"/domain", std::nullopt, "see GET /domains"}}};
}

Error Shipped(const std::string& name, const std::string& what) {
  return Error{ErrorCode::kConflict,
               "'" + Echo(name) + "' is a shipped domain (config/domains); it cannot be " + what, {}};
}

// The name a document gives itself, checked as a route segment and an identifier of the API.
std::variant<std::string, Error> DocumentName(const Json& doc) {
  if (!doc.is_object()) return Bad("a domain document must be a JSON object", "/");
  auto it = doc.find("name");
  if (it == doc.end()) return Bad("missing required field", "/name");
  if (!it->is_string()) return Bad("must be a string", "/name");
  static const std::regex kName("[A-Za-z][A-Za-z0-9_]{0,63}");
  const std::string name = it->get<std::string>();
  if (!std::regex_match(name, kName))
    return Bad("a domain name is a letter then letters, digits or _ (at most 64), got '" +
                   Echo(name) + "'", "/name");
  return name;
}

// Checks a document as an action model: the request budget, then templates and the domain
// itself; pointers are relative to the document.
std::optional<Error> CheckDocument(const Json& doc, const ModelBudget& budget) {
  if (auto over = CheckActionModel(doc, budget, "")) return *over;
  Diagnostics d;
  auto dom = LoadDomain(doc, d);
  if (!dom) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid action model", d);
  if (auto over = CheckExpandedDomain(*dom, budget, "")) return *over;
  return std::nullopt;
}

DomainInfo InfoOf(const Domain& d, const std::string& source, long version) {
  DomainInfo info{d.name, d.description, {}, source, version};
  for (const auto& a : d.automata) info.automata.push_back(a.name);
  return info;
}

}  // namespace

std::variant<std::shared_ptr<const Domain>, Error> Core::Impl::NamedDomain(
    const std::string& name) const {
  if (auto it = domains.find(name); it != domains.end())
    return std::shared_ptr<const Domain>(std::shared_ptr<const Domain>(), &it->second);
  if (!stored_domains) return Unknown(name);
  auto got = stored_domains->Get(name);
  if (auto* e = std::get_if<Error>(&got)) return *e;
  const auto& stored = std::get<std::optional<StoredDocument>>(got);
  if (!stored) return Unknown(name);
  Diagnostics d;
  auto dom = LoadDomain(stored->doc, d);
  if (!dom) {  // checked when written; only a change of the rules since can get here
    spdlog::error("{}", Json({{"event", "stored_domain_invalid"}, {"domain", name}}).dump());
    return Error{ErrorCode::kInvalidInput,
                 "stored domain '" + Echo(name) + "' no longer loads: " + d.errors()[0].ToString() +
                     "; replace it with PUT /domains/" + name, {}};
  }
  return std::make_shared<const Domain>(std::move(*dom));
}

std::variant<std::vector<DomainInfo>, Error> Core::ListDomains() const {
  std::vector<DomainInfo> out;
  for (const auto& [name, d] : impl_->domains) out.push_back(InfoOf(d, "shipped", 0));
  if (!impl_->stored_domains) return out;
  auto names = impl_->stored_domains->List();
  if (auto* e = std::get_if<Error>(&names)) return *e;
  for (const auto& name : std::get<std::vector<std::string>>(names)) {
    auto got = impl_->stored_domains->Get(name);
    if (auto* e = std::get_if<Error>(&got)) return *e;
    const auto& stored = std::get<std::optional<StoredDocument>>(got);
    if (!stored) continue;  // deleted meanwhile
    Diagnostics d;
    if (auto dom = LoadDomain(stored->doc, d)) out.push_back(InfoOf(*dom, "stored", stored->version));
  }
  return out;
}

std::variant<Json, Error> Core::GetDomain(const std::string& name, bool as_written) const {
  if (auto it = impl_->domains.find(name); it != impl_->domains.end()) return DomainToJson(it->second);
  if (!as_written) {
    auto dom = impl_->NamedDomain(name);
    if (auto* e = std::get_if<Error>(&dom)) return *e;
    return DomainToJson(*std::get<std::shared_ptr<const Domain>>(dom));
  }
  if (!impl_->stored_domains) return Unknown(name);
  auto got = impl_->stored_domains->Get(name);
  if (auto* e = std::get_if<Error>(&got)) return *e;
  const auto& stored = std::get<std::optional<StoredDocument>>(got);
  if (!stored) return Unknown(name);
  return stored->doc;
}

std::variant<std::string, Error> Core::CreateDomain(const Json& document) {
  auto name = DocumentName(document);
  if (auto* e = std::get_if<Error>(&name)) return *e;
  const std::string& n = std::get<std::string>(name);
  if (impl_->domains.count(n)) return Shipped(n, "created again");
  if (auto e = CheckDocument(document, impl_->cfg.budget)) return *e;
  if (!impl_->stored_domains) return impl_->StoreFailed("domain");
  StoredDocument d;
  d.id = n;
  d.doc = document;
  switch (impl_->stored_domains->Create(d)) {
    case StoreResult::kOk: return n;
    case StoreResult::kConflict:
      return Error{ErrorCode::kConflict,
                   "domain '" + n + "' exists; PUT /domains/" + n + " replaces it", {}};
    case StoreResult::kFull:
      return Error{ErrorCode::kTooLarge, "the service holds as many domains as it may; delete one first", {}};
    default: return impl_->StoreFailed("domain");
  }
}

std::optional<Error> Core::ReplaceDomain(const std::string& name, const Json& document) {
  if (impl_->domains.count(name)) return Shipped(name, "replaced");
  auto given = DocumentName(document);
  if (auto* e = std::get_if<Error>(&given)) return *e;
  if (std::get<std::string>(given) != name)
    return Bad("the document is named '" + Echo(std::get<std::string>(given)) +
                   "' but the path names '" + Echo(name) + "'", "/name");
  if (auto e = CheckDocument(document, impl_->cfg.budget)) return *e;
  if (!impl_->stored_domains) return impl_->StoreFailed("domain");
  StoredDocument d;
  d.id = name;
  d.doc = document;
  switch (impl_->stored_domains->Replace(d)) {
    case StoreResult::kOk: return std::nullopt;
    case StoreResult::kNotFound: return Unknown(name);
    default: return impl_->StoreFailed("domain");
  }
}

std::optional<Error> Core::DeleteDomain(const std::string& name, bool force) {
  if (impl_->domains.count(name)) return Shipped(name, "deleted");
  if (!impl_->stored_domains) return Unknown(name);
  auto got = impl_->stored_domains->Get(name);
  if (auto* e = std::get_if<Error>(&got)) return *e;
  if (!std::get<std::optional<StoredDocument>>(got)) return Unknown(name);
  if (!force) {
    const long users = impl_->sessions->CountWhere("domain", name);
    if (users < 0) return impl_->StoreFailed("session");
    if (users > 0)
      return Error{ErrorCode::kConflict,
                   std::to_string(users) + " live session(s) use domain '" + name +
                       "'; delete with force=true to delete it anyway (their follow-ups then fail)",
                   {}};
  }
  switch (impl_->stored_domains->Delete(name)) {
    case StoreResult::kOk: return std::nullopt;
    case StoreResult::kNotFound: return Unknown(name);
    default: return impl_->StoreFailed("domain");
  }
}

std::variant<std::string, Error> Core::DomainDiagram(const std::string& name) const {
  auto dom = impl_->NamedDomain(name);
  if (auto* e = std::get_if<Error>(&dom)) return *e;
  return DomainSvg(*std::get<std::shared_ptr<const Domain>>(dom));
}

std::variant<DraftAnswer, Error> Core::DraftDomain(const std::string& description,
                                                   const CallContext& ctx) {
  auto llm = impl_->Llm();
  if (auto* e = std::get_if<Error>(&llm)) return *e;
  if (ctx.observer) ctx.observer->OnStage("drafting", Json::object());
  DraftOptions o;
  o.max_repairs = impl_->cfg.llm.max_repairs;
  o.prompts_dir = impl_->cfg.prompts_dir;
  auto r = Draft(description, *std::get<std::unique_ptr<LlmClient>>(llm), o);
  if (auto* e = std::get_if<Error>(&r)) {
    Error out = *e;
    for (auto& d : out.details)  // pointers relative to the request body
      if (d.pointer.rfind("/description", 0) != 0) d.pointer = "/action_model" + d.pointer;
    return out;
  }
  return DraftAnswer{DraftJson(std::get<DraftResult>(r))};
}

}  // namespace ctb::app
