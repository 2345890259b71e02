// The live executions of the core (contract section 14): one thread each that dispatches its
// plan as the executive decides (executive/run.h), plays the sim adapter, replans through the
// core, and writes every change to the execution store before it is acknowledged or sent.
// Internal to app/.
#pragma once

#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "app/core.h"
#include "app/document_store.h"
#include "executive/run.h"
#include "executive/sim.h"

namespace ctb::app {

class Executions {
 public:
  // lease_ms: how long this replica's claim on an execution lasts unless renewed; shared: the
  // store is shared with other replicas (Redis), so claims are renewed and expired ones taken over.
  Executions(Core& core, std::unique_ptr<DocumentStore> store, long lease_ms, bool shared);
  ~Executions();  // stops every thread (executions stay stored and resume at the next start)

  using DomainOf = std::function<std::variant<std::shared_ptr<const Domain>, Error>(const Json& doc)>;
  // Resumes the running executions of the store at start-up (with a shared store only those whose
  // claim ran out) and, with a shared store, keeps taking over expired ones; how many at start.
  int Resume(DomainOf domain_of);

  // A new execution of `plan` (an answer with network); the stored document's request parts in
  // `doc` ({"domain"?, "action_model"?, "state_plan", "adapter", "speed", "sim", "options"}).
  std::variant<std::string, Error> Start(std::shared_ptr<const Domain> d, Json doc, const Json& plan,
                                         const RequestOptions& options);
  std::variant<Json, Error> Get(const std::string& id);
  std::variant<Json, Error> Report(const std::string& id, const Json& report);
  std::optional<Error> Stop(const std::string& id);
  // The execution's domain, for checking a new state plan; kNotFound / kConflict (ended).
  std::variant<std::shared_ptr<const Domain>, Error> DomainOfLive(const std::string& id);
  // Stores the (checked) state plan and asks for a replan.
  std::optional<Error> ChangeStatePlan(const std::string& id, const Json& state_plan);
  std::variant<std::vector<ExecutionEvent>, Error> Events(const std::string& id, long after, long wait_ms,
                                                         bool* ended);
  void SetSink(const std::string& adapter, std::shared_ptr<CommandSink> sink, const std::string& execution);
  void StopAll();
  // The histories of the stored executions of the named domain (any state).
  std::variant<std::vector<Json>, Error> Histories(const std::string& domain);

 private:
  struct Live;
  std::shared_ptr<Live> Find(const std::string& id);
  void Launch(std::shared_ptr<Live> live);
  void Loop(std::shared_ptr<Live> live);
  void Replan(std::shared_ptr<Live>& live, std::unique_lock<std::mutex>& lk, const std::string& why);
  std::variant<exec::Applied, Error> ApplyLocked(Live& live, const exec::Report& r);
  void Emit(Live& live, const std::string& name, Json data);
  bool Persist(Live& live);
  std::shared_ptr<CommandSink> SinkFor(const Live& live);
  int Claim(bool at_start);  // the executions claimed, -1 when the store could not be listed
  void Scan(bool resumed);
  std::shared_ptr<Live> LiveFrom(const StoredDocument& stored);

  Core& core_;
  std::unique_ptr<DocumentStore> store_;
  std::mutex mu_;
  std::map<std::string, std::shared_ptr<Live>> live_;
  std::vector<std::shared_ptr<Live>> retired_;  // let go and replaced by a later claim
  std::map<std::string, std::shared_ptr<CommandSink>> sinks_;  // by adapter, or "grpc:<id>"
  const long lease_ms_;
  const bool shared_;
  const std::string me_;  // this replica, in the documents it claims
  DomainOf domain_of_;
  std::thread scanner_;
  std::mutex scan_mu_;
  std::condition_variable scan_cv_;
  bool scan_stop_ = false;
};

}  // namespace ctb::app
