// `ctburton execute`: dispatches a plan on a clock (real time, or --speed N times faster; 0: no
// waiting), prints each transition when it is due, takes injected faults from --fault flags or
// stdin, replans from what happened (the application core's Replan, as POST /replan) and goes on
// until the goal is reached.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <deque>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "client/commands.h"
#include "client/execute_sample.h"
#include "client/execute_server.h"
#include "client/local_core.h"
#include "planner/replan/replan.h"

namespace ctb::cli {

namespace {

struct ExecuteCliOptions {
  std::string domain, file, config_dir, objective, keep = "none";
  std::vector<std::string> faults;
  bool faults_stdin = false;
  bool json = false;
  double speed = 1;
  long time_limit_ms = 60000;
  // --sample: simulated executions of the flexible plan (client/execute_sample.h).
  std::string sample, dispatch = "dynamic", controllability;
  unsigned seed = 1;
  int runs = 1;
  // --server: the execution runs in that server on its simulated team (execute_server.h).
  std::string server;
  double fail = 0;
};

struct Fault {
  std::string kind;  // delay, block, at
  std::string automaton, a, b;
  double seconds = 0;
  double time = 0;
  std::string text;
};

// delay:AUTOMATON:SECONDS[@T] | block:AUTOMATON:FROM:TO[@T] | at:AUTOMATON:LOCATION[@T]
std::optional<Fault> ParseFault(const std::string& spec, double default_time, std::string& why) {
  Fault f;
  f.text = spec;
  f.time = default_time;
  std::string s = spec;
  if (auto at = s.rfind('@'); at != std::string::npos) {
    try {
      f.time = std::stod(s.substr(at + 1));
    } catch (...) {
      why = "bad time after '@'";
      return std::nullopt;
    }
    s = s.substr(0, at);
  }
  std::vector<std::string> parts;
  std::stringstream ss(s);
  for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
  if (parts.empty()) return std::nullopt;
  f.kind = parts[0];
  if (f.kind == "delay" && parts.size() == 3) {
    f.automaton = parts[1];
    try {
      f.seconds = std::stod(parts[2]);
    } catch (...) {
      why = "bad number of seconds";
      return std::nullopt;
    }
  } else if (f.kind == "block" && parts.size() == 4) {
    f.automaton = parts[1], f.a = parts[2], f.b = parts[3];
  } else if (f.kind == "at" && parts.size() == 3) {
    f.automaton = parts[1], f.a = parts[2];
  } else {
    why = "expected delay:AUTOMATON:SECONDS, block:AUTOMATON:FROM:TO or at:AUTOMATON:LOCATION "
          "(each optionally followed by @TIME)";
    return std::nullopt;
  }
  if (!std::isfinite(f.time) || f.time < 0 || !std::isfinite(f.seconds) || f.seconds < 0) {
    why = "times and delays must be non-negative numbers";
    return std::nullopt;
  }
  return f;
}

class Executor {
 public:
  Executor(LocalProblem& p, const ExecuteCliOptions& o) : p_(p), o_(o) {}

