// The live executions (executions.h).
#include "app/executions.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <chrono>

#include "app/ids.h"
#include "app/store_common.h"

namespace ctb::app {

namespace {

constexpr std::size_t kKeptEvents = 500;  // per execution, in the store and in GET
constexpr int kMaxReplansInARow = 8;
// A replan plans from at most this far ahead (wall time): a replan slower than that is late.
constexpr long kMaxReplanLeadMs = 5000;

// The store's 503: "the execution store failed (why); <what then>".
Error StoreFailed(const DocumentStore& store, const std::string& then) {
  const std::string why = store.LastError();
  return {ErrorCode::kUnavailable, "the execution store failed" + (why.empty() ? "" : " (" + why + ")") + "; " + then, {}};
}

Error NotFound(const std::string& id) {
  return {ErrorCode::kNotFound, "unknown execution '" + Echo(id) + "'", {}};
}

// Events as the stored document and GET /executions/{id} hold them, and back.
Json EventsJson(const std::vector<ExecutionEvent>& events) {
  Json out = Json::array();
  for (const auto& e : events) out.push_back({{"seq", e.seq}, {"event", e.name}, {"data", e.data}});
  return out;
}

std::vector<ExecutionEvent> StoredEvents(const Json& doc) {
  std::vector<ExecutionEvent> out;
  for (const auto& e : doc.value("events", Json::array()))
    out.push_back({e.value("seq", 0L), e.value("event", ""), e.value("data", Json())});
  return out;
}

}  // namespace

struct Executions::Live {
  explicit Live(std::shared_ptr<const Domain> d) : domain(std::move(d)), run(*domain) {}
  double Now() const { return static_cast<double>(store::NowMs() - origin_ms) * speed / 1000.0; }

