#include "grpc/grpc_front.h"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <condition_variable>
#include <chrono>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "app/ids.h"
#include "ctburton/v1/planner.grpc.pb.h"
#include "grpc/convert.h"

namespace ctb::grpcfront {

namespace {

using Clock = std::chrono::steady_clock;
using grpc::ServerContext;
using grpc::Status;

std::optional<std::string> ReadFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// "ipv4:127.0.0.1:5000" -> "ipv4:127.0.0.1"; "ipv6:[::1]:5000" -> "ipv6:[::1]".
std::string PeerAddress(const std::string& peer) {
  auto colon = peer.rfind(':');
  return colon == std::string::npos || colon < 5 ? peer : peer.substr(0, colon);
}

// Forwards the core's improving plans to a stream as INTERMEDIATE results.
class StreamObserver : public app::Observer {
 public:
  explicit StreamObserver(grpc::ServerWriter<pb::PlanResult>* w) : w_(w) {}
  void OnSolution(const SolveProgress& progress) override { w_->Write(IntermediateOf(progress)); }

 private:
  grpc::ServerWriter<pb::PlanResult>* w_;
};

class PlannerService final : public pb::Planner::Service {
 public:
  PlannerService(app::Core& core, const app::ApiKeys* keys, int max_streams)
      : core_(core), keys_(keys), max_streams_(max_streams) {}