  int Run() {
    for (const auto& spec : o_.faults) {
      std::string why;
      auto f = ParseFault(spec, 0, why);
      if (!f) {
        std::cerr << "error: --fault '" << spec << "': " << why << "\n";
        return 2;
      }
      faults_.push_back(*f);
    }
    if (o_.faults_stdin) std::thread([this] { ReadStdin(); }).detach();
    if (!Replan(0, Json(), "start")) return 1;
    start_ = std::chrono::steady_clock::now();
    constexpr double kNever = 1e300;
    for (;;) {
      TakeStdinFaults();
      auto next = NextTransitionTime();
      if (!next && held_.empty()) break;  // the goal is reached; later faults do not matter
      const double tn = next.value_or(kNever);
      const Fault* fault = nullptr;
      for (const auto& f : faults_)
        if (f.kind != "delay" && (!fault || f.time < fault->time)) fault = &f;
      const Json* held = nullptr;
      for (const auto& [a, h] : held_)
        if (!held || h["time"].get<double>() < (*held)["time"].get<double>()) held = &h;
      const double tf = fault ? fault->time : kNever;
      const double th = held ? (*held)["time"].get<double>() : kNever;
      const double when = std::max(now_, std::min({tn, tf, th}));
      if (!WaitUntil(when)) continue;  // a stdin fault arrived: look again
      now_ = when;
      if (held && th <= tf && th <= tn) {
        Json entry = *held;
        held_.erase(entry["automaton"].get<std::string>());
        Print("late", entry);
        executed_.push_back(entry);
        if (!Replan(now_, Json(), "late " + entry["automaton"].get<std::string>())) return 1;
        continue;
      }
      if (fault && tf <= tn) {
        Fault f = *fault;
        faults_.erase(faults_.begin() + (fault - faults_.data()));
        if (!ApplyFault(f)) return 1;
        continue;
      }
      Dispatch(when);
    }
    Line({{"type", "done"}, {"goal_reached_at", plan_["goal_reached_at"]}},
         "goal reached at t = " + plan_["goal_reached_at"].dump() + " s");
    return 0;
  }

 private:
  std::optional<double> NextTransitionTime() const {
    for (const auto& t : plan_["transitions"])
      if (!t.value("executed", false) && !t.value("observed", false) && !Done(t))
        return t["time"].get<double>();
    return std::nullopt;
  }
  bool Done(const Json& t) const { return dispatched_.count(Key(t)) > 0; }
  static std::string Key(const Json& t) {
    return t["automaton"].get<std::string>() + "|" + t["event"].dump();
  }

  // Dispatches every transition due at `when`, holding those a delay fault makes late.
  void Dispatch(double when) {
    for (const auto& t : plan_["transitions"]) {
      if (t.value("executed", false) || t.value("observed", false) || Done(t) ||
          t["time"].get<double>() != when)
        continue;
      dispatched_.insert(Key(t));
      const std::string a = t["automaton"];
      if (held_.count(a)) continue;  // waits for its late transition
      Json entry = {{"time", when}, {"automaton", a}, {"from", t["from"]}, {"to", t["to"]}};
      auto d = std::find_if(faults_.begin(), faults_.end(), [&](const Fault& f) {
        return f.kind == "delay" && f.automaton == a && f.time <= when;
      });
      if (d != faults_.end()) {
        entry["time"] = when + d->seconds;
        held_[a] = entry;
        Line({{"type", "fault"}, {"time", when}, {"fault", d->text}},
             Stamp(when) + "FAULT " + d->text + ": " + a + " " + t["from"].get<std::string>() +
                 " -> " + t["to"].get<std::string>() + " comes " + Json(d->seconds).dump() + " s late");
        faults_.erase(d);
        continue;
      }
      Print("command", t);
      executed_.push_back(entry);
    }
  }

  bool ApplyFault(const Fault& f) {
    Line({{"type", "fault"}, {"time", now_}, {"fault", f.text}}, Stamp(now_) + "FAULT " + f.text);
    Json observed;
    if (f.kind == "block")
      blocked_.push_back({{"automaton", f.automaton}, {"from", f.a}, {"to", f.b}});
    else
      observed = {{f.automaton, {{"location", f.a}, {"since", now_}}}};
    return Replan(now_, observed, f.text);
  }