  std::string id;
  std::shared_ptr<const Domain> domain;
  StoredDocument stored;  // the stored document and its version
  exec::Run run;
  std::optional<exec::SimTeam> sim;
  RequestOptions options;
  std::string adapter;
  double speed = 1;
  long origin_ms = 0;
  long replans = 0;
  int replans_in_a_row = 0;  // without a report between them
  // How long the last replan took, in plan seconds: the next one plans from that far ahead, so
  // that its first moments are not already past when it is adopted (a slow machine, a high speed).
  double replan_lead = 0;
  std::vector<ExecutionEvent> events;
  long seq = 0;
  std::optional<std::string> pending_replan;
  bool poked = false;
  bool ended = false;
  std::atomic<bool> cancel{false};  // a stop or a shutdown: the replan's solver is killed
  std::atomic<bool> shutdown{false};
  std::atomic<bool> let_go{false};  // another replica carries it now
  long persisted_ms = 0;            // the last write (a claim lasts lease_ms from it)
  std::mutex mu;
  std::condition_variable cv;
  std::thread thread;
};

Executions::Executions(Core& core, std::unique_ptr<DocumentStore> store, long lease_ms, bool shared)
    : core_(core), store_(std::move(store)), lease_ms_(lease_ms), shared_(shared), me_(RandomHex(8)) {}

Executions::~Executions() { StopAll(); }

void Executions::StopAll() {
  std::thread scanner;
  {
    std::lock_guard<std::mutex> lock(scan_mu_);
    scan_stop_ = true;
    scanner = std::move(scanner_);  // one caller joins it
  }
  scan_cv_.notify_all();
  if (scanner.joinable()) scanner.join();
  std::vector<std::shared_ptr<Live>> all;
  {
    std::lock_guard<std::mutex> lock(mu_);
    for (auto& [id, l] : live_) all.push_back(l);
    all.insert(all.end(), retired_.begin(), retired_.end());
  }
  for (auto& l : all) {
    {
      std::lock_guard<std::mutex> lk(l->mu);
      l->shutdown = true;
      l->cancel = true;
    }
    l->cv.notify_all();
  }
  // Shutdown may come from two threads at once (the server's signal thread and its main thread):
  // each thread is taken out under its execution's lock, so only one caller joins it.
  for (auto& l : all) {
    std::thread t;
    {
      std::lock_guard<std::mutex> lk(l->mu);
      t = std::move(l->thread);
    }
    if (t.joinable()) t.join();
  }
}

std::shared_ptr<Executions::Live> Executions::Find(const std::string& id) {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = live_.find(id);
  return it == live_.end() || it->second->let_go ? nullptr : it->second;
}

void Executions::SetSink(const std::string& adapter, std::shared_ptr<CommandSink> sink,
                         const std::string& execution) {
  std::lock_guard<std::mutex> lock(mu_);
  const std::string key = execution.empty() ? adapter : adapter + ":" + execution;
  if (sink)
    sinks_[key] = std::move(sink);
  else
    sinks_.erase(key);
}

std::shared_ptr<CommandSink> Executions::SinkFor(const Live& live) {
  std::lock_guard<std::mutex> lock(mu_);
  for (const std::string& key : {live.adapter + ":" + live.id, live.adapter}) {
    auto it = sinks_.find(key);
    if (it != sinks_.end()) return it->second;
  }
  return nullptr;
}

void Executions::Emit(Live& live, const std::string& name, Json data) {
  live.events.push_back({++live.seq, name, std::move(data)});
  if (live.events.size() > kKeptEvents) live.events.erase(live.events.begin());
  live.cv.notify_all();
}

bool Executions::Persist(Live& live) {
  Json& doc = live.stored.doc;
  doc["run"] = live.run.ToJson();
  doc["events"] = EventsJson(live.events);
  doc["seq"] = live.seq;
  doc["replans"] = live.replans;
  doc["owner"] = me_;
  live.persisted_ms = store::NowMs();
  doc["lease_until_ms"] = live.persisted_ms + lease_ms_;
  switch (store_->Update(live.stored)) {
    case StoreResult::kOk: return true;
    case StoreResult::kConflict:
      // Another replica wrote it: that one carries it now; this one lets go.
      spdlog::warn("{}", LogText("execution " + live.id + ": changed by another process; this one stops carrying it"));
      live.shutdown = true;
      live.let_go = true;
      return false;
    default: spdlog::error("{}", LogText("execution " + live.id + ": the execution store failed")); return false;
  }
}

std::variant<exec::Applied, Error> Executions::ApplyLocked(Live& live, const exec::Report& r) {
  exec::Run before = live.run;
  auto applied = live.run.Apply(r, live.Now());
  if (auto* e = std::get_if<Error>(&applied)) return *e;
  const exec::Applied& a = std::get<exec::Applied>(applied);
  if (a.duplicate) return a;
  const std::size_t events = live.events.size();
  const long seq = live.seq;
  Emit(live, "reported", r.ToJson());
  if (!Persist(live)) {  // not stored: as if it never came
    live.run = std::move(before);
    live.events.resize(events);
    live.seq = seq;
    return StoreFailed(*store_, "the report was not stored: send it again");
  }
  live.replans_in_a_row = 0;
  if (a.replan && !live.pending_replan) live.pending_replan = *a.replan;
  live.poked = true;
  live.cv.notify_all();
  return a;
}

void Executions::Replan(std::shared_ptr<Live>& live, std::unique_lock<std::mutex>& lk, const std::string& why) {
  const double now = live->Now();
  if (!live->stored.doc.value("replan", true)) {
    live->run.Finish(exec::State::kFailed, "the world departed from the plan and replanning is off: " + why);
    return;
  }
  // Plans that are late already when adopted (the clock outruns the planner: a speed too high
  // for the team, or a device that never reports) would be replanned for ever.
  if (++live->replans_in_a_row > kMaxReplansInARow) {
    live->run.Finish(exec::State::kFailed, std::to_string(kMaxReplansInARow) +
                                               " replans in a row without a report between them; the last after: " + why);
    return;
  }
  const long t0 = store::NowMs();
  ReplanCall call;
  call.domain.loaded = live->domain;
  call.state_plan = live->stored.doc["state_plan"];
  call.request = live->run.ReplanRequest(now + live->replan_lead);
  call.options = live->options;
  const std::size_t seen = live->run.history().size();
  CallContext ctx;
  ctx.cancelled = [l = live.get()] { return l->cancel.load(); };
  ctx.request_id = "execution-" + live->id;
  lk.unlock();
  auto r = core_.Replan(call, ctx);
  lk.lock();
  live->replan_lead = std::min<double>(store::NowMs() - t0, kMaxReplanLeadMs) / 1000.0 * live->speed;
  if (live->shutdown || live->run.state() != exec::State::kRunning) return;
  if (auto* e = std::get_if<Error>(&r)) {
    live->run.Finish(exec::State::kFailed, "replanning failed: " + e->message);
    return;
  }
  const Answer& answer = std::get<Answer>(r);
  const SolveResult& result = answer.result;
  const Json& doc = answer.document;
  if ((result.status == Termination::kOptimal || result.status == Termination::kFeasible) &&
      result.network && result.network->is_object()) {
    if (auto e = live->run.Adopt(doc, now)) {
      live->run.Finish(exec::State::kFailed, e->message);
      return;
    }
    ++live->replans;
    // ms: from the decision to replan to the new plan adopted; its first commands go out at once.
    Emit(*live, "replanned", {{"why", why}, {"now", call.request["now"]}, {"status", TerminationName(result.status)},
                              {"objective", ObjectiveJson(result)}, {"diff", answer.diff.value_or(Json())},
                              {"ms", store::NowMs() - t0}});
    if (!live->run.Replay(seen)) live->pending_replan = "reports came while replanning that the new plan does not have next";
    Persist(*live);
    return;
  }
  std::string reason = "no plan was found in time after: " + why;
  if (result.status == Termination::kInfeasible) {
    reason = "no plan is left after: " + why;
    if (result.explanation && !result.explanation->conflicts.empty())
      reason += ". " + result.explanation->conflicts[0].text;
  }
  live->run.Finish(exec::State::kFailed, reason);
}

void Executions::Loop(std::shared_ptr<Live> live) {
  std::unique_lock<std::mutex> lk(live->mu);
  while (!live->shutdown && live->run.state() == exec::State::kRunning) {
    live->poked = false;
    const double now = live->Now();
    bool changed = false;
    if (live->sim)
      for (const auto& r : live->sim->Due(live->run, now)) {
        auto a = ApplyLocked(*live, r);
        if (auto* e = std::get_if<Error>(&a)) spdlog::warn("{}", LogText("execution " + live->id + ": sim report refused: " + e->message));
        changed = true;
      }
    if (live->pending_replan) {
      const std::string why = *live->pending_replan;
      live->pending_replan.reset();
      Replan(live, lk, why);
      continue;
    }
    exec::Decision d = live->run.Advance(now);
    for (const auto& c : d.dispatch) Emit(*live, "dispatched", c.ToJson());
    if (!d.dispatch.empty()) {
      // Stored before sent: a restart never sends a command twice, and a replica that lost its
      // claim (the write conflicts) sends nothing.
      if (!Persist(*live)) continue;
      if (auto sink = SinkFor(*live)) {
        lk.unlock();
        for (const auto& c : d.dispatch) sink->Send(live->id, c.ToJson());
        lk.lock();
      }
      continue;
    }
    if (d.finished) break;
    if (d.replan) {
      Replan(live, lk, *d.replan);
      continue;
    }
    if (changed) continue;
    std::optional<double> wake = live->run.NextWake(now);
    if (live->sim)
      if (auto s = live->sim->NextDue(live->run, now)) wake = wake ? std::min(*wake, *s) : *s;
    auto woken = [&] { return live->shutdown || live->poked || live->pending_replan.has_value(); };
    // With a shared store the claim is renewed a third of a lease after the last write.
    std::optional<long> until_ms;
    if (wake) until_ms = live->origin_ms + static_cast<long>(std::ceil(*wake * 1000.0 / live->speed));
    if (shared_) {
      const long renew = live->persisted_ms + lease_ms_ / 3;
      if (store::NowMs() >= renew) {
        Persist(*live);
        continue;
      }
      until_ms = until_ms ? std::min(*until_ms, renew) : renew;
    }
    if (!until_ms) {
      live->cv.wait(lk, woken);
    } else {
      const auto at = std::chrono::system_clock::time_point(std::chrono::milliseconds(*until_ms));
      live->cv.wait_until(lk, at, woken);
    }
  }
  if (live->shutdown && live->run.state() == exec::State::kRunning) return;  // resumes at the next start
  Emit(*live, "finished", {{"state", exec::StateName(live->run.state())}, {"why", live->run.why()}});
  live->ended = true;
  Persist(*live);
  live->cv.notify_all();
}

void Executions::Launch(std::shared_ptr<Live> live) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    auto& slot = live_[live->id];
    if (slot) retired_.push_back(slot);  // one this replica let go: its thread is joined at the end
    slot = live;
  }
  live->thread = std::thread([this, live] { Loop(live); });
}

