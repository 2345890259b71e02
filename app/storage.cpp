// Storage health and the guarded stores (storage.h).
#include "app/storage.h"

#include <spdlog/spdlog.h>

#include "app/store_common.h"

namespace ctb::app {

namespace {

using store::NowMs;

constexpr long kRemindMs = 30000;  // a failing store is logged again at most this often
constexpr long kRetryOpenMs = 1000;

void LogEvent(spdlog::level::level_enum level, Json event) { spdlog::log(level, "{}", store::Dump(event)); }

}  // namespace

void StorageHealth::Failed(const std::string& store, const std::string& why, bool write) {
  std::lock_guard<std::mutex> lock(mu_);
  State& s = stores_[store];
  const long now = NowMs();
  s.why = why.empty() ? "failed" : why;
  s.write_failed = s.write_failed || write;
  ++s.failures;
  if (s.ok) {
    s.ok = false;
    s.since_ms = now;
    s.failures = 1;
    s.logged_ms = now;
    LogEvent(spdlog::level::err, {{"event", "storage_failed"}, {"store", store}, {"error", s.why}, {"backend", backend_}});
  } else if (now - s.logged_ms >= kRemindMs) {
    s.logged_ms = now;
    LogEvent(spdlog::level::warn, {{"event", "storage_still_failing"}, {"store", store}, {"error", s.why},
                                   {"failures", s.failures}, {"failing_for_ms", now - s.since_ms}});
  }
}

void StorageHealth::Worked(const std::string& store, bool write) {
  std::lock_guard<std::mutex> lock(mu_);
  State& s = stores_[store];
  if (s.ok || (s.write_failed && !write)) return;
  LogEvent(spdlog::level::info, {{"event", "storage_recovered"}, {"store", store}, {"failures", s.failures},
                                 {"failed_for_ms", NowMs() - s.since_ms}});
  s = State{};
}

void StorageHealth::Note(const std::string& note) {
  std::lock_guard<std::mutex> lock(mu_);
  notes_.push_back(note);
}

void StorageHealth::Watch(const std::string& store, std::function<void()> probe) {
  std::lock_guard<std::mutex> lock(mu_);
  probes_[store] = std::move(probe);
}

void StorageHealth::Unwatch(const std::string& store) {
  std::lock_guard<std::mutex> lock(mu_);
  probes_.erase(store);
}

void StorageHealth::Refresh() {
  std::vector<std::function<void()>> due;
  {
    std::lock_guard<std::mutex> lock(mu_);
    for (const auto& [name, s] : stores_)
      if (!s.ok && probes_.count(name)) due.push_back(probes_[name]);
  }
  for (auto& probe : due) probe();  // outside the lock: the probe reports here
}

bool StorageHealth::Degraded() const {
  std::lock_guard<std::mutex> lock(mu_);
  for (const auto& [name, s] : stores_)
    if (!s.ok) return true;
  return false;
}

std::string StorageHealth::Why(const std::string& store) const {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = stores_.find(store);
  return it == stores_.end() || it->second.ok ? std::string() : it->second.why;
}

Json StorageHealth::ToJson() const {
  std::lock_guard<std::mutex> lock(mu_);
  Json stores = Json::object();
  bool degraded = false;
  for (const auto& [name, s] : stores_) {
    Json j = {{"status", s.ok ? "ok" : "failing"}};
    if (!s.ok) {
      j["error"] = s.why;
      j["failing_since_ms"] = s.since_ms;
      degraded = true;
    }
    stores[name] = j;
  }
  Json out = {{"status", degraded ? "degraded" : "ok"}, {"backend", backend_}, {"stores", stores}};
  if (!notes_.empty()) out["notes"] = notes_;
  return out;
}

std::string StorageHealth::Metrics() const {
  std::lock_guard<std::mutex> lock(mu_);
  std::string out =
      "# HELP ctb_storage_up Whether the store's last call worked (1) or failed (0).\n"
      "# TYPE ctb_storage_up gauge\n";
  for (const auto& [name, s] : stores_) out += "ctb_storage_up{store=\"" + name + "\"} " + (s.ok ? "1" : "0") + "\n";
  return out;
}

Error StoreFailed(const StorageHealth& health, const std::string& store) {
  const std::string why = health.Why(store);
  return Error{ErrorCode::kUnavailable,
               "the " + store + " store failed" + (why.empty() ? "" : " (" + why + ")") + "; retry later", {}};
}

namespace {

// The store behind a guard: opened when it can be, every outcome reported to the health.
class GuardedDocumentStore : public DocumentStore {
 public:
  GuardedDocumentStore(DocumentStoreOpener open, std::string name, std::shared_ptr<StorageHealth> health)
      : open_(std::move(open)), name_(std::move(name)), health_(std::move(health)) {
    Open();
    health_->Watch(name_, [this] {
      if (auto s = Open()) Report(s->Probe(), *s, true);  // the store's own write probe, as a write
    });
  }
  ~GuardedDocumentStore() override { health_->Unwatch(name_); }
  GuardedDocumentStore(const GuardedDocumentStore&) = delete;
  GuardedDocumentStore& operator=(const GuardedDocumentStore&) = delete;