  Status Solve(ServerContext* c, const pb::SolveRequest* q, pb::PlanResult* r) override {
    return Run(c, "Solve", [&]() -> Status { return DoSolve(c, *q, r, nullptr); });
  }
  Status SolveAnytime(ServerContext* c, const pb::SolveRequest* q,
                      grpc::ServerWriter<pb::PlanResult>* w) override {
    return RunStream(c, "SolveAnytime", [&]() -> Status {
      StreamObserver obs(w);
      pb::PlanResult r;
      Status st = DoSolve(c, *q, &r, &obs);
      if (st.ok()) w->Write(r);
      return st;
    });
  }
  Status Plan(ServerContext* c, const pb::PlanRequest* q, pb::PlanResult* r) override {
    return Run(c, "Plan", [&]() -> Status { return DoPlan(c, *q, r, nullptr); });
  }
  Status PlanAnytime(ServerContext* c, const pb::PlanRequest* q,
                     grpc::ServerWriter<pb::PlanResult>* w) override {
    return RunStream(c, "PlanAnytime", [&]() -> Status {
      StreamObserver obs(w);
      pb::PlanResult r;
      Status st = DoPlan(c, *q, &r, &obs);
      if (st.ok()) w->Write(r);
      return st;
    });
  }
  Status Validate(ServerContext* c, const pb::SolveRequest* q, pb::ValidateResult* r) override {
    return Run(c, "Validate", [&]() -> Status {
      auto call = SolveCallOf(*q);
      auto v = core_.Validate(call);
      if (auto* e = std::get_if<Error>(&v)) return StatusOf(*e);
      r->set_valid(true);
      for (const auto& w : std::get<app::ValidateAnswer>(v).WarningsJson()) FromJson(w, r->add_warnings());
      return Status::OK;
    });
  }
  Status Translate(ServerContext* c, const pb::PlanRequest* q, pb::TranslateResult* r) override {
    return Run(c, "Translate", [&]() -> Status {
      app::TranslateCall call;
      call.domain.name = q->domain();
      call.command = q->command();
      if (q->has_prompting()) call.prompting = q->prompting();
      auto t = core_.Translate(call, Context(c, nullptr));
      if (auto* e = std::get_if<Error>(&t)) return StatusOf(*e);
      const auto& a = std::get<app::TranslateAnswer>(t);
      FromJson(a.state_plan, r->mutable_state_plan());
      r->set_reasoning(a.reasoning);
      for (const auto& w : a.warnings) FromJson(w, r->add_warnings());
      return Status::OK;
    });
  }
  Status ListDomains(ServerContext* c, const pb::ListDomainsRequest*,
                     pb::ListDomainsResult* r) override {
    return Run(c, "ListDomains", [&]() -> Status {
      auto list = core_.ListDomains();
      if (auto* e = std::get_if<Error>(&list)) return StatusOf(*e);
      for (const auto& d : std::get<std::vector<app::DomainInfo>>(list)) {
        auto* x = r->add_domains();
        x->set_name(d.name);
        x->set_description(d.description);
        for (const auto& a : d.automata) x->add_automata(a);
        x->set_source(d.source);
        x->set_version(static_cast<int32_t>(d.version));
      }
      return Status::OK;
    });
  }
  Status GetDomain(ServerContext* c, const pb::GetDomainRequest* q, pb::ActionModel* r) override {
    return Run(c, "GetDomain", [&]() -> Status {
      auto d = core_.GetDomain(q->name(), false);
      if (auto* e = std::get_if<Error>(&d)) return StatusOf(*e);
      if (auto err = FromJson(std::get<Json>(d), r)) return Status(grpc::StatusCode::INTERNAL, *err);
      return Status::OK;
    });
  }
  Status GetDomainDocument(ServerContext* c, const pb::GetDomainRequest* q,
                           pb::DomainDocument* r) override {
    return Run(c, "GetDomainDocument", [&]() -> Status {
      auto d = core_.GetDomain(q->name());
      if (auto* e = std::get_if<Error>(&d)) return StatusOf(*e);
      if (auto err = FromJson(std::get<Json>(d), r->mutable_document()))
        return Status(grpc::StatusCode::INTERNAL, *err);
      return Status::OK;
    });
  }
  Status CreateDomain(ServerContext* c, const pb::DomainDocument* q, pb::DomainName* r) override {
    return Run(c, "CreateDomain", [&]() -> Status {
      auto n = core_.CreateDomain(ToJson(q->document()));
      if (auto* e = std::get_if<Error>(&n)) return StatusOf(*e);
      r->set_name(std::get<std::string>(n));
      return Status::OK;
    });
  }
  Status ReplaceDomain(ServerContext* c, const pb::ReplaceDomainRequest* q, pb::DomainName* r) override {
    return Run(c, "ReplaceDomain", [&]() -> Status {
      if (auto e = core_.ReplaceDomain(q->name(), ToJson(q->document()))) return StatusOf(*e);
      r->set_name(q->name());
      return Status::OK;
    });
  }
  Status DeleteDomain(ServerContext* c, const pb::DeleteDomainRequest* q,
                      pb::DeleteDomainResult*) override {
    return Run(c, "DeleteDomain", [&]() -> Status {
      if (auto e = core_.DeleteDomain(q->name(), q->force())) return StatusOf(*e);
      return Status::OK;
    });
  }
  Status GetDomainDiagram(ServerContext* c, const pb::GetDomainRequest* q, pb::DomainDiagram* r) override {
    return Run(c, "GetDomainDiagram", [&]() -> Status {
      auto svg = core_.DomainDiagram(q->name());
      if (auto* e = std::get_if<Error>(&svg)) return StatusOf(*e);
      r->set_svg(std::get<std::string>(svg));
      return Status::OK;
    });
  }
  Status DraftDomain(ServerContext* c, const pb::DraftDomainRequest* q, pb::DraftDomainResult* r) override {
    return Run(c, "DraftDomain", [&]() -> Status {
      auto d = core_.DraftDomain(q->description(), Context(c, nullptr));
      if (auto* e = std::get_if<Error>(&d)) return StatusOf(*e);
      if (auto err = FromJson(std::get<app::DraftAnswer>(d).document, r))
        return Status(grpc::StatusCode::INTERNAL, *err);
      return Status::OK;
    });
  }
  Status ImportPddl(ServerContext* c, const pb::ImportPddlRequest* q, pb::ImportPddlResult* r) override {
    return Run(c, "ImportPddl", [&]() -> Status {
      auto d = core_.ImportPddl({q->domain(), q->problem(), q->name(), q->store()});
      if (auto* e = std::get_if<Error>(&d)) return StatusOf(*e);
      const auto& a = std::get<app::PddlImportAnswer>(d);
      Json out = a.ToJson();
      if (out["state_plan"].is_null()) out.erase("state_plan");
      if (auto err = FromJson(out, r)) return Status(grpc::StatusCode::INTERNAL, *err);
      return Status::OK;
    });
  }
  Status CheckNetwork(ServerContext* c, const pb::NetworkCheckRequest* q,
                      pb::NetworkCheckResult* r) override {
    return Run(c, "CheckNetwork", [&]() -> Status {
      Json body = ToJson(*q);  // empty lists are left out by the JSON mapping
      if (!body.contains("points")) body["points"] = Json::array();
      if (!body.contains("links")) body["links"] = Json::array();
      for (Json& l : body["links"]) {  // proto3 leaves a 0 bound out; the core requires lb
        if (l.is_object() && !l.contains("lb")) l["lb"] = 0;
      }
      auto v = core_.CheckNetwork(body);
      if (auto* e = std::get_if<Error>(&v)) return StatusOf(*e);
      if (auto err = FromJson(std::get<Json>(v), r)) return Status(grpc::StatusCode::INTERNAL, *err);
      return Status::OK;
    });
  }
  Status GetSession(ServerContext* c, const pb::GetSessionRequest* q, pb::Session* r) override {
    return Run(c, "GetSession", [&]() -> Status {
      auto s = core_.GetSession(q->session());
      if (auto* e = std::get_if<Error>(&s)) return StatusOf(*e);
      FromJson(std::get<Json>(s), r);
      return Status::OK;
    });
  }
  Status DeleteSession(ServerContext* c, const pb::DeleteSessionRequest* q,
                       pb::DeleteSessionResult*) override {
    return Run(c, "DeleteSession", [&]() -> Status {
      if (auto e = core_.DeleteSession(q->session())) return StatusOf(*e);
      return Status::OK;
    });
  }
  Status Replan(ServerContext* c, const pb::ReplanRequest* q, pb::PlanResult* r) override {
    return Run(c, "Replan", [&]() -> Status {
      auto s = core_.Replan(ReplanCallOf(*q), Context(c, nullptr));
      if (auto* e = std::get_if<Error>(&s)) return StatusOf(*e);
      const app::Answer& a = std::get<app::Answer>(s);
      *r = ResultOf(a);
      if (!a.session.empty()) r->set_session(a.session);
      return Status::OK;
    });
  }