std::variant<std::string, Error> Executions::Start(std::shared_ptr<const Domain> d, Json doc, const Json& plan,
                                                   const RequestOptions& options) {
  auto live = std::make_shared<Live>(std::move(d));
  if (auto e = live->run.Adopt(plan, 0)) return *e;
  live->id = RandomHex(16);
  live->adapter = doc.value("adapter", "sim");
  live->speed = doc.value("speed", 1.0);
  live->options = options;
  // How late a report may describe its moment: the sim's are exact; devices' lag a little.
  live->run.SetGrace(live->adapter == "sim" ? 0.0 : std::max(live->domain->time_resolution, 0.2 * live->speed));
  if (live->adapter == "sim") {
    Diagnostics diags;
    auto so = exec::ParseSimOptions(doc.value("sim", Json()), "/sim", diags);
    if (!so) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid sim options", diags);
    live->sim.emplace(*so, live->domain->time_resolution);
  }
  live->origin_ms = store::NowMs();
  doc["execution"] = live->id;
  doc["origin_ms"] = live->origin_ms;
  live->stored.id = live->id;
  live->stored.doc = std::move(doc);
  live->stored.doc["run"] = live->run.ToJson();
  switch (store_->Create(live->stored)) {
    case StoreResult::kOk: break;
    case StoreResult::kFull:
      return Error{ErrorCode::kBusy, "too many executions are stored; delete finished ones", {}};
    default: return StoreFailed(*store_, "retry later");
  }
  Launch(live);
  return live->id;
}

