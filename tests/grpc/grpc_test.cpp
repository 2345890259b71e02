// The gRPC front end (contract section 10) against the real server binary with the real
// minizinc: statuses, streams, errors with pointers, deadlines and cancels that kill the solver,
// health, reflection, API keys, and the same answer as HTTP.
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <google/protobuf/util/json_util.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "ctburton/v1/planner.grpc.pb.h"
#include "google/rpc/error_details.pb.h"
#include "google/rpc/status.pb.h"
#include "grpc/health/v1/health.grpc.pb.h"
#include "grpc/reflection/v1alpha/reflection.grpc.pb.h"
#include "tests/server/harness.h"

namespace {

namespace pb = ::ctburton::v1;
using ctb::testing::FreeLoopbackPort;
using ctb::testing::ServerProcess;
using nlohmann::json;

std::string Src() { return CTB_TEST_SOURCE_DIR; }

json ReadJson(const std::string& rel) {
  std::ifstream in(Src() + "/" + rel);
  return json::parse(in);
}

template <typename M>
M FromJson(const json& j) {
  M m;
  google::protobuf::util::JsonParseOptions o;
  EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(j.dump(), &m, o).ok()) << j.dump();
  return m;
}

// A message as JSON (protobuf's JSON mapping).
json ToJson(const google::protobuf::Message& m) {
  std::string out;
  EXPECT_TRUE(google::protobuf::util::MessageToJsonString(m, &out).ok());
  return json::parse(out);
}

// A server with both front ends; extra flags as given.
struct GrpcServer {
  explicit GrpcServer(std::vector<std::string> args = {}, json config = json::object())
      : grpc_port(FreeLoopbackPort()),
        proc(config, Args(args, grpc_port)),
        channel(grpc::CreateChannel("127.0.0.1:" + std::to_string(grpc_port),
                                    grpc::InsecureChannelCredentials())),
        stub(pb::Planner::NewStub(channel)) {
    EXPECT_TRUE(channel->WaitForConnected(std::chrono::system_clock::now() + std::chrono::seconds(10)));
  }
  static std::vector<std::string> Args(std::vector<std::string> a, int port) {
    a.push_back("--grpc-port");
    a.push_back(std::to_string(port));
    return a;
  }
  int grpc_port;
  ServerProcess proc;
  std::shared_ptr<grpc::Channel> channel;
  std::unique_ptr<pb::Planner::Stub> stub;
};

void Deadline(grpc::ClientContext& c, int ms) {
  c.set_deadline(std::chrono::system_clock::now() + std::chrono::milliseconds(ms));
}

pb::SolveRequest SolveOf(const std::string& domain, const std::string& plan_file,
                         const std::string& objective, int time_limit_ms = 30000,
                         int max_horizon = -1) {
  pb::SolveRequest q;
  q.set_domain(domain);
  *q.mutable_state_plan() = FromJson<pb::StatePlan>(ReadJson(plan_file));
  q.mutable_options()->set_objective(objective);
  q.mutable_options()->set_time_limit_ms(time_limit_ms);
  if (max_horizon > 0) q.mutable_options()->set_max_horizon(max_horizon);
  return q;
}

// Assembly, C onto A from a tower, fastest, up to 64 events: its proof runs to the time limit.
pb::SolveRequest LongSolve() {
  return SolveOf("assembly", "tests/data/slow_c_on_a.json", "makespan", 60000, 64);
}

