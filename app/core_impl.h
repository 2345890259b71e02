// The core's state and the helpers its use cases share. Internal to app/.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <variant>

#include "app/core.h"
#include "app/document_store.h"
#include "app/job_gate.h"
#include "app/storage.h"
#include "planner/model/state_plan.h"
#include "planner/solve/solve.h"

namespace ctb::app {

class Executions;

struct Core::Impl {
  explicit Impl(const CoreConfig& c) : cfg(c), gate(c.solver_workers, c.solver_queue, metrics) {}

  CoreConfig cfg;
  Metrics metrics;
  JobGate gate;
  std::map<std::string, Domain> domains;
  std::shared_ptr<StorageHealth> storage;  // what the stores last did (storage.h)
  std::unique_ptr<DocumentStore> sessions;
  std::unique_ptr<DocumentStore> stored_domains;  // domains created through the API
  std::shared_ptr<LlmClient> demo_llm;
  std::atomic<bool> stopping{false};
  bool ready = false;
  std::atomic<bool> mqtt_configured{false};
  // Last: destroyed first, its threads stopped while the rest of the core still stands.
  std::shared_ptr<Executions> executions;

  // A shipped or stored domain by name; kNotFound (pointer /domain) when unknown.
  std::variant<std::shared_ptr<const Domain>, Error> NamedDomain(const std::string& name) const;
  // A domain by name or inline action model; over the model budget: kTooLarge with `limit`.
  std::variant<std::shared_ptr<const Domain>, Error> ResolveDomain(const DomainRef& ref) const;
  // The state plan document checked against the domain; pointers prefixed with `prefix`.
  std::variant<StatePlan, Error> CheckPlan(const Json& j, const Domain& d,
                                           const std::string& prefix) const;
  // The request's options within the service's limits, as planner options.
  std::variant<SolveOptions, Error> MakeOptions(const RequestOptions& r) const;
  // Solves in a job slot; the job stops when ctx.cancelled() or Shutdown().
  std::variant<Answer, Error> SolveGated(const Domain& d, const StatePlan& sp, SolveOptions o,
                                         const CallContext& ctx);
  // Runs `run` in a job slot with the job's cancel flag and progress set in its options.
  std::variant<Answer, Error> RunGated(
      SolveOptions o, const CallContext& ctx,
      const std::function<std::variant<Answer, Error>(const SolveOptions&)>& run);
  // The same for any job: the gate's refusal, or what `run` throws, as an Error.
  std::optional<Error> InGate(SolveOptions o, const CallContext& ctx,
                              const std::function<void(const SolveOptions&)>& run);
  // A report in words (ReplanCall::command) read by the LLM: {"request": the request with the
  // report's observed/blocked merged in, "report": what the answer shows}.
  std::variant<Json, Error> ReadReportInWords(const Domain& d, const StatePlan& sp,
                                              const Json& request, const std::string& command,
                                              const CallContext& ctx) const;
  // The 503 of a store ("session", "domain", "execution") that failed, with the backend's words.
  Error StoreFailed(const std::string& store) const { return app::StoreFailed(*storage, store); }
  // The configured LLM client, else the demo recordings, else kUnavailable.
  std::variant<std::unique_ptr<LlmClient>, Error> Llm() const;
};

// Opens the execution store and resumes the executions that were running (core_execute.cpp).
std::optional<Error> OpenExecutions(Core& core, Core::Impl& impl);

// The answer of a solve: its document written (ResultJson) and its statistics as text.
Answer AnswerOf(SolveResult result, const Domain& d, const StatePlan& sp);
// The statistics of a result as text, for the front ends' metrics (gRPC's map).
std::map<std::string, std::string> MetricsOf(const SolveResult& r);

// Bad input at one pointer.
Error Bad(const std::string& message, const std::string& pointer);

}  // namespace ctb::app