int Executions::Resume(DomainOf domain_of) {
  domain_of_ = std::move(domain_of);
  const int n = Claim(/*at_start=*/true);
  if (shared_ || n < 0) scanner_ = std::thread([this, resumed = n >= 0] { Scan(resumed); });
  return n;
}

// With a shared store, every half lease: the running executions whose claim ran out (their
// replica died) are claimed and carried on here. Until the store could be listed once (it
// failed at start), the resumption at start is tried again at the same pace.
void Executions::Scan(bool resumed) {
  std::unique_lock<std::mutex> lock(scan_mu_);
  while (!scan_stop_) {
    scan_cv_.wait_for(lock, std::chrono::milliseconds(lease_ms_ / 2), [&] { return scan_stop_; });
    if (scan_stop_) break;
    lock.unlock();
    const int claimed = Claim(/*at_start=*/!resumed);
    resumed = resumed || claimed >= 0;
    lock.lock();
    if (resumed && !shared_) break;
  }
}

int Executions::Claim(bool at_start) {
  auto ids = store_->List();
  if (auto* e = std::get_if<Error>(&ids)) {
    spdlog::error("{}", LogText("executions: cannot list the stored ones: " + e->message));
    return -1;
  }
  int claimed = 0;
  for (const auto& id : std::get<std::vector<std::string>>(ids)) {
    if (Find(id)) continue;
    auto got = store_->Get(id);
    auto* s = std::get_if<std::optional<StoredDocument>>(&got);
    if (!s || !*s || (**s).doc.value("run", Json::object()).value("state", "") != "running") continue;
    StoredDocument stored = **s;
    // A file of this process alone (SQLite): what runs in it was this server's before a restart.
    // A shared store: another replica's while its claim lasts.
    if ((shared_ || !at_start) && stored.doc.value("lease_until_ms", 0L) > store::NowMs()) continue;
    auto live = LiveFrom(stored);
    if (!live) continue;
    if (!Persist(*live)) continue;  // another replica claimed it first
    spdlog::info("{}", Json({{"event", "execution_claimed"}, {"execution", id},
                             {"from", stored.doc.value("owner", "")}, {"at_start", at_start}}).dump());
    Launch(live);
    ++claimed;
  }
  return claimed;
}