  bool Replan(double now, const Json& observed, const std::string& why) {
    app::ReplanCall call;
    call.domain = p_.domain;
    call.state_plan = p_.state_plan;
    call.request = {{"now", now}, {"executed", executed_}, {"blocked", blocked_}};
    if (!observed.is_null()) call.request["observed"] = observed;
    if (!plan_.is_null()) call.request["trajectory"] = plan_;
    call.keep = o_.keep;
    if (!o_.objective.empty()) call.options.objective = o_.objective;
    call.options.time_limit_ms = o_.time_limit_ms;
    auto r = p_.core->Replan(call, {});
    if (auto* e = std::get_if<Error>(&r)) {
      PrintError(RelativeTo(*e, "/state_plan"));
      return false;
    }
    app::Answer& answer = std::get<app::Answer>(r);
    const SolveResult& res = answer.result;
    Json ans = std::move(answer.document);
    std::string text = Stamp(now) + (why == "start" ? "PLAN " : "REPLAN ") + TerminationName(res.status);
    if (auto v = res.Value()) text += std::string(", ") + ObjectiveName(res.objective) + " " + v->ToJson().dump();
    if (answer.diff && why != "start")
      text += " (kept " + std::to_string((*answer.diff)["kept"].size()) + ", moved " +
              std::to_string((*answer.diff)["moved"].size()) + ", added " +
              std::to_string((*answer.diff)["added"].size()) + ", dropped " +
              std::to_string((*answer.diff)["dropped"].size()) + ")";
    Line({{"type", why == "start" ? "plan" : "replan"}, {"time", now}, {"answer", ans}}, text);
    if (res.status != Termination::kOptimal && res.status != Termination::kFeasible) {
      if (res.explanation && !o_.json)
        for (const auto& c : res.explanation->conflicts) std::cout << "  " << c.text << "\n";
      return false;
    }
    // Observations the replan absorbed are part of the history from now on.
    for (const auto& t : ans["transitions"])
      if (t.value("observed", false) && t["time"].get<double>() >= now)
        executed_.push_back({{"time", t["time"]}, {"automaton", t["automaton"]}, {"from", t["from"]},
                             {"to", t["to"]}, {"observed", true}});
    plan_ = ans;
    dispatched_.clear();
    return true;
  }

  // Sleeps until plan time `when` (scaled); false when a stdin fault arrived meanwhile.
  bool WaitUntil(double when) {
    if (o_.speed <= 0) return true;
    for (;;) {
      const double elapsed =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() * o_.speed;
      clock_ = elapsed;
      if (elapsed >= when) return true;
      if (TakeStdinFaults()) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(
          std::clamp<long>(std::lround((when - elapsed) / o_.speed * 1000), 1, 50)));
    }
  }

  void ReadStdin() {
    for (std::string line; std::getline(std::cin, line);) {
      if (line.empty()) continue;
      std::lock_guard<std::mutex> lock(mu_);
      incoming_.push_back(line);
    }
  }
  bool TakeStdinFaults() {
    std::lock_guard<std::mutex> lock(mu_);
    bool any = false;
    for (; !incoming_.empty(); incoming_.pop_front()) {
      std::string why;
      auto f = ParseFault(incoming_.front(), std::max(now_, clock_.load()), why);
      if (!f) {
        std::cerr << "ignored fault '" << incoming_.front() << "': " << why << "\n";
        continue;
      }
      faults_.push_back(*f);
      any = true;
    }
    return any;
  }

  void Print(const std::string& type, const Json& t) {
    std::string cmd = t.contains("command") && t["command"].is_string() ? t["command"].get<std::string>() : "-";
    Line({{"type", type}, {"time", t["time"]}, {"automaton", t["automaton"]}, {"command", cmd},
          {"from", t["from"]}, {"to", t["to"]}},
         Stamp(t["time"].get<double>()) + t["automaton"].get<std::string>() + "  " + cmd + "  " +
             t["from"].get<std::string>() + " -> " + t["to"].get<std::string>());
  }
  static std::string Stamp(double t) {
    std::ostringstream s;
    s << "t=" << std::setw(8) << std::fixed << std::setprecision(1) << t << "  ";
    return s.str();
  }
  void Line(const Json& j, const std::string& text) {
    if (o_.json) std::cout << j.dump() << std::endl;
    else std::cout << text << std::endl;
  }