  // Executing with the caller as the device side (contract section 14): events out (the
  // `dispatched` ones are the commands), reports in. One thread reads, this one writes.
  Status Execute(ServerContext* c,
                 grpc::ServerReaderWriter<pb::ExecutionEvent, pb::ExecuteMessage>* stream) override {
    return RunStream(c, "Execute", [&]() -> Status {
      pb::ExecuteMessage first;
      if (!stream->Read(&first) || first.kind_case() != pb::ExecuteMessage::kStart)
        return Status(grpc::StatusCode::INVALID_ARGUMENT, "the first message of Execute is an ExecuteStart");
      auto started = core_.StartExecution(ExecuteCallOf(first.start()), Context(c, nullptr));
      if (auto* e = std::get_if<Error>(&started)) return StatusOf(*e);
      const std::string id = std::get<std::string>(started);
      std::mutex write_mu;
      std::mutex done_mu;
      std::condition_variable reader_done;
      bool reading = true;
      auto write = [&](pb::ExecutionEvent& ev) {
        std::lock_guard<std::mutex> lock(write_mu);
        return stream->Write(ev);
      };
      std::thread reader([&] {
        pb::ExecuteMessage m;
        while (stream->Read(&m)) {
          std::variant<Json, Error> r = Error{ErrorCode::kInvalidInput, "after the start, only reports", {}};
          if (m.kind_case() == pb::ExecuteMessage::kReport) r = core_.ReportExecution(id, ReportOf(m.report()));
          if (auto* e = std::get_if<Error>(&r)) {
            pb::ExecutionEvent ev = Refused(id, *e);
            write(ev);
          }
        }
        std::lock_guard<std::mutex> lock(done_mu);
        reading = false;
        reader_done.notify_all();
      });
      long after = 0;
      bool ended = false;
      while (!ended && !c->IsCancelled()) {
        auto events = core_.ExecutionEvents(id, after, 500, &ended);
        if (std::holds_alternative<Error>(events)) break;
        bool written = true;
        for (const auto& e : std::get<std::vector<app::ExecutionEvent>>(events)) {
          pb::ExecutionEvent ev;
          ev.set_execution(id);
          ev.set_seq(e.seq);
          ev.set_event(e.name);
          FromJson(e.data, ev.mutable_data());
          after = e.seq;
          if (!(written = write(ev))) break;
        }
        if (!written) break;
      }
      if (!ended) core_.StopExecution(id);  // the device side went away: nothing can carry it on
      {
        // The caller closes its side once it has read `finished`; one that does not is cut off.
        std::unique_lock<std::mutex> lock(done_mu);
        if (!reader_done.wait_for(lock, std::chrono::seconds(2), [&] { return !reading; })) c->TryCancel();
      }
      reader.join();
      return ended ? Status::OK : Status(grpc::StatusCode::CANCELLED, "the execution was stopped");
    });
  }