std::shared_ptr<Executions::Live> Executions::LiveFrom(const StoredDocument& stored) {
  const Json& doc = stored.doc;
  const std::string& id = stored.id;
  auto dom = domain_of_ ? domain_of_(doc) : std::variant<std::shared_ptr<const Domain>, Error>(
                                                Error{ErrorCode::kInternal, "no domain resolver", {}});
  if (auto* e = std::get_if<Error>(&dom)) {
    spdlog::error("{}", LogText("execution " + id + ": cannot resume: " + e->message));
    return nullptr;
  }
  auto live = std::make_shared<Live>(std::get<std::shared_ptr<const Domain>>(dom));
  if (auto e = live->run.FromJson(doc["run"])) {
    spdlog::error("{}", LogText("execution " + id + ": cannot resume: " + e->message));
    return nullptr;
  }
  auto opts = ParseRequestOptions(doc.value("options", Json::object()));
  if (auto* o = std::get_if<RequestOptions>(&opts)) live->options = *o;
  live->id = id;
  live->stored = stored;
  live->adapter = doc.value("adapter", "sim");
  live->speed = doc.value("speed", 1.0);
  live->origin_ms = doc.value("origin_ms", 0L);
  live->replans = doc.value("replans", 0L);
  live->seq = doc.value("seq", 0L);
  live->events = StoredEvents(doc);
  if (live->adapter == "sim") {
    Diagnostics diags;
    auto so = exec::ParseSimOptions(doc.value("sim", Json()), "/sim", diags);
    live->sim.emplace(so.value_or(exec::SimOptions{}), live->domain->time_resolution);
  }
  return live;
}

namespace {

Json View(const std::string& id, const Json& doc, const Json& run, double now, const std::vector<ExecutionEvent>& events) {
  Json v = {{"execution", id},
            {"state", run.value("state", "running")},
            {"now", now},
            {"history", run.value("history", Json::array())},
            {"plan", run.value("plan", Json())},
            {"replans", doc.value("replans", 0L)},
            {"adapter", doc.value("adapter", "sim")},
            {"speed", doc.value("speed", 1.0)},
            {"events", EventsJson(events)}};
  if (!run.value("why", std::string()).empty()) v["why"] = run["why"];
  if (!run.value("blocked", Json::array()).empty()) v["blocked"] = run["blocked"];
  return v;
}


}  // namespace

std::variant<std::vector<Json>, Error> Executions::Histories(const std::string& domain) {
  auto ids = store_->List();
  if (auto* e = std::get_if<Error>(&ids)) return *e;
  std::vector<Json> out;
  for (const auto& id : std::get<std::vector<std::string>>(ids)) {
    if (auto live = Find(id)) {
      std::lock_guard<std::mutex> lk(live->mu);
      if (!live->stored.doc.contains("action_model") && live->stored.doc.value("domain", "") == domain)
        out.push_back(live->run.history());
      continue;
    }
    auto got = store_->Get(id);
    if (auto* e = std::get_if<Error>(&got)) return *e;
    const auto& s = std::get<std::optional<StoredDocument>>(got);
    if (s && !s->doc.contains("action_model") && s->doc.value("domain", "") == domain)
      out.push_back(s->doc.value("run", Json::object()).value("history", Json::array()));
  }
  return out;
}

std::variant<Json, Error> Executions::Get(const std::string& id) {
  if (auto live = Find(id)) {
    std::lock_guard<std::mutex> lk(live->mu);
    Json doc = live->stored.doc;
    doc["replans"] = live->replans;
    return View(id, doc, live->run.ToJson(), live->Now(), live->events);
  }
  auto got = store_->Get(id);
  if (auto* e = std::get_if<Error>(&got)) return *e;
  const auto& s = std::get<std::optional<StoredDocument>>(got);
  if (!s) return NotFound(id);
  const double now = static_cast<double>(store::NowMs() - s->doc.value("origin_ms", 0L)) *
                     s->doc.value("speed", 1.0) / 1000.0;
  return View(id, s->doc, s->doc.value("run", Json::object()), now, StoredEvents(s->doc));
}

