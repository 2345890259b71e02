// `ctburton execute --server URL` (execute_server.h).
#include "client/execute_server.h"

#include <httplib.h>

#include <iostream>

#include "client/commands.h"
#include "client/remote.h"
#include "planner/model/json_io.h"

namespace ctb::cli {

namespace {

std::string Line(const std::string& name, const Json& d) {
  auto t = [](const Json& x) { return "t = " + x.dump() + " s"; };
  if (name == "dispatched")
    return t(d["at"]) + ": sent " + d.value("automaton", "") + " " + d.value("command", "") + " (" +
           d.value("from", "") + " -> " + d.value("to", "") + ")";
  if (name == "reported")
    return t(d["time"]) + ": " + d.value("automaton", "") +
           (d.contains("failed") ? " could not " + d.value("failed", "") : " reached " + d.value("location", ""));
  if (name == "replanned")
    return "t = " + d["now"].dump() + " s: replanned (" + d.value("why", "") + ") in " + d["ms"].dump() +
           " ms: " + d.value("status", "");
  if (name == "finished")
    return "finished: " + d.value("state", "") + (d.value("why", "").empty() ? "" : " (" + d.value("why", "") + ")");
  return name;
}

// Reads the SSE of GET /executions/{id}/events until it ends, printing each event.
bool Follow(const std::string& server, const std::string& id, bool json) {
  httplib::Client cli(server);
  cli.set_connection_timeout(5, 0);
  cli.set_read_timeout(60, 0);
  std::string buffer;
  auto res = cli.Get(("/executions/" + id + "/events").c_str(), [&](const char* data, size_t n) {
    buffer.append(data, n);
    for (std::size_t end; (end = buffer.find("\n\n")) != std::string::npos;) {
      const std::string block = buffer.substr(0, end);
      buffer.erase(0, end + 2);
      std::string event = "message", text;
      std::size_t start = 0;
      while (start <= block.size()) {
        std::size_t nl = block.find('\n', start);
        const std::string line = block.substr(start, nl == std::string::npos ? std::string::npos : nl - start);
        if (line.rfind("event: ", 0) == 0) event = line.substr(7);
        if (line.rfind("data: ", 0) == 0) text += line.substr(6);
        if (nl == std::string::npos) break;
        start = nl + 1;
      }
      Json d = Json::parse(text, nullptr, false);
      if (d.is_discarded()) continue;
      if (json) {
        Json out = {{"event", event}, {"data", d}};
        std::cout << out.dump() << "\n" << std::flush;
      } else {
        std::cout << Line(event, d) << "\n" << std::flush;
      }
    }
    return true;
  });
  return res && res->status == 200;
}

}  // namespace

int RunServerExecute(const ServerExecuteOptions& o) {
  Diagnostics diags;
  auto plan = ReadJsonFile(o.file, diags);
  if (!plan) {
    PrintError(Error::FromDiagnostics(ErrorCode::kInvalidInput, "cannot read " + o.file, diags));
    return 2;
  }
  Json body = {{"state_plan", *plan}, {"adapter", "sim"}, {"speed", o.speed},
               {"sim", {{"fail", o.fail}, {"seed", o.seed}}},
               {"options", {{"time_limit_ms", o.time_limit_ms}}}};
  if (!o.objective.empty()) body["options"]["objective"] = o.objective;
  if (auto e = AddDomain(body, o.domain)) {
    PrintError(*e);
    return 2;
  }
  auto started = PostJson(o.server, "/executions", body, o.time_limit_ms);
  if (auto* e = std::get_if<Error>(&started)) {
    PrintError(*e);
    return e->code == ErrorCode::kInvalidInput ? 2 : 3;
  }
  const std::string id = std::get<Json>(started).value("execution", "");
  if (!o.json) std::cout << "execution " << id << " on " << o.server << "\n";
  if (!Follow(o.server, id, o.json)) {
    PrintError({ErrorCode::kUnavailable, "lost the events of execution " + id, {}});
    return 3;
  }
  httplib::Client cli(o.server);
  auto res = cli.Get(("/executions/" + id).c_str());
  Json v = res ? Json::parse(res->body, nullptr, false) : Json();
  if (!v.is_object()) return 3;
  const Json summary = {{"execution", id}, {"state", v.value("state", "")}, {"replans", v.value("replans", 0)},
                        {"history", v.value("history", Json::array()).size()}};
  if (o.json) std::cout << summary.dump() << "\n";
  return v.value("state", "") == "succeeded" ? 0 : 1;
}

}  // namespace ctb::cli