  int in_flight() const { return in_flight_; }

 private:
  app::CallContext Context(ServerContext* c, app::Observer* obs) {
    app::CallContext ctx;
    ctx.observer = obs;
    ctx.request_id = app::RandomHex(8);
    const auto deadline = c->deadline();
    ctx.cancelled = [c, deadline]() {
      return c->IsCancelled() || std::chrono::system_clock::now() > deadline;
    };
    return ctx;
  }

  app::SolveCall SolveCallOf(const pb::SolveRequest& q) {
    app::SolveCall call;
    if (q.model_case() == pb::SolveRequest::kDomain) call.domain.name = q.domain();
    if (q.model_case() == pb::SolveRequest::kActionModel) call.domain.action_model = ToJson(q.action_model());
    if (q.has_state_plan()) call.state_plan = ToJson(q.state_plan());
    if (q.has_options()) call.options = OptionsOf(q.options());
    return call;
  }

  // The request as the JSON body of POST /replan: proto3's JSON mapping leaves out zero values,
  // so `now` and each observation's `since` are written explicitly, and a trajectory's timelines
  // lose their wrapper.
  static app::ExecutionCall ExecuteCallOf(const pb::ExecuteStart& q) {
    app::ExecutionCall call;
    call.adapter = "grpc";
    if (q.has_session()) call.session = q.session();
    if (q.has_domain()) call.domain.name = q.domain();
    if (q.has_action_model()) call.domain.action_model = ToJson(q.action_model());
    if (q.has_state_plan()) call.state_plan = ToJson(q.state_plan());
    if (q.has_trajectory()) call.trajectory = ToJson(q.trajectory());
    call.speed = q.speed() == 0 ? 1 : q.speed();
    if (q.has_options()) call.options = OptionsOf(q.options());
    call.replan = !q.no_replan();
    return call;
  }

  // The report as contract 14's JSON (time always present, even 0).
  static Json ReportOf(const pb::ExecutionReport& r) {
    Json j = {{"automaton", r.automaton()}, {"time", r.time()}};
    if (r.has_location()) j["location"] = r.location();
    if (r.has_failed()) j["failed"] = r.failed();
    return j;
  }

  static pb::ExecutionEvent Refused(const std::string& id, const Error& e) {
    pb::ExecutionEvent ev;
    ev.set_execution(id);
    ev.set_event("refused");
    Json data = {{"code", CodeName(e.code)}, {"message", e.message}};
    if (!e.details.empty()) data["path"] = e.details[0].pointer.empty() ? "/" : e.details[0].pointer;
    FromJson(data, ev.mutable_data());
    return ev;
  }

