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

// A file of this process (SQLite): its integrity is checked first; a damaged file is kept
// aside and what reads of it carried into a new one (storage.h).
std::optional<Error> CheckDataFile(const CoreConfig& cfg, StorageHealth& health) {
  if (!cfg.session_store.empty() && cfg.session_store != "sqlite") return std::nullopt;
  std::error_code ec;
  std::filesystem::create_directories(cfg.data_dir, ec);
  auto check = CheckSqliteFile(cfg.data_dir + "/sessions.db");
  if (auto* e = std::get_if<Error>(&check)) return *e;
  const auto& c = std::get<SqliteFileCheck>(check);
  if (!c.damaged) return std::nullopt;
  spdlog::error("{}", Json({{"event", "storage_damaged_file"}, {"problem", c.problem}, {"kept_at", c.kept_at},
                            {"records_carried_over", c.salvaged}}).dump());
  health.Note("the database file was damaged (" + c.problem + "): it was kept aside as " +
              std::filesystem::path(c.kept_at).filename().string() + " and " + std::to_string(c.salvaged) +
              " records that could be read were carried into a new file");
  return std::nullopt;
}

// The session and domain stores behind their guards: the server starts even when storage
// cannot be opened yet (a read-only data directory, Redis down) and opens it when it can.
std::optional<Error> OpenStores(Core::Impl& impl) {
  const CoreConfig& cfg = impl.cfg;
  const std::string backend = cfg.session_store.empty() || cfg.session_store == "sqlite"
                                  ? "sqlite:" + cfg.data_dir + "/sessions.db"
                                  : cfg.session_store;
  impl.storage = std::make_shared<StorageHealth>(backend);
  if (auto e = CheckDataFile(cfg, *impl.storage)) return e;
  const DocumentStoreConfig sc{cfg.session_store, cfg.data_dir, "session", cfg.max_sessions, cfg.session_idle_s};
  const DocumentStoreConfig dc{cfg.session_store, cfg.data_dir, "domain", 1000, 0};  // 1000 at most, never expire
  std::string host;
  int port = 0, db = 0;
  const bool local = sc.url.empty() || sc.url == "sqlite" || sc.url == "memory";
  if (!local)  // a wrong URL stops the start; an unreachable server does not
    if (auto e = ParseRedisUrl(sc.url, host, port, db)) return Error{e->code, "session store: " + e->message, {}};
  impl.sessions = GuardDocumentStore([sc] { return OpenDocumentStore(sc); }, "session", impl.storage);
  impl.stored_domains = GuardDocumentStore([dc] { return OpenDocumentStore(dc); }, "domain", impl.storage);
  return std::nullopt;
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
  if (auto e = OpenStores(*impl)) return *e;
  if (cfg.demo && cfg.llm.base_url.empty() && cfg.llm.replay_dir.empty()) {
    auto replay = MakeReplayClient(cfg.recordings_dir, cfg.llm.model);
    if (auto* c = std::get_if<std::unique_ptr<LlmClient>>(&replay))
      impl->demo_llm = std::move(*c);
    else
      spdlog::warn("{}", LogText("--demo: no recordings in '" + cfg.recordings_dir + "'"));
  }
  impl->ready = !cfg.probe_solver || MiniZincAvailable(cfg.minizinc);
  if (!impl->ready) spdlog::warn("{}", LogText("minizinc is not runnable: solves fail"));
  std::unique_ptr<Core> core(new Core(std::move(impl)));
  if (auto e = OpenExecutions(*core, *core->impl_)) return *e;
  return core;
}

std::variant<Json, Error> Core::GetSession(const std::string& id) {
  auto got = impl_->sessions->Get(id);
  if (auto* e = std::get_if<Error>(&got)) return *e;
  const auto& stored = std::get<std::optional<StoredDocument>>(got);
  if (!stored)
    return Error{ErrorCode::kNotFound, "unknown or expired session '" + Echo(id) + "'", {}};
  return SessionView(*stored);
}

std::optional<Error> Core::DeleteSession(const std::string& id) {
  switch (impl_->sessions->Delete(id)) {
    case StoreResult::kOk: return std::nullopt;
    case StoreResult::kNotFound:
      return Error{ErrorCode::kNotFound, "unknown or expired session '" + Echo(id) + "'", {}};
    default: return impl_->StoreFailed("session");
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

Json Core::Storage() const {
  impl_->storage->Refresh();
  return impl_->storage->ToJson();
}

std::string Core::StorageMetrics() const { return impl_->storage->Metrics(); }

void Core::Shutdown() {
  impl_->stopping = true;
  if (impl_->executions) impl_->executions->StopAll();
  impl_->gate.WakeAll();
}

Metrics& Core::metrics() { return impl_->metrics; }

}  // namespace ctb::app