  LocalProblem& p_;
  const ExecuteCliOptions& o_;
  Json plan_;
  Json executed_ = Json::array(), blocked_ = Json::array();
  std::vector<Fault> faults_;
  std::map<std::string, Json> held_;
  std::set<std::string> dispatched_;
  double now_ = 0;
  std::atomic<double> clock_{0};
  std::chrono::steady_clock::time_point start_;
  std::mutex mu_;
  std::deque<std::string> incoming_;
};

int RunExecute(const ExecuteCliOptions& o) {
  if (!o.server.empty()) {
    if (!o.sample.empty() || !o.faults.empty() || o.faults_stdin) {
      std::cerr << "error: --server runs the execution in the server; --sample and --fault are for local runs "
                   "(faults in the server: --fail)\n";
      return 2;
    }
    return RunServerExecute({o.server, o.domain, o.file, o.objective, o.speed > 0 ? o.speed : 1, o.fail, o.seed,
                             o.json, o.time_limit_ms});
  }
  if (!o.sample.empty()) {
    SampleOptions s{o.domain, o.file, o.config_dir, o.objective, o.controllability, o.sample,
                    o.dispatch, o.seed, o.runs, o.json, o.time_limit_ms};
    return RunSampledExecutions(s);
  }
  if (!ParseKeep(o.keep)) {
    std::cerr << "error: --keep must be none, started or min_change\n";
    return 2;
  }
  auto opened = OpenLocalProblem(o.domain, o.config_dir, o.file);
  if (auto* e = std::get_if<Error>(&opened)) {
    PrintError(*e);
    return 1;
  }
  return Executor(std::get<LocalProblem>(opened), o).Run();
}

}  // namespace

Runner AddExecute(CLI::App& app) {
  auto o = std::make_shared<ExecuteCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "execute", "Dispatch a plan on a clock, inject faults, replan and go on");
  sub->add_option("--domain", o->domain, "Domain name or path")->required();
  sub->add_option("file", o->file, "State plan JSON file")->required();
  sub->add_option("--objective", o->objective, "cost, makespan or cost_then_makespan");
  sub->add_option("--speed", o->speed, "Plan seconds per real second (default 1; 0: no waiting)")
      ->check(CLI::Range(0.0, 1e6));
  sub->add_option("--fault", o->faults,
                  "delay:AUTOMATON:SECONDS, block:AUTOMATON:FROM:TO or at:AUTOMATON:LOCATION, "
                  "each optionally @TIME (plan seconds); repeatable");
  sub->add_flag("--faults-stdin", o->faults_stdin, "Read faults from stdin, one per line, applied "
                "when read unless @TIME is given");
  sub->add_option("--keep", o->keep, "none (default), started or min_change");
  sub->add_flag("--json", o->json, "One JSON object per line instead of text");
  sub->add_option("--time-limit-ms", o->time_limit_ms, "Time limit of each (re)plan")
      ->check(CLI::Range(1L, 3600L * 1000));
  sub->add_option("--config-dir", o->config_dir, "Configuration directory");
  sub->add_option("--sample", o->sample,
                  "Simulate executions of the flexible plan instead (no waiting): contingent "
                  "durations drawn uniformly or from their distributions")
      ->check(CLI::IsMember({"uniform", "distribution"}));
  sub->add_option("--runs", o->runs, "With --sample: how many executions (default 1)")
      ->check(CLI::Range(1, 1000000));
  sub->add_option("--seed", o->seed, "With --sample or --server: the random seed (default 1)");
  sub->add_option("--server", o->server,
                  "Run the execution in a ctburton server on its simulated team and follow its events, "
                  "e.g. http://127.0.0.1:8080");
  sub->add_option("--fail", o->fail, "With --server: the chance that a commanded move fails (default 0)")
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--dispatch", o->dispatch,
                  "With --sample: dynamic (default: what happened decides what starts next) or "
                  "fixed (every start at its planned time)")
      ->check(CLI::IsMember({"dynamic", "fixed"}));
  sub->add_option("--controllability", o->controllability,
                  "dynamic (default where there are contingent transitions), strong or none "
                  "(plan as if every duration were the planner's, to measure how often it fails)")
      ->check(CLI::IsMember({"dynamic", "strong", "none"}));
  return [o, sub]() { return sub->parsed() ? RunExecute(*o) : -1; };
}

}  // namespace ctb::cli