  app::ReplanCall ReplanCallOf(const pb::ReplanRequest& q) {
    app::ReplanCall call;
    if (q.has_session()) call.session = q.session();
    if (q.has_command()) call.command = q.command();
    if (q.has_domain()) call.domain.name = q.domain();
    if (q.has_action_model()) call.domain.action_model = ToJson(q.action_model());
    if (q.has_state_plan()) call.state_plan = ToJson(q.state_plan());
    Json body = ToJson(q);
    Json request = Json::object();
    request["now"] = q.now();
    for (const char* k : {"executed", "blocked"})
      if (body.contains(k)) request[k] = body[k];
    if (q.observed_size() > 0) {
      request["observed"] = Json::object();
      for (const auto& [name, ob] : q.observed()) {
        request["observed"][name] = {{"location", ob.location()}};
        if (ob.has_since()) request["observed"][name]["since"] = ob.since();
      }
    }
    if (q.has_trajectory()) {
      Json t = ToJson(q.trajectory());
      if (t.contains("timelines") && t["timelines"].is_object())
        for (auto& [name, tl] : t["timelines"].items()) tl = tl.value("segments", Json::array());
      // The mapping also leaves out a transition's time 0 and writes its int64 event as a string.
      for (int i = 0; i < q.trajectory().transitions_size(); ++i) {
        const auto& tr = q.trajectory().transitions(i);
        t["transitions"][i]["time"] = tr.time();
        if (tr.event() > 0) t["transitions"][i]["event"] = tr.event();
        else t["transitions"][i].erase("event");
      }
      request["trajectory"] = t;
    }
    call.request = request;
    if (q.has_options()) {
      const auto& o = q.options();
      if (o.has_objective()) call.options.objective = o.objective();
      if (o.has_time_limit_ms()) call.options.time_limit_ms = o.time_limit_ms();
      if (o.has_horizon()) call.options.horizon = o.horizon();
      if (o.has_max_horizon()) call.options.max_horizon = o.max_horizon();
      if (o.has_keep()) call.keep = o.keep();
    }
    return call;
  }

  Status DoSolve(ServerContext* c, const pb::SolveRequest& q, pb::PlanResult* r,
                 app::Observer* obs) {
    auto s = core_.Solve(SolveCallOf(q), Context(c, obs));
    if (auto* e = std::get_if<Error>(&s)) return StatusOf(*e);
    *r = ResultOf(std::get<app::Answer>(s));
    return Status::OK;
  }

  Status DoPlan(ServerContext* c, const pb::PlanRequest& q, pb::PlanResult* r, app::Observer* obs) {
    app::PlanCall call;
    if (!q.domain().empty()) call.domain = q.domain();
    call.command = q.command();
    if (q.has_prompting()) call.prompting = q.prompting();
    if (q.has_session()) call.session = q.session();
    if (q.has_options()) call.options = OptionsOf(q.options());
    auto p = core_.Plan(call, Context(c, obs));
    if (auto* e = std::get_if<Error>(&p)) return StatusOf(*e);
    const auto& a = std::get<app::PlanAnswer>(p);
    *r = ResultOf(a.answer);
    r->set_session(a.session);
    r->set_reasoning(a.translation.reasoning);
    FromJson(a.translation.state_plan, r->mutable_state_plan());
    for (const auto& w : a.translation.warnings) FromJson(w, r->add_warnings());
    return Status::OK;
  }

  bool Authorized(ServerContext* c) {
    if (!keys_) return true;
    const auto& md = c->client_metadata();
    auto it = md.find("authorization");
    if (it == md.end()) return false;
    return keys_->CheckHeader(std::string(it->second.data(), it->second.size()));
  }

  // Access control, in-flight count, metrics and a log line around one call.
  template <typename F>
  Status Run(ServerContext* c, const char* method, F&& fn) {
    const auto t0 = Clock::now();
    ++in_flight_;
    Status st = Authorized(c) ? fn()
                              : Status(grpc::StatusCode::UNAUTHENTICATED,
                                       "this server needs an API key: send metadata "
                                       "\"authorization: Bearer KEY\"");
    --in_flight_;
    const double secs = std::chrono::duration<double>(Clock::now() - t0).count();
    const std::string route = std::string("grpc:") + method;
    core_.metrics().Request(route, static_cast<int>(st.error_code()), secs);
    spdlog::info("{}", Json({{"event", "grpc_call"}, {"method", method}, {"peer", c->peer()},
                             {"code", static_cast<int>(st.error_code())},
                             {"ms", std::lround(secs * 1000)}})
                           .dump(-1, ' ', false, Json::error_handler_t::replace));
    return st;
  }