// Waits up to `ms` for the server to have no solver child; true when it has none.
bool SolversGone(const ServerProcess& p, int ms) {
  for (int i = 0; i < ms / 50; ++i) {
    if (p.Children("minizinc").empty() && p.Children("fzn-gecode").empty()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

bool SolverRunning(const ServerProcess& p, int ms) {
  for (int i = 0; i < ms / 50; ++i) {
    if (!p.Children("minizinc").empty() || !p.Children("fzn-gecode").empty()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

TEST(Grpc, SolveAShippedExampleOptimally) {
  GrpcServer s;
  grpc::ClientContext c;
  pb::PlanResult r;
  auto st = s.stub->Solve(&c, SolveOf("presentation", "config/examples/presentation/test1_cot.json", "makespan"), &r);
  ASSERT_TRUE(st.ok()) << st.error_message();
  EXPECT_EQ(r.status(), pb::SOLVED_OPTIMALLY);
  EXPECT_TRUE(r.trajectory().verified());
  EXPECT_EQ(r.trajectory().status(), "optimal");
  EXPECT_GT(r.trajectory().transitions_size(), 3);
  EXPECT_EQ(r.trajectory().timelines().count("proj"), 1u);
  EXPECT_GT(r.trajectory().timelines().at("proj").segments_size(), 1);
  EXPECT_TRUE(r.objective().has_number_value());
  EXPECT_EQ(r.objective().number_value(), r.trajectory().goal_reached_at());
  EXPECT_FALSE(r.metrics().at("solver").empty());
  EXPECT_GT(r.state_plan_summary_size(), 0);
}

// Action events (contract section 15) cross the proto: the computer boots (15 s) before the
// projector starts warming up (30 s).
TEST(Grpc, AStatePlanWithAnOrderedActionSolves) {
  GrpcServer s;
  grpc::ClientContext c;
  pb::PlanResult r;
  auto st = s.stub->Solve(&c, SolveOf("presentation", "config/examples/presentation/actions.json", "makespan"), &r);
  ASSERT_TRUE(st.ok()) << st.error_message();
  EXPECT_EQ(r.status(), pb::SOLVED_OPTIMALLY);
  EXPECT_TRUE(r.trajectory().verified());
  EXPECT_EQ(r.objective().number_value(), 15 + 30);
  ASSERT_EQ(r.trajectory().temporal().count("BootThenWarm"), 1u);
  EXPECT_EQ(r.trajectory().temporal().at("BootThenWarm").event1(), 15);
  EXPECT_EQ(r.trajectory().temporal().at("BootThenWarm").event2(), 15);
  bool said = false;
  for (const auto& line : r.state_plan_summary())
    said = said || line.pointer() == "/constraints/temporal/BootThenWarm";
  EXPECT_TRUE(said);
}

TEST(Grpc, AnInfeasibleExampleIsUnsolvableWithItsExplanation) {
  GrpcServer s;
  grpc::ClientContext c;
  pb::PlanResult r;
  auto st = s.stub->Solve(&c, SolveOf("presentation", "tests/data/deadline_infeasible.json", "cost"), &r);
  ASSERT_TRUE(st.ok()) << st.error_message();
  EXPECT_TRUE(r.status() == pb::UNSOLVABLE_PROVEN || r.status() == pb::UNSOLVABLE_INCOMPLETELY);
  EXPECT_EQ(r.trajectory().status(), "infeasible");
  ASSERT_GT(r.explanation().conflicts_size(), 0);
  EXPECT_GT(r.explanation().conflicts(0).constraints_size(), 0);
  EXPECT_FALSE(r.explanation().conflicts(0).text().empty());
  // The proof's reach is stated, and agrees with the status.
  const std::string reach = r.metrics().at("infeasible_for");
  EXPECT_EQ(r.status() == pb::UNSOLVABLE_PROVEN, reach == "any_horizon") << reach;
}

TEST(Grpc, SolveAnytimeStreamsImprovingPlansThenTheFinalResult) {
  GrpcServer s;
  grpc::ClientContext c;
  Deadline(c, 60000);
  auto reader = s.stub->SolveAnytime(&c, SolveOf("search_rescue", "config/examples/search_rescue/test1.json", "makespan"));
  std::vector<pb::PlanResult> all;
  pb::PlanResult r;
  while (reader->Read(&r)) all.push_back(r);
  auto st = reader->Finish();
  ASSERT_TRUE(st.ok()) << st.error_message();
  ASSERT_GE(all.size(), 2u);
  for (size_t i = 0; i + 1 < all.size(); ++i) EXPECT_EQ(all[i].status(), pb::INTERMEDIATE);
  EXPECT_EQ(all.back().status(), pb::SOLVED_OPTIMALLY);
  // Each improving plan is no worse than the one before, and the last one is the answer.
  double prev = 1e18;
  for (size_t i = 0; i + 1 < all.size(); ++i) {
    ASSERT_TRUE(all[i].objective().has_number_value());
    EXPECT_LE(all[i].objective().number_value(), prev);
    prev = all[i].objective().number_value();
  }
  EXPECT_EQ(all.back().objective().number_value(), prev);
}

TEST(Grpc, PlanAnytimeFromTheRecordingsInDemoMode) {
  GrpcServer s({"--demo"});
  grpc::ClientContext c;
  Deadline(c, 90000);
  pb::PlanRequest q;
  q.set_domain("presentation");
  q.set_command(
      "The computer and projector start in the off state, and the connection is disconnected. The "
      "projector should turn on and stay on for 1800 seconds, following which everything should "
      "turn off within 600 seconds. In addition, the projector should turn on within 60 seconds.");
  auto reader = s.stub->PlanAnytime(&c, q);
  std::vector<pb::PlanResult> all;
  pb::PlanResult r;
  while (reader->Read(&r)) all.push_back(r);
  auto st = reader->Finish();
  ASSERT_TRUE(st.ok()) << st.error_message();
  ASSERT_FALSE(all.empty());
  const auto& last = all.back();
  EXPECT_TRUE(last.status() == pb::SOLVED_OPTIMALLY || last.status() == pb::SOLVED_SATISFICING);
  EXPECT_FALSE(last.session().empty());
  EXPECT_FALSE(last.reasoning().empty());
  EXPECT_EQ(last.state_plan().initial_state().at("proj"), "projOff");
  EXPECT_TRUE(last.trajectory().verified());
  // The session is there, over gRPC as over HTTP.
  grpc::ClientContext c2;
  pb::GetSessionRequest gq;
  gq.set_session(last.session());
  pb::Session sess;
  ASSERT_TRUE(s.stub->GetSession(&c2, gq, &sess).ok());
  EXPECT_EQ(sess.domain(), "presentation");
  EXPECT_EQ(sess.turns().values_size(), 1);
}

TEST(Grpc, ValidateNamesEveryErrorByItsPointer) {
  GrpcServer s;
  json plan = ReadJson("config/examples/presentation/test1_cot.json");
  plan["end_state"]["goal_constraint"] = "projl[i+1]==projOnn";
  plan["initial_state"]["comp"] = "compNowhere";
  pb::SolveRequest q;
  q.set_domain("presentation");
  *q.mutable_state_plan() = FromJson<pb::StatePlan>(plan);
  grpc::ClientContext c;
  pb::ValidateResult r;
  auto st = s.stub->Validate(&c, q, &r);
  ASSERT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(st.error_message().find("/state_plan/end_state/goal_constraint"), std::string::npos)
      << st.error_message();
  google::rpc::Status details;
  ASSERT_TRUE(details.ParseFromString(st.error_details()));
  ASSERT_EQ(details.details_size(), 1);
  google::rpc::BadRequest bad;
  ASSERT_TRUE(details.details(0).UnpackTo(&bad));
  std::set<std::string> fields;
  for (const auto& v : bad.field_violations()) fields.insert(v.field());
  EXPECT_TRUE(fields.count("/state_plan/end_state/goal_constraint")) << bad.DebugString();
  EXPECT_TRUE(fields.count("/state_plan/initial_state/comp")) << bad.DebugString();
  // A valid plan validates.
  pb::SolveRequest ok;
  ok.set_domain("presentation");
  *ok.mutable_state_plan() = FromJson<pb::StatePlan>(ReadJson("config/examples/presentation/test1_cot.json"));
  grpc::ClientContext c2;
  ASSERT_TRUE(s.stub->Validate(&c2, ok, &r).ok());
  EXPECT_TRUE(r.valid());
  // Unknown domain and bad options are errors too.
  ok.set_domain("nosuch");
  grpc::ClientContext c3;
  EXPECT_EQ(s.stub->Validate(&c3, ok, &r).error_code(), grpc::StatusCode::NOT_FOUND);
  pb::SolveRequest bad_opts = SolveOf("presentation", "config/examples/presentation/test1_cot.json", "fastest");
  grpc::ClientContext c4;
  pb::PlanResult pr;
  auto st4 = s.stub->Solve(&c4, bad_opts, &pr);
  EXPECT_EQ(st4.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(st4.error_message().find("/options/objective"), std::string::npos);
}

// Domains through the API (contract section 12) over gRPC: the same calls as HTTP's /domains.
// CheckNetwork (contract section 13): A ==[1,3]==> C, C -[-2,-1]-> B is consistent but neither
// strongly nor dynamically controllable (B must precede C by 1 to 2 before C is seen); with
// C -[0,1]-> B it is dynamic but not strong. An unknown point is INVALID_ARGUMENT at its pointer.
TEST(Grpc, CheckNetworkAnswersLikeHttp) {
  GrpcServer s;
  pb::NetworkCheckRequest q;
  for (const char* p : {"A", "B", "C"}) q.add_points(p);
  pb::NetworkLink* ac = q.add_links();
  ac->set_from("A");
  ac->set_to("C");
  ac->set_lb(1);
  ac->set_ub(3);
  ac->set_contingent(true);
  pb::NetworkLink* cb = q.add_links();
  cb->set_from("C");
  cb->set_to("B");
  cb->set_lb(-2);
  cb->set_ub(-1);
  grpc::ClientContext c;
  pb::NetworkCheckResult r;
  ASSERT_TRUE(s.stub->CheckNetwork(&c, q, &r).ok());
  EXPECT_TRUE(r.consistent());
  EXPECT_FALSE(r.strong());
  EXPECT_FALSE(r.dynamic());
  ASSERT_EQ(r.conflict_size(), 2);
  EXPECT_EQ(r.conflict(0), 0);
  EXPECT_EQ(r.conflict(1), 1);
  cb->set_lb(0);
  cb->set_ub(1);
  grpc::ClientContext c2;
  ASSERT_TRUE(s.stub->CheckNetwork(&c2, q, &r).ok());
  EXPECT_TRUE(r.dynamic());
  EXPECT_FALSE(r.strong());
  cb->set_to("D");
  grpc::ClientContext c3;
  auto st = s.stub->CheckNetwork(&c3, q, &r);
  EXPECT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(st.error_message().find("/links/1/to"), std::string::npos) << st.error_message();
}

// ImportPddl (issue 32 item 5): the same model as HTTP POST /domains/import-pddl; a problem in the
// domain text is INVALID_ARGUMENT naming /domain and the line.
TEST(Grpc, ImportPddlGivesTheSameModelAsHttp) {
  GrpcServer s;
  auto text = [](const std::string& f) {
    std::ifstream in(Src() + "/tests/interchange/pddl/" + f);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  pb::ImportPddlRequest q;
  q.set_domain(text("search_rescue_domain.pddl"));
  q.set_problem(text("search_rescue_problem.pddl"));
  grpc::ClientContext c;
  pb::ImportPddlResult r;
  ASSERT_TRUE(s.stub->ImportPddl(&c, q, &r).ok());
  auto http = s.proc.Client().Post("/domains/import-pddl", json({{"domain", q.domain()}, {"problem", q.problem()}}).dump(),
                                   "application/json");
  ASSERT_TRUE(http);
  ASSERT_EQ(http->status, 200) << http->body;
  const json h = json::parse(http->body);
  EXPECT_EQ(ToJson(r.action_model()), h["action_model"]);
  EXPECT_EQ(ToJson(r.state_plan()), h["state_plan"]);
  EXPECT_EQ(r.ground_actions(), h["ground_actions"].get<long>());
  EXPECT_EQ(r.actions_size(), static_cast<int>(h["actions"].size()));
  EXPECT_FALSE(r.stored());
  q.set_domain("(define (domain d) (:frobnicate))");
  grpc::ClientContext c2;
  auto st = s.stub->ImportPddl(&c2, q, &r);
  EXPECT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(st.error_message().find("domain.pddl:1:"), std::string::npos) << st.error_message();
}

TEST(Grpc, DomainsAreCreatedReadDrawnUsedAndDeleted) {
  const std::string data = "/tmp/ctb-grpc-domains-" + std::to_string(getpid());
  GrpcServer s({"--data-dir", data});
  const json drones = ReadJson("config/templates/drones.json");
  pb::DomainDocument doc;
  *doc.mutable_document() = FromJson<google::protobuf::Struct>(drones);
  grpc::ClientContext c1;
  pb::DomainName name;
  ASSERT_TRUE(s.stub->CreateDomain(&c1, doc, &name).ok());
  EXPECT_EQ(name.name(), "drones");
  grpc::ClientContext c2;
  EXPECT_EQ(s.stub->CreateDomain(&c2, doc, &name).error_code(), grpc::StatusCode::ABORTED);
  // A bad document: INVALID_ARGUMENT, the template's pointer as the field.
  json bad = drones;
  bad["automata"][0]["transitions"][1]["guard"] = "{self}l[i]==nowhere";
  pb::DomainDocument bad_doc;
  *bad_doc.mutable_document() = FromJson<google::protobuf::Struct>(bad);
  grpc::ClientContext c3;
  auto st = s.stub->CreateDomain(&c3, bad_doc, &name);
  ASSERT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(st.error_message().find("/automata/0/transitions/1"), std::string::npos) << st.error_message();
  // As written, and as plain automata.
  pb::GetDomainRequest get;
  get.set_name("drones");
  grpc::ClientContext c4;
  pb::DomainDocument written;
  ASSERT_TRUE(s.stub->GetDomainDocument(&c4, get, &written).ok());
  std::string text;
  google::protobuf::util::JsonPrintOptions po;
  po.preserve_proto_field_names = true;
  ASSERT_TRUE(google::protobuf::util::MessageToJsonString(written.document(), &text, po).ok());
  EXPECT_EQ(json::parse(text), drones);
  grpc::ClientContext c5;
  pb::ActionModel plain;
  ASSERT_TRUE(s.stub->GetDomain(&c5, get, &plain).ok());
  ASSERT_EQ(plain.automata_size(), 3);
  EXPECT_EQ(plain.automata(0).name(), "drone1");
  grpc::ClientContext c6;
  pb::DomainDiagram svg;
  ASSERT_TRUE(s.stub->GetDomainDiagram(&c6, get, &svg).ok());
  EXPECT_EQ(svg.svg().rfind("<svg", 0), 0u);
  EXPECT_NE(svg.svg().find("hangarDoor"), std::string::npos);
  grpc::ClientContext c7;
  pb::ListDomainsResult list;
  ASSERT_TRUE(s.stub->ListDomains(&c7, pb::ListDomainsRequest(), &list).ok());
  ASSERT_EQ(list.domains_size(), 4);
  int stored = 0;
  for (const auto& d : list.domains()) stored += d.source() == "stored" && d.version() == 1;
  EXPECT_EQ(stored, 1);
  // Solved by name like a shipped domain.
  json plan = {{"initial_state", {{"drone1", "inHangar"}, {"drone2", "inHangar"}, {"hangarDoor", "closed"}}},
               {"end_state", {{"maintenance_constraint", "true"},
                              {"goal_constraint", "drone1l[i+1]==atA /\\ drone2l[i+1]==atB"}}},
               {"constraints", {{"episodes", json::object()}, {"temporal", json::object()}, {"event", json::object()}}}};
  pb::SolveRequest q;
  q.set_domain("drones");
  *q.mutable_state_plan() = FromJson<pb::StatePlan>(plan);
  q.mutable_options()->set_objective("makespan");
  grpc::ClientContext c8;
  pb::PlanResult r;
  auto solved = s.stub->Solve(&c8, q, &r);
  ASSERT_TRUE(solved.ok()) << solved.error_message();
  EXPECT_EQ(r.status(), pb::SOLVED_OPTIMALLY);
  EXPECT_EQ(r.trajectory().goal_reached_at(), 28);
  // Replaced with four drones; a shipped domain stays.
  json four = drones;
  four["parameters"]["N"] = 4;
  pb::ReplaceDomainRequest rep;
  rep.set_name("drones");
  *rep.mutable_document() = FromJson<google::protobuf::Struct>(four);
  grpc::ClientContext c9;
  ASSERT_TRUE(s.stub->ReplaceDomain(&c9, rep, &name).ok());
  grpc::ClientContext c10;
  ASSERT_TRUE(s.stub->GetDomain(&c10, get, &plain).ok());
  EXPECT_EQ(plain.automata_size(), 5);
  pb::DeleteDomainRequest del;
  del.set_name("presentation");
  grpc::ClientContext c11;
  pb::DeleteDomainResult gone;
  EXPECT_EQ(s.stub->DeleteDomain(&c11, del, &gone).error_code(), grpc::StatusCode::ABORTED);
  del.set_name("drones");
  grpc::ClientContext c12;
  EXPECT_TRUE(s.stub->DeleteDomain(&c12, del, &gone).ok());
  grpc::ClientContext c13;
  EXPECT_EQ(s.stub->DeleteDomain(&c13, del, &gone).error_code(), grpc::StatusCode::NOT_FOUND);
  std::filesystem::remove_all(data);
}

TEST(Grpc, AClientDeadlineKillsTheSolverWithinASecond) {
  GrpcServer s;
  grpc::ClientContext c;
  Deadline(c, 2000);
  pb::PlanResult r;
  auto t0 = std::chrono::steady_clock::now();
  auto st = s.stub->Solve(&c, LongSolve(), &r);
  EXPECT_EQ(st.error_code(), grpc::StatusCode::DEADLINE_EXCEEDED);
  EXPECT_TRUE(SolversGone(s.proc, 1500)) << "a solver outlived its client's deadline";
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
  EXPECT_TRUE(s.proc.Alive());
}

TEST(Grpc, CancelMidStreamKillsTheSolver) {
  GrpcServer s;
  grpc::ClientContext c;
  auto reader = s.stub->SolveAnytime(&c, LongSolve());
  pb::PlanResult r;
  ASSERT_TRUE(reader->Read(&r));  // the first improving plan: the solve is under way
  EXPECT_EQ(r.status(), pb::INTERMEDIATE);
  ASSERT_TRUE(SolverRunning(s.proc, 5000));
  c.TryCancel();
  while (reader->Read(&r)) {
  }
  EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::CANCELLED);
  EXPECT_TRUE(SolversGone(s.proc, 1500)) << "a solver outlived its cancelled stream";
}

// A busy refusal says when to try again, as HTTP's Retry-After does: RESOURCE_EXHAUSTED with a
// google.rpc.RetryInfo of 2 s (seen without one by bench/soak.py).
TEST(Grpc, ABusyRefusalSaysWhenToRetry) {
  GrpcServer s({}, {{"solver_workers", 1}, {"solver_queue", 0}});
  grpc::ClientContext hold;
  auto reader = s.stub->SolveAnytime(&hold, LongSolve());
  pb::PlanResult first;
  ASSERT_TRUE(reader->Read(&first)) << "the long solve holds the one solver place once it reports";
  grpc::ClientContext c;
  pb::PlanResult r;
  auto st = s.stub->Solve(&c, SolveOf("presentation", "config/examples/presentation/test1_cot.json", "cost"), &r);
  ASSERT_EQ(st.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << st.error_message();
  google::rpc::Status details;
  ASSERT_TRUE(details.ParseFromString(st.error_details()));
  google::rpc::RetryInfo info;
  bool found = false;
  for (const auto& d : details.details())
    if (d.Is<google::rpc::RetryInfo>()) found = d.UnpackTo(&info);
  ASSERT_TRUE(found) << "no RetryInfo in the status details";
  EXPECT_EQ(info.retry_delay().seconds(), 2);
  hold.TryCancel();
  while (reader->Read(&first)) {
  }
  reader->Finish();
}

TEST(Grpc, HealthAndReflectionAreOn) {
  GrpcServer s;
  auto health = grpc::health::v1::Health::NewStub(s.channel);
  grpc::ClientContext c;
  grpc::health::v1::HealthCheckRequest hq;
  grpc::health::v1::HealthCheckResponse hr;
  ASSERT_TRUE(health->Check(&c, hq, &hr).ok());
  EXPECT_EQ(hr.status(), grpc::health::v1::HealthCheckResponse::SERVING);
  hq.set_service("ctburton.v1.Planner");
  grpc::ClientContext c1;
  ASSERT_TRUE(health->Check(&c1, hq, &hr).ok());
  EXPECT_EQ(hr.status(), grpc::health::v1::HealthCheckResponse::SERVING);

  auto refl = grpc::reflection::v1alpha::ServerReflection::NewStub(s.channel);
  grpc::ClientContext c2;
  auto stream = refl->ServerReflectionInfo(&c2);
  grpc::reflection::v1alpha::ServerReflectionRequest rq;
  rq.set_list_services("*");
  ASSERT_TRUE(stream->Write(rq));
  stream->WritesDone();
  grpc::reflection::v1alpha::ServerReflectionResponse rr;
  ASSERT_TRUE(stream->Read(&rr));
  std::set<std::string> names;
  for (const auto& svc : rr.list_services_response().service()) names.insert(svc.name());
  EXPECT_TRUE(names.count("ctburton.v1.Planner"));
  EXPECT_TRUE(names.count("grpc.health.v1.Health"));
  stream->Finish();
}

TEST(Grpc, ApiKeysGuardEveryMethodButHealth) {
  const std::string keyfile = "/tmp/ctb-grpc-keys-" + std::to_string(getpid());
  {
    std::ofstream(keyfile) << "# test keys\nk-0123456789abcdef-first\n"
                           << "sha256:" << "9b1c7d1f6f9dd0c2c7d9c8b4a3f6e2d1c0b9a8f7e6d5c4b3a2f1e0d9c8b7a6f5\n";
  }
  GrpcServer s({"--api-keys", keyfile});
  pb::ListDomainsRequest q;
  pb::ListDomainsResult r;
  grpc::ClientContext none;
  auto st = s.stub->ListDomains(&none, q, &r);
  EXPECT_EQ(st.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  grpc::ClientContext wrong;
  wrong.AddMetadata("authorization", "Bearer k-0123456789abcdef-firsT");
  EXPECT_EQ(s.stub->ListDomains(&wrong, q, &r).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  grpc::ClientContext right;
  right.AddMetadata("authorization", "Bearer k-0123456789abcdef-first");
  ASSERT_TRUE(s.stub->ListDomains(&right, q, &r).ok());
  EXPECT_EQ(r.domains_size(), 3);
  // Health needs no key.
  auto health = grpc::health::v1::Health::NewStub(s.channel);
  grpc::ClientContext hc;
  grpc::health::v1::HealthCheckRequest hq;
  grpc::health::v1::HealthCheckResponse hr;
  EXPECT_TRUE(health->Check(&hc, hq, &hr).ok());
  // HTTP: the same keys.
  auto http = s.proc.Client();
  auto a = http.Get("/domains");
  ASSERT_TRUE(a);
  EXPECT_EQ(a->status, 401);
  EXPECT_EQ(json::parse(a->body)["error"]["code"], "unauthenticated");
  auto b = http.Get("/domains", {{"Authorization", "Bearer k-0123456789abcdef-first"}});
  ASSERT_TRUE(b);
  EXPECT_EQ(b->status, 200);
  auto h = http.Get("/healthz");
  ASSERT_TRUE(h);
  EXPECT_EQ(h->status, 200);
  // The key never appears in the server's answers (it is never echoed).
  EXPECT_EQ(a->body.find("k-0123456789abcdef"), std::string::npos);
  std::remove(keyfile.c_str());
}

TEST(Grpc, KeysAreReReadOnSighup) {
  const std::string keyfile = "/tmp/ctb-grpc-rotate-" + std::to_string(getpid());
  { std::ofstream(keyfile) << "old-key-0123456789abcdef\n"; }
  GrpcServer s({"--api-keys", keyfile});
  auto list = [&](const std::string& key) {
    grpc::ClientContext c;
    c.AddMetadata("authorization", "Bearer " + key);
    pb::ListDomainsResult r;
    return s.stub->ListDomains(&c, pb::ListDomainsRequest(), &r).error_code();
  };
  EXPECT_EQ(list("old-key-0123456789abcdef"), grpc::StatusCode::OK);
  { std::ofstream(keyfile) << "new-key-0123456789abcdef\n"; }
  kill(s.proc.pid(), SIGHUP);
  grpc::StatusCode after = grpc::StatusCode::OK;
  for (int i = 0; i < 40 && after == grpc::StatusCode::OK; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    after = list("old-key-0123456789abcdef");
  }
  EXPECT_EQ(after, grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(list("new-key-0123456789abcdef"), grpc::StatusCode::OK);
  std::remove(keyfile.c_str());
}

// One request, both front ends: the same plan, status and objective.
TEST(Grpc, HttpAndGrpcGiveTheSameAnswer) {
  GrpcServer s;
  for (const auto& [domain, file, objective] :
       {std::tuple{"presentation", "config/examples/presentation/test1_cot.json", "makespan"},
        // Makespan: the first-plan engine's plan meets the lower bound, so both solves give the
        // same plan (with cost, equally cheap plans from whichever exact engine proves first may
        // differ between the two solves).
        std::tuple{"search_rescue", "config/examples/search_rescue/test2.json", "makespan"},
        std::tuple{"presentation", "tests/data/deadline_infeasible.json", "cost"}}) {
    json body = {{"domain", domain}, {"state_plan", ReadJson(file)},
                 {"options", {{"objective", objective}, {"time_limit_ms", 30000}}}};
    auto http = s.proc.Client().Post("/solve", body.dump(), "application/json");
    ASSERT_TRUE(http);
    ASSERT_EQ(http->status, 200) << http->body;
    json h = json::parse(http->body);
    grpc::ClientContext c;
    pb::PlanResult g;
    ASSERT_TRUE(s.stub->Solve(&c, SolveOf(domain, file, objective), &g).ok());
    EXPECT_EQ(g.trajectory().status(), h["status"]) << file;
    EXPECT_EQ(g.trajectory().verified(), h["verified"].get<bool>());
    if (h["objective"]["value"].is_number()) {
      EXPECT_EQ(g.objective().number_value(), h["objective"]["value"].get<double>()) << file;
    }
    ASSERT_EQ(g.trajectory().transitions_size(), static_cast<int>(h.value("transitions", json::array()).size()));
    for (int i = 0; i < g.trajectory().transitions_size(); ++i) {
      const auto& gt = g.trajectory().transitions(i);
      const auto& ht = h["transitions"][i];
      EXPECT_EQ(gt.automaton(), ht["automaton"]);
      EXPECT_EQ(gt.from(), ht["from"]);
      EXPECT_EQ(gt.to(), ht["to"]);
      EXPECT_EQ(gt.time(), ht["time"].get<double>());
    }
    EXPECT_EQ(g.explanation().conflicts_size(),
              static_cast<int>(h.value("explanation", json::object()).value("conflicts", json::array()).size()));
    EXPECT_EQ(g.state_plan_summary_size(), static_cast<int>(h["state_plan_summary"].size()));
  }
}

// Replanning (contract section 11) over both front ends: one request, the same answer. Robot 1
// stands at door 1 at t = 1 and cannot open it; by hand robot 2 comes to open it and the goal
// moves from 11 to 12 (tests/planner/replan_test.cpp, Robot2ComesToOpenDoor1). The objective is
// cost, then makespan: that future is the only one (with makespan alone an idle robot's extra
// moves could differ between two solves, and the portfolio's strategies race).
TEST(Grpc, ReplanGivesTheSameAnswerAsHttp) {
  GrpcServer s;
  const json sp = ReadJson("config/examples/search_rescue/test2.json");
  json solve = {{"domain", "search_rescue"}, {"state_plan", sp},
                {"options", {{"objective", "makespan"}, {"time_limit_ms", 30000}}}};
  auto planned = s.proc.Client().Post("/solve", solve.dump(), "application/json");
  ASSERT_TRUE(planned);
  ASSERT_EQ(planned->status, 200) << planned->body;
  const json plan = json::parse(planned->body);
  ASSERT_EQ(plan["goal_reached_at"], 11);
  json body = {
      {"domain", "search_rescue"}, {"state_plan", sp},
      {"trajectory", {{"events", plan["events"]}, {"transitions", plan["transitions"]}}},
      {"now", 1},
      {"executed", json::parse(R"([
          {"time": 0, "automaton": "robot1", "from": "outside", "to": "goingToDoor1"},
          {"time": 1, "automaton": "robot1", "from": "goingToDoor1", "to": "atDoor1"}])")},
      {"blocked", json::parse(R"([{"automaton": "robot1", "from": "atDoor1", "to": "door1Opening"}])")},
      {"options", {{"objective", "cost_then_makespan"}, {"time_limit_ms", 30000}}}};
  auto http = s.proc.Client().Post("/replan", body.dump(), "application/json");
  ASSERT_TRUE(http);
  ASSERT_EQ(http->status, 200) << http->body;
  const json h = json::parse(http->body);
  ASSERT_EQ(h["status"], "optimal") << http->body;
  EXPECT_EQ(h["goal_reached_at"], 12);

  grpc::ClientContext c;
  Deadline(c, 60000);
  pb::PlanResult g;
  auto st = s.stub->Replan(&c, FromJson<pb::ReplanRequest>(body), &g);
  ASSERT_TRUE(st.ok()) << st.error_message();
  EXPECT_EQ(g.status(), pb::SOLVED_OPTIMALLY);
  EXPECT_EQ(g.trajectory().status(), h["status"]);
  EXPECT_EQ(g.trajectory().verified(), h["verified"].get<bool>());
  EXPECT_EQ(g.trajectory().goal_reached_at(), h["goal_reached_at"].get<double>());
  ASSERT_TRUE(g.objective().has_struct_value());
  EXPECT_EQ(g.objective().struct_value().fields().at("cost").number_value(), h["objective"]["value"]["cost"].get<double>());
  EXPECT_EQ(g.objective().struct_value().fields().at("makespan").number_value(), 12);
  EXPECT_EQ(g.trajectory().now(), 1);
  ASSERT_EQ(g.trajectory().transitions_size(), static_cast<int>(h["transitions"].size()));
  for (int i = 0; i < g.trajectory().transitions_size(); ++i) {
    const auto& gt = g.trajectory().transitions(i);
    const auto& ht = h["transitions"][i];
    EXPECT_EQ(gt.automaton(), ht["automaton"]) << i;
    EXPECT_EQ(gt.from(), ht["from"]) << i;
    EXPECT_EQ(gt.to(), ht["to"]) << i;
    EXPECT_EQ(gt.time(), ht["time"].get<double>()) << i;
    EXPECT_EQ(gt.executed(), ht.value("executed", false)) << i;
  }
  // The diff, item by item.
  const auto same = [](const auto& items, const json& hs, const char* kind) {
    ASSERT_EQ(items.size(), static_cast<int>(hs.size())) << kind;
    for (int i = 0; i < items.size(); ++i) {
      EXPECT_EQ(items[i].automaton(), hs[i]["automaton"]) << kind << i;
      EXPECT_EQ(items[i].from(), hs[i]["from"]) << kind << i;
      EXPECT_EQ(items[i].to(), hs[i]["to"]) << kind << i;
      EXPECT_EQ(items[i].has_time_before(), hs[i].contains("time_before")) << kind << i;
      EXPECT_EQ(items[i].has_time_after(), hs[i].contains("time_after")) << kind << i;
    }
  };
  same(g.diff().kept(), h["diff"]["kept"], "kept");
  same(g.diff().moved(), h["diff"]["moved"], "moved");
  same(g.diff().added(), h["diff"]["added"], "added");
  same(g.diff().dropped(), h["diff"]["dropped"], "dropped");
  EXPECT_FALSE(h["diff"]["dropped"].empty());
  EXPECT_EQ(g.state_plan_summary_size(), static_cast<int>(h["state_plan_summary"].size()));

  // A bad history is the same located error on both: robot 1 has no move from goingToDoor1 to
  // atDoor3, so /executed/1/to (HTTP 400, gRPC INVALID_ARGUMENT).
  body["executed"][1]["to"] = "atDoor3";
  auto bad = s.proc.Client().Post("/replan", body.dump(), "application/json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_EQ(json::parse(bad->body)["error"]["path"], "/executed/1/to") << bad->body;
  grpc::ClientContext c2;
  auto st2 = s.stub->Replan(&c2, FromJson<pb::ReplanRequest>(body), &g);
  EXPECT_EQ(st2.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(st2.error_message().find("/executed/1/to"), std::string::npos) << st2.error_message();
}

}  // namespace

namespace {

// The scaled profile's proxy (docker/nginx.conf) in miniature: nginx with grpc_pass over HTTP/2
// to two replicas; a stream through it reaches a replica and comes back whole.
TEST(Grpc, AStreamThroughNginxReachesAReplica) {
  ASSERT_TRUE(ctb::testing::Executable("/usr/sbin/nginx")) << "nginx missing: bash scripts/install-deps.sh --test";
  const std::string dir = "/tmp/ctb-grpc-nginx-" + std::to_string(getpid());
  for (const char* sub : {"body", "proxy", "fastcgi", "uwsgi", "scgi", "logs"}) {
    std::filesystem::create_directories(dir + "/" + sub);
    chmod((dir + "/" + sub).c_str(), 0777);
  }
  GrpcServer r1, r2;
  const int proxy = FreeLoopbackPort();
  std::ofstream(dir + "/nginx.conf")
      << "daemon off;\nworker_processes 1;\npid " << dir << "/nginx.pid;\nerror_log " << dir
      << "/logs/error.log;\nevents { worker_connections 256; }\nhttp {\n  access_log off;\n"
      << "  client_body_temp_path " << dir << "/body;\n  proxy_temp_path " << dir << "/proxy;\n"
      << "  fastcgi_temp_path " << dir << "/fastcgi;\n  uwsgi_temp_path " << dir << "/uwsgi;\n"
      << "  scgi_temp_path " << dir << "/scgi;\n"
      << "  upstream ctb_grpc {\n    server 127.0.0.1:" << r1.grpc_port << ";\n    server 127.0.0.1:"
      << r2.grpc_port << ";\n  }\n"
      << "  server {\n    listen 127.0.0.1:" << proxy << " http2;\n    location / {\n"
      << "      grpc_pass grpc://ctb_grpc;\n      grpc_read_timeout 120s;\n    }\n  }\n}\n";
  pid_t nginx = ctb::testing::Spawn({"/usr/sbin/nginx", "-p", dir, "-c", dir + "/nginx.conf"},
                                    dir + "/nginx.out");
  ASSERT_TRUE(ctb::testing::WaitForPort(proxy, 5000)) << "nginx did not start";
  auto channel = grpc::CreateChannel("127.0.0.1:" + std::to_string(proxy), grpc::InsecureChannelCredentials());
  auto stub = pb::Planner::NewStub(channel);
  for (int round = 0; round < 2; ++round) {  // round robin: each replica gets one
    grpc::ClientContext c;
    Deadline(c, 60000);
    auto reader = stub->SolveAnytime(&c, SolveOf("search_rescue", "config/examples/search_rescue/test1.json", "makespan"));
    std::vector<pb::PlanResult> all;
    pb::PlanResult r;
    while (reader->Read(&r)) all.push_back(r);
    auto st = reader->Finish();
    ASSERT_TRUE(st.ok()) << st.error_message();
    ASSERT_GE(all.size(), 2u);
    EXPECT_EQ(all.front().status(), pb::INTERMEDIATE);
    EXPECT_EQ(all.back().status(), pb::SOLVED_OPTIMALLY);
  }
  int served = 0;
  for (auto* s : {&r1, &r2}) {
    auto m = s->proc.Client().Get("/metrics");
    if (m && m->body.find("route=\"grpc:SolveAnytime\"") != std::string::npos) ++served;
  }
  EXPECT_EQ(served, 2) << "both replicas served a stream through nginx";
  ctb::testing::StopChild(nginx);
  std::filesystem::remove_all(dir);
}

}  // namespace

// Execute (contract section 14): the test is the device side. It reads the commands from the
// stream, answers each with the transition done, reports the plan's other transitions (a door,
// a robot arriving) in plan order when their moment comes, and sees the run end `finished` /
// succeeded. A report with a
// location the robot lacks is refused on the stream with its pointer, and the execution goes on.
TEST(Grpc, ExecuteWithTheCallerAsTheDevicesRunsAPlanToTheGoal) {
  GrpcServer s;
  grpc::ClientContext c;
  Deadline(c, 60000);
  auto stream = s.stub->Execute(&c);
  pb::ExecuteMessage start;
  start.mutable_start()->set_domain("search_rescue");
  *start.mutable_start()->mutable_state_plan() =
      FromJson<pb::StatePlan>(ReadJson("config/examples/search_rescue/test1.json"));
  const double speed = 20;  // 13 plan s in 0.65 s; a report up to 4 plan s off is on time
  start.mutable_start()->set_speed(speed);
  ASSERT_TRUE(stream->Write(start));
  json plan;
  std::set<std::string> sent;  // "automaton from to" dispatched
  std::map<std::string, double> sent_at, last_real, last_plan;
  std::chrono::steady_clock::time_point origin;
  std::size_t next = 0;
  int refused = 0, dispatched = 0;
  std::string last, id;
  pb::ExecutionEvent ev;
  auto report = [&](const std::string& automaton, const std::string& location, double time) {
    pb::ExecuteMessage m;
    m.mutable_report()->set_automaton(automaton);
    m.mutable_report()->set_location(location);
    m.mutable_report()->set_time(time);
    return stream->Write(m);
  };
  while (stream->Read(&ev)) {
    last = ev.event();
    if (id.empty()) {
      origin = std::chrono::steady_clock::now();  // the first command goes out at plan time 0
      id = ev.execution();
      httplib::Client h("127.0.0.1", s.proc.port());
      auto r = h.Get(("/executions/" + id).c_str());
      ASSERT_TRUE(r);
      plan = json::parse(r->body)["plan"];
      EXPECT_TRUE(report("robot1", "onTheMoon", 0));  // refused, and the run goes on
    }
    std::string text;
    google::protobuf::util::MessageToJsonString(ev.data(), &text);
    const json data = json::parse(text);
    if (ev.event() == "refused") {
      ++refused;
      EXPECT_EQ(data["path"], "/location") << text;
    }
    if (ev.event() == "dispatched") {
      ++dispatched;
      const std::string key = data["automaton"].get<std::string>() + " " + data["from"].get<std::string>() + " " +
                              data["to"].get<std::string>();
      sent.insert(key);
      sent_at[key] = data["at"].get<double>();
    }
    if (ev.event() == "finished") {
      EXPECT_EQ(data["state"], "succeeded") << text;
      break;
    }
    // Every transition of the plan whose turn has come, in plan order: a commanded one once its
    // command came (at the command's time), another on its own clock (its plan time shifted by
    // how late its automaton's previous transition was).
    const json& ts = plan["transitions"];
    while (next < ts.size()) {
      const json& t = ts[next];
      const std::string a = t["automaton"];
      const std::string key = a + " " + t["from"].get<std::string>() + " " + t["to"].get<std::string>();
      const double planned = t["time"].get<double>();
      double at = planned + (last_plan.count(a) ? last_real[a] - last_plan[a] : 0);
      if (t["command"].is_string()) {
        if (!sent_at.count(key)) break;
        at = sent_at[key];
      }
      at = std::max(at, last_real.count(a) ? last_real[a] : 0.0);
      // A device reports a move when it has made it: not before its moment on the wall clock.
      std::this_thread::sleep_until(origin + std::chrono::microseconds(static_cast<long>(at / speed * 1e6)));
      ASSERT_TRUE(report(a, t["to"], at));
      last_real[a] = at;
      last_plan[a] = planned;
      ++next;
    }
  }
  EXPECT_EQ(last, "finished");
  EXPECT_EQ(refused, 1);
  EXPECT_GT(dispatched, 3);
  stream->WritesDone();
  EXPECT_TRUE(stream->Finish().ok());
  // The same execution over HTTP: succeeded, every transition of the plan in the history.
  httplib::Client h("127.0.0.1", s.proc.port());
  auto r = h.Get(("/executions/" + id).c_str());
  ASSERT_TRUE(r);
  const json v = json::parse(r->body);
  EXPECT_EQ(v["state"], "succeeded") << v.value("why", "") << "\n" << v["events"].dump();
  EXPECT_EQ(v["adapter"], "grpc");
  EXPECT_EQ(v["history"].size(), plan["transitions"].size());
}

// A first message that is not a start is refused; a caller that goes away stops its execution.
TEST(Grpc, ExecuteNeedsAStartAndStopsWhenTheCallerLeaves) {
  GrpcServer s;
  {
    grpc::ClientContext c;
    Deadline(c, 30000);
    auto stream = s.stub->Execute(&c);
    pb::ExecuteMessage m;
    m.mutable_report()->set_automaton("robot1");
    ASSERT_TRUE(stream->Write(m));
    stream->WritesDone();
    pb::ExecutionEvent ev;
    EXPECT_FALSE(stream->Read(&ev));
    EXPECT_EQ(stream->Finish().error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  }
  std::string id;
  {
    grpc::ClientContext c;
    Deadline(c, 30000);
    auto stream = s.stub->Execute(&c);
    pb::ExecuteMessage start;
    start.mutable_start()->set_domain("search_rescue");
    *start.mutable_start()->mutable_state_plan() =
        FromJson<pb::StatePlan>(ReadJson("config/examples/search_rescue/test1.json"));
    ASSERT_TRUE(stream->Write(start));
    pb::ExecutionEvent ev;
    ASSERT_TRUE(stream->Read(&ev));
    EXPECT_EQ(ev.event(), "dispatched");
    id = ev.execution();
    c.TryCancel();
    while (stream->Read(&ev)) {
    }
    stream->Finish();
  }
  httplib::Client h("127.0.0.1", s.proc.port());
  json v;
  for (int i = 0; i < 500; ++i) {
    auto r = h.Get(("/executions/" + id).c_str());
    ASSERT_TRUE(r);
    v = json::parse(r->body);
    if (v["state"] != "running") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(v["state"], "stopped");
}
