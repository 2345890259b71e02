// Core: opening (shipped domains, session and domain stores, demo recordings), sessions and the
// service's state. The use cases live in core_solve.cpp, core_plan.cpp, core_replan.cpp and
// core_domains.cpp.
#include "app/core.h"

#include <spdlog/spdlog.h>

#include <filesystem>

#include "app/core_impl.h"
#include "app/executions.h"
#include "app/ids.h"
#include "app/session_doc.h"
#include "planner/model/catalog.h"
#include "planner/solve/runner.h"

namespace ctb::app {

namespace {

std::string Safe(const std::string& s) {
  return Json(s).dump(-1, ' ', false, Json::error_handler_t::replace);
}

// Every *.json of <config_dir>/domains, by name; an Error names a bad file or a repeated name.
std::variant<std::map<std::string, Domain>, Error> LoadShippedDomains(const std::string& dir) {
  std::map<std::string, Domain> out;
  std::error_code ec;
  for (const auto& f : std::filesystem::directory_iterator(dir + "/domains", ec)) {
    if (f.path().extension() != ".json") continue;
    Diagnostics d;
    auto dom = LoadDomainFile(f.path().string(), d);
    if (!dom)
      return Error{ErrorCode::kInvalidInput,
                   "domain file " + f.path().string() + " is invalid: " + d.errors()[0].ToString(),
                   {}};
    if (out.count(dom->name))
      return Error{ErrorCode::kInvalidInput, "domain file " + f.path().string() +
                                                 " repeats the domain name '" + dom->name +
                                                 "' of another file", {}};
    std::string name = dom->name;
    out.emplace(name, std::move(*dom));
  }
  if (out.empty()) return Error{ErrorCode::kInvalidInput, "no domain files in " + dir + "/domains", {}};
  return out;
}

}  // namespace

Core::Core(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Core::~Core() {
  if (impl_ && impl_->executions) impl_->executions->StopAll();
}

std::variant<std::unique_ptr<Core>, Error> Core::Open(const CoreConfig& cfg) {
  auto impl = std::make_unique<Impl>(cfg);
  auto domains = LoadShippedDomains(cfg.config_dir);
  if (auto* e = std::get_if<Error>(&domains)) return *e;
  impl->domains = std::move(std::get<std::map<std::string, Domain>>(domains));
  SessionStoreConfig sc{cfg.session_store, cfg.data_dir, cfg.max_sessions, cfg.session_idle_s};
  auto store = OpenSessionStore(sc);
  if (auto* e = std::get_if<Error>(&store))
    return Error{e->code, "session store: " + e->message, e->details};
  impl->sessions = std::move(std::get<std::unique_ptr<SessionStore>>(store));
  auto domain_store = OpenDomainStore(sc);
  if (auto* e = std::get_if<Error>(&domain_store))
    return Error{e->code, "domain store: " + e->message, e->details};
  impl->stored_domains = std::move(std::get<std::unique_ptr<DomainStore>>(domain_store));
  if (cfg.demo && cfg.llm.base_url.empty() && cfg.llm.replay_dir.empty()) {
    auto replay = MakeReplayClient(cfg.recordings_dir, cfg.llm.model);
    if (auto* c = std::get_if<std::unique_ptr<LlmClient>>(&replay))
      impl->demo_llm = std::move(*c);
    else
      spdlog::warn("{}", Safe("--demo: no recordings in '" + cfg.recordings_dir + "'"));
  }
  SetSolverMemoryLimitMb(cfg.solver_memory_mb);
  impl->ready = MiniZincAvailable(cfg.minizinc);
  if (!impl->ready) spdlog::warn("{}", Safe("minizinc is not runnable: solves fail"));
  std::unique_ptr<Core> core(new Core(std::move(impl)));
  if (auto e = OpenExecutions(*core, *core->impl_)) return *e;
  return core;
}

std::variant<Json, Error> Core::GetSession(const std::string& id) {
  auto got = impl_->sessions->Get(id);
  if (auto* e = std::get_if<Error>(&got)) return *e;
  const auto& stored = std::get<std::optional<StoredSession>>(got);
  if (!stored)
    return Error{ErrorCode::kNotFound, "unknown or expired session '" + Echo(id) + "'", {}};
  return SessionView(*stored);
}

std::optional<Error> Core::DeleteSession(const std::string& id) {
  switch (impl_->sessions->Delete(id)) {
    case StoreResult::kOk: return std::nullopt;
    case StoreResult::kNotFound:
      return Error{ErrorCode::kNotFound, "unknown or expired session '" + Echo(id) + "'", {}};
    default: return Error{ErrorCode::kUnavailable, "the session store failed; retry later", {}};
  }
}

std::string Core::LlmMode() const {
  const LlmConfig& l = impl_->cfg.llm;
  return !l.replay_dir.empty() ? "replay"
         : !l.base_url.empty() ? "endpoint"
         : impl_->demo_llm     ? "recordings"
                               : "none";
}

bool Core::SolverReady() const { return impl_->ready; }

void Core::Shutdown() {
  impl_->stopping = true;
  if (impl_->executions) impl_->executions->StopAll();
  impl_->gate.WakeAll();
}

Metrics& Core::metrics() { return impl_->metrics; }

}  // namespace ctb::app