std::variant<Json, Error> Executions::Report(const std::string& id, const Json& body) {
  Diagnostics diags;
  auto r = exec::ParseReport(body, "", diags);
  if (!r) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid report", diags);
  auto live = Find(id);
  if (!live) {
    auto got = Get(id);
    if (auto* e = std::get_if<Error>(&got)) return *e;
    const std::string state = std::get<Json>(got).value("state", "?");
    if (state == "running")  // another replica carries it (shared store): only it stores reports
      return Error{ErrorCode::kBusy, "the execution is carried by another replica; send the report again", {}};
    return Error{ErrorCode::kConflict, "the execution has ended (" + state + ")", {}};
  }
  std::lock_guard<std::mutex> lk(live->mu);
  if (live->run.state() != exec::State::kRunning || live->shutdown)
    return Error{ErrorCode::kConflict, std::string("the execution has ended (") + exec::StateName(live->run.state()) + ")", {}};
  auto a = ApplyLocked(*live, *r);
  if (auto* e = std::get_if<Error>(&a)) return *e;
  const auto& applied = std::get<exec::Applied>(a);
  Json out = {{"stored", true}, {"duplicate", applied.duplicate}};
  if (applied.replan) out["replan"] = *applied.replan;
  return out;
}

std::variant<std::shared_ptr<const Domain>, Error> Executions::DomainOfLive(const std::string& id) {
  auto live = Find(id);
  if (!live) {
    auto got = Get(id);
    if (auto* e = std::get_if<Error>(&got)) return *e;
    return Error{ErrorCode::kConflict, "the execution has ended or is carried by another replica", {}};
  }
  std::lock_guard<std::mutex> lk(live->mu);
  if (live->run.state() != exec::State::kRunning)
    return Error{ErrorCode::kConflict, std::string("the execution has ended (") + exec::StateName(live->run.state()) + ")", {}};
  return live->domain;
}

std::optional<Error> Executions::ChangeStatePlan(const std::string& id, const Json& state_plan) {
  auto live = Find(id);
  if (!live) return Error{ErrorCode::kConflict, "the execution has ended or is carried by another replica", {}};
  {
    std::lock_guard<std::mutex> lk(live->mu);
    if (live->run.state() != exec::State::kRunning)
      return Error{ErrorCode::kConflict, std::string("the execution has ended (") + exec::StateName(live->run.state()) + ")", {}};
    const Json before = live->stored.doc["state_plan"];
    live->stored.doc["state_plan"] = state_plan;
    if (!Persist(*live)) {
      live->stored.doc["state_plan"] = before;
      return StoreFailed(*store_, "the new state plan was not taken");
    }
    live->pending_replan = "the state plan changed";
    live->replans_in_a_row = 0;
    live->poked = true;
  }
  live->cv.notify_all();
  return std::nullopt;
}

std::optional<Error> Executions::Stop(const std::string& id) {
  auto live = Find(id);
  if (!live) {
    auto got = Get(id);
    if (auto* e = std::get_if<Error>(&got)) return *e;
    return std::nullopt;  // ended already: nothing to stop
  }
  {
    std::lock_guard<std::mutex> lk(live->mu);
    if (live->run.state() == exec::State::kRunning) live->run.Finish(exec::State::kStopped, "stopped by a client");
    live->cancel = true;
    live->poked = true;
  }
  live->cv.notify_all();
  return std::nullopt;
}

std::variant<std::vector<ExecutionEvent>, Error> Executions::Events(const std::string& id, long after,
                                                                   long wait_ms, bool* ended) {
  auto live = Find(id);
  if (!live) {
    auto got = store_->Get(id);
    if (auto* e = std::get_if<Error>(&got)) return *e;
    const auto& s = std::get<std::optional<StoredDocument>>(got);
    if (!s) return NotFound(id);
    std::vector<ExecutionEvent> out;
    for (auto& e : StoredEvents(s->doc))
      if (e.seq > after) out.push_back(e);
    if (ended) *ended = true;
    return out;
  }
  std::unique_lock<std::mutex> lk(live->mu);
  auto any = [&] { return live->ended || live->shutdown || (!live->events.empty() && live->events.back().seq > after); };
  live->cv.wait_for(lk, std::chrono::milliseconds(wait_ms), any);
  std::vector<ExecutionEvent> out;
  for (const auto& e : live->events)
    if (e.seq > after) out.push_back(e);
  // At shutdown the stream ends too: the client reconnects (Last-Event-ID) where it resumes.
  if (ended) *ended = live->ended || live->shutdown;
  return out;
}

}  // namespace ctb::app