  // Run() for streaming calls, within the per-client cap.
  template <typename F>
  Status RunStream(ServerContext* c, const char* method, F&& fn) {
    const std::string peer = PeerAddress(c->peer());
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (streams_[peer] >= max_streams_)
        return Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      "too many streaming calls from this client at once (limit " +
                          std::to_string(max_streams_) + ")");
      ++streams_[peer];
    }
    Status st = Run(c, method, fn);
    std::lock_guard<std::mutex> lock(mu_);
    if (--streams_[peer] == 0) streams_.erase(peer);
    return st;
  }

  app::Core& core_;
  const app::ApiKeys* keys_;
  const int max_streams_;
  std::atomic<int> in_flight_{0};
  std::mutex mu_;
  std::map<std::string, int> streams_;
};

}  // namespace

struct GrpcFrontEnd::Impl {
  std::unique_ptr<PlannerService> service;
  std::unique_ptr<grpc::Server> server;
  int port = 0;
  std::once_flag shutdown_once;
  std::thread shutdown_thread;
};

GrpcFrontEnd::GrpcFrontEnd(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

GrpcFrontEnd::~GrpcFrontEnd() { Wait(); }

std::variant<std::unique_ptr<GrpcFrontEnd>, std::string> GrpcFrontEnd::Start(
    const GrpcOptions& o, app::Core& core, const app::ApiKeys* keys) {
  std::shared_ptr<grpc::ServerCredentials> creds = grpc::InsecureServerCredentials();
  if (!o.tls_cert.empty()) {
    auto cert = ReadFile(o.tls_cert), key = ReadFile(o.tls_key);
    if (!cert) return "cannot read the gRPC TLS certificate " + o.tls_cert;
    if (!key) return "cannot read the gRPC TLS key " + o.tls_key;
    grpc::SslServerCredentialsOptions ssl;
    ssl.pem_key_cert_pairs.push_back({*key, *cert});
    creds = grpc::SslServerCredentials(ssl);
  }
  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  auto impl = std::make_unique<Impl>();
  impl->service = std::make_unique<PlannerService>(core, keys, o.max_streams_per_client);
  grpc::ServerBuilder b;
  const std::string host = o.host.find(':') != std::string::npos ? "[" + o.host + "]" : o.host;
  b.AddListeningPort(host + ":" + std::to_string(o.port), creds, &impl->port);
  b.RegisterService(impl->service.get());
  b.SetMaxReceiveMessageSize(static_cast<int>(o.max_message_bytes));
  impl->server = b.BuildAndStart();
  if (!impl->server || impl->port == 0)
    return "cannot serve gRPC on " + o.host + ":" + std::to_string(o.port);
  auto* health = impl->server->GetHealthCheckService();
  if (health) health->SetServingStatus("ctburton.v1.Planner", true);
  return std::unique_ptr<GrpcFrontEnd>(new GrpcFrontEnd(std::move(impl)));
}

int GrpcFrontEnd::port() const { return impl_->port; }
int GrpcFrontEnd::InFlight() const { return impl_->service->in_flight(); }

void GrpcFrontEnd::BeginShutdown() {
  std::call_once(impl_->shutdown_once, [this] {
    if (auto* health = impl_->server->GetHealthCheckService()) health->Shutdown();
    // Shutdown() waits for running calls up to the deadline, then cancels them: on a thread of
    // its own so that the caller can drain the HTTP side meanwhile.
    impl_->shutdown_thread = std::thread([this] {
      impl_->server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(10));
    });
  });
}

void GrpcFrontEnd::Wait() {
  BeginShutdown();
  if (impl_->shutdown_thread.joinable()) impl_->shutdown_thread.join();
  impl_->server->Wait();
}

}  // namespace ctb::grpcfront