  std::variant<std::optional<StoredDocument>, Error> Get(const std::string& id) override {
    return Fetch<std::variant<std::optional<StoredDocument>, Error>>([&](DocumentStore& s) { return s.Get(id); });
  }
  StoreResult Create(StoredDocument& d) override { return Call([&](DocumentStore& s) { return s.Create(d); }); }
  StoreResult Write(StoredDocument& d, bool any_version) override {
    return Call([&](DocumentStore& s) { return s.Write(d, any_version); });
  }
  StoreResult Delete(const std::string& id) override { return Call([&](DocumentStore& s) { return s.Delete(id); }); }
  long Count() override { return Number([](DocumentStore& s) { return s.Count(); }); }
  long CountWhere(const std::string& field, const std::string& value) override {
    return Number([&](DocumentStore& s) { return s.CountWhere(field, value); });
  }
  std::variant<std::vector<std::string>, Error> List() override {
    return Fetch<std::variant<std::vector<std::string>, Error>>([](DocumentStore& s) { return s.List(); });
  }
  std::string LastError() const override { return health_->Why(name_); }
  bool Probe() override { return true; }  // the guard probes the store inside

 private:
  // A call that reads (a variant of a value or an Error): the Error names the store and why.
  template <class R, class F>
  R Fetch(F f) {
    auto s = Open();
    if (!s) return Failed();
    R r = f(*s);
    const bool ok = !std::holds_alternative<Error>(r);
    Report(ok, *s, false);
    if (!ok) return Failed();
    return r;
  }
  // A call that writes.
  template <class F>
  StoreResult Call(F f) {
    auto s = Open();
    if (!s) return StoreResult::kUnavailable;
    StoreResult r = f(*s);
    Report(r != StoreResult::kUnavailable, *s, true);
    return r;
  }
  // A call that counts (-1 when it failed).
  template <class F>
  long Number(F f) {
    auto s = Open();
    if (!s) return -1;
    long n = f(*s);
    Report(n >= 0, *s, false);
    return n;
  }
  void Report(bool ok, const DocumentStore& s, bool write) {
    if (ok) health_->Worked(name_, write);
    else health_->Failed(name_, s.LastError(), write);
  }
  Error Failed() const { return StoreFailed(*health_, name_); }

  std::shared_ptr<DocumentStore> Open() {
    std::lock_guard<std::mutex> lock(mu_);
    if (inner_) return inner_;
    const long now = NowMs();
    if (tried_ms_ == 0 || now - tried_ms_ >= kRetryOpenMs) {
      tried_ms_ = now;
      auto opened = open_();
      if (auto* s = std::get_if<std::unique_ptr<DocumentStore>>(&opened)) {
        inner_ = std::move(*s);
        health_->Worked(name_, false);
        return inner_;
      }
      why_ = std::get<Error>(opened).message;
    }
    health_->Failed(name_, why_);
    return nullptr;
  }

  DocumentStoreOpener open_;
  std::string name_;
  std::shared_ptr<StorageHealth> health_;
  std::mutex mu_;
  std::shared_ptr<DocumentStore> inner_;
  long tried_ms_ = 0;
  std::string why_;
};

}  // namespace

std::unique_ptr<DocumentStore> GuardDocumentStore(DocumentStoreOpener open, std::string store,
                                                  std::shared_ptr<StorageHealth> health) {
  return std::make_unique<GuardedDocumentStore>(std::move(open), std::move(store), std::move(health));
}

}  // namespace ctb::app
