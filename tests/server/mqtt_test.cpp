// The executive's MQTT adapter end to end (contract section 14, issue 27 item 2): a real
// mosquitto broker on a free loopback port, the real server binary with --mqtt-url, and a team of
// simulated devices written with libmosquitto in this process. The devices answer every command
// with the transition done ({"location": to, "time": at}) and play the transitions the plan has
// without a command (arrivals, doors) when their time comes, in plan order. Garbage and a report
// with an unknown location are sent on a state topic on the way: both are refused on the error
// topic and the execution goes on to succeed. Every wait is on an event or a bounded poll.
#include <mosquitto.h>

#include <condition_variable>
#include <map>
#include <set>

#include "harness.h"

namespace ctb::testing {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// mosquitto on 127.0.0.1:port, no persistence, anonymous clients; stopped with the test.
class Broker {
 public:
  explicit Broker(const std::string& dir) : port_(FreeLoopbackPort()) {
    const std::string conf = dir + "/mosquitto.conf";
    std::ofstream(conf) << "listener " << port_ << " 127.0.0.1\nallow_anonymous true\npersistence false\n";
    const char* bin = Executable("/usr/sbin/mosquitto") ? "/usr/sbin/mosquitto" : "/usr/bin/mosquitto";
    if (!Executable(bin)) {
      ADD_FAILURE() << "mosquitto is not installed: bash scripts/install-deps.sh --test";
      return;
    }
    pid_ = Spawn({bin, "-c", conf}, dir + "/mosquitto.log");
    if (!WaitForPort(port_, 10000)) ADD_FAILURE() << "mosquitto did not listen: " << ReadFile(dir + "/mosquitto.log");
  }
  ~Broker() { StopChild(pid_); }
  int port() const { return port_; }

 private:
  int port_;
  pid_t pid_ = -1;
};

struct Message {
  std::string topic;
  json payload;  // null when the payload was not JSON
};

// A transition's command, "" when the device moves on its own (the plan writes null or nothing).
std::string CommandOf(const json& t) {
  auto it = t.find("command");
  return it != t.end() && it->is_string() ? it->get<std::string>() : "";
}

std::string Key(const json& t) {
  return t.value("automaton", "") + "|" + t.value("from", "") + "|" + t.value("to", "");
}

// The transitions of `plan` that no command causes, due by `now` given what happened, in plan
// order: once every transition of an earlier event has happened (what its guard reads); at
// the planned time, or later as far as what came before was late (its automaton's previous
// transition plus the planned gap, the latest of the earlier ones). Marks them happened. `next`:
// the soonest time one that is not due yet becomes due, if any.
std::vector<std::pair<json, double>> DuePassive(const json& plan, double now, std::map<std::string, double>& happened,
                                                std::optional<double>& next) {
  std::vector<std::pair<json, double>> due;
  next.reset();
  const json transitions = plan.is_object() ? plan.value("transitions", json::array()) : json::array();
  for (std::size_t i = 0; i < transitions.size(); ++i) {
    const json& t = transitions[i];
    if (t.value("executed", false) || !CommandOf(t).empty() || happened.count(Key(t)) ||
        t.value("from", "") == t.value("to", ""))  // a stay, not a move: nothing to report
      continue;
    const double planned = t.value("time", 0.0);
    const long event = t.value("event", 0L);
    double at = planned;
    bool ready = true;
    for (std::size_t j = 0; j < transitions.size() && ready; ++j) {
      const json& c = transitions[j];
      const long ce = c.value("event", 0L);
      if (ce >= event) continue;  // a guard reads the stage before its event: causes come earlier
      if (c.value("from", "") == c.value("to", "")) continue;  // a stay (a replan's observed state)
      auto it = happened.find(Key(c));
      if (it == happened.end()) {
        ready = false;
        break;
      }
      at = std::max(at, it->second);
      if (j < i && c.value("automaton", "") == t.value("automaton", "")) {
        bool last = true;  // the automaton's previous transition: keep the planned gap after it
        for (std::size_t k = j + 1; k < i; ++k)
          if (transitions[k].value("automaton", "") == t.value("automaton", "") &&
              transitions[k].value("from", "") != transitions[k].value("to", ""))
            last = false;
        if (last) at = std::max(at, it->second + (planned - c.value("time", 0.0)));
      }
    }
    if (!ready) continue;
    if (now >= at) {
      due.push_back({t, at});
      happened[Key(t)] = at;
    } else if (!next || at < *next) {
      next = at;
    }
  }
  return due;
}

// The device side: one MQTT client that subscribes to every command and error topic, answers
// each command at once with its transition done, and (once Play() is called) a thread that
// reports the plan's transitions without a command when their time comes, on the team's own
// clock: it waits for the moment or for a change (a command answered, a new plan), never polls.
class Devices {
 public:
  // answer: reply to every command with its transition done (false: only record them).
  explicit Devices(int port, bool answer = true) : answer_(answer) {
    mosquitto_lib_init();
    m_ = mosquitto_new(("ctb-test-devices-" + std::to_string(getpid())).c_str(), true, this);
    mosquitto_connect_callback_set(m_, [](mosquitto* m, void*, int rc) {
      if (rc == 0) {
        mosquitto_subscribe(m, nullptr, "ctburton/+/+/command", 1);
        mosquitto_subscribe(m, nullptr, "ctburton/+/+/error", 1);
      }
    });
    mosquitto_subscribe_callback_set(m_, [](mosquitto*, void* self, int, int, const int*) {
      auto* d = static_cast<Devices*>(self);
      std::lock_guard<std::mutex> lock(d->mu_);
      ++d->subscribed_;
      d->cv_.notify_all();
    });
    mosquitto_message_callback_set(m_, [](mosquitto*, void* self, const mosquitto_message* msg) {
      static_cast<Devices*>(self)->OnMessage(msg);
    });
    EXPECT_EQ(mosquitto_connect(m_, "127.0.0.1", port, 30), MOSQ_ERR_SUCCESS);
    EXPECT_EQ(mosquitto_loop_start(m_), MOSQ_ERR_SUCCESS);
  }
  ~Devices() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
      cv_.notify_all();
    }
    if (player_.joinable()) player_.join();
    mosquitto_disconnect(m_);
    mosquitto_loop_stop(m_, false);
    mosquitto_destroy(m_);
  }

  bool WaitCommands(std::size_t n, long ms) {
    std::unique_lock<std::mutex> lock(mu_);
    return cv_.wait_for(lock, std::chrono::milliseconds(ms), [&] { return commands_.size() >= n; });
  }
  bool WaitSubscribed(long ms) {
    std::unique_lock<std::mutex> lock(mu_);
    return cv_.wait_for(lock, std::chrono::milliseconds(ms), [&] { return subscribed_ >= 2; });
  }
  // Waits until `n` error messages came.
  bool WaitErrors(std::size_t n, long ms) {
    std::unique_lock<std::mutex> lock(mu_);
    return cv_.wait_for(lock, std::chrono::milliseconds(ms), [&] { return errors_.size() >= n; });
  }
  void Publish(const std::string& topic, const std::string& payload) {
    EXPECT_EQ(mosquitto_publish(m_, nullptr, topic.c_str(), static_cast<int>(payload.size()), payload.data(), 1, false),
              MOSQ_ERR_SUCCESS);
  }
  // Plays execution `id`'s passive transitions; plan time = (now - origin) * speed.
  void Play(const std::string& id, Clock::time_point origin, double speed, std::ofstream* trace) {
    player_ = std::thread([this, id, origin, speed, trace] {
      std::unique_lock<std::mutex> lock(mu_);
      while (!stop_) {
        const double now = std::chrono::duration<double>(Clock::now() - origin).count() * speed;
        std::optional<double> next;
        for (const auto& [t, at] : DuePassive(plan_, now, happened_, next)) {
          json report = {{"location", t.value("to", "")}, {"time", at}};
          Publish("ctburton/" + id + "/" + t.value("automaton", "") + "/state", report.dump());
          if (trace) *trace << now << " " << t.value("automaton", "") << " " << report.dump() << std::endl;
        }
        if (next)
          cv_.wait_until(lock, origin + std::chrono::duration_cast<Clock::duration>(
                                            std::chrono::duration<double>(*next / speed)));
        else
          cv_.wait(lock);
      }
    });
  }
  // What GET /executions/{id} says: the plan being dispatched and the history.
  void Update(const json& view) {
    std::lock_guard<std::mutex> lock(mu_);
    for (const auto& h : view.value("history", json::array())) happened_.emplace(Key(h), h.value("time", 0.0));
    if (view.contains("plan") && view["plan"] != plan_) plan_ = view["plan"];
    cv_.notify_all();
  }
  std::vector<Message> commands() {
    std::lock_guard<std::mutex> lock(mu_);
    return commands_;
  }
  std::vector<Message> errors() {
    std::lock_guard<std::mutex> lock(mu_);
    return errors_;
  }

 private:
  void OnMessage(const mosquitto_message* msg) {
    std::string topic = msg->topic;
    std::string text(static_cast<const char*>(msg->payload), static_cast<std::size_t>(msg->payloadlen));
    json payload = json::parse(text, nullptr, false);
    if (payload.is_discarded()) payload = nullptr;
    const bool command = topic.size() > 8 && topic.compare(topic.size() - 8, 8, "/command") == 0;
    std::lock_guard<std::mutex> lock(mu_);
    (command ? commands_ : errors_).push_back({topic, payload});
    cv_.notify_all();
    if (!command || !payload.is_object() || !answer_) return;
    // The device does what it was told at once: the transition is done at the command's time.
    const std::string state = topic.substr(0, topic.size() - 8) + "/state";
    const std::string automaton = topic.substr(topic.rfind('/', topic.size() - 9) + 1,
                                               topic.size() - 8 - topic.rfind('/', topic.size() - 9) - 1);
    json report = {{"location", payload.value("to", "")}, {"time", payload.value("at", json(0))}};
    Publish(state, report.dump());
    happened_[automaton + "|" + payload.value("from", "") + "|" + payload.value("to", "")] =
        payload.value("at", 0.0);
  }

  const bool answer_;
  mosquitto* m_ = nullptr;
  std::mutex mu_;
  std::condition_variable cv_;
  int subscribed_ = 0;
  bool stop_ = false;
  std::vector<Message> commands_, errors_;
  json plan_;
  std::map<std::string, double> happened_;  // automaton|from|to -> when
  std::thread player_;
};

bool WaitForLogLine(const std::string& path, const std::string& needle, long ms) {
  for (auto until = Clock::now() + std::chrono::milliseconds(ms); Clock::now() < until;) {
    if (ReadFile(path).find(needle) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

TEST(MqttExecution, DevicesOverMosquittoRunThePlanToSuccess) {
  const auto t0 = Clock::now();
  const std::string dir = TempDir("mqtt");
  Broker broker(dir);
  Devices devices(broker.port());
  ASSERT_TRUE(devices.WaitSubscribed(10000)) << "the devices did not subscribe";
  const std::string url = "mqtt://127.0.0.1:" + std::to_string(broker.port());
  const std::string log = dir + "/server.log";
  ServerProcess server(json::object(),
                       {"--mqtt-url", url, "--mqtt-client-id", "ctb-test-server-" + std::to_string(getpid()),
                        "--data-dir", dir + "/data"},
                       {}, log);
  ASSERT_TRUE(WaitForLogLine(log, "subscribed to ctburton/+/+/state", 10000)) << ReadFile(log);
  EXPECT_NE(ReadFile(log).find(url), std::string::npos) << "the MQTT URL is logged at start-up";

  auto http = server.Client(30);
  const double speed = 20;
  json body = {{"domain", "search_rescue"},
               {"state_plan", json::parse(ReadFile(SourceDir() + "/config/examples/search_rescue/test1.json"))},
               {"adapter", "mqtt"},
               {"speed", speed}};
  auto started = http.Post("/executions", body.dump(), "application/json");
  ASSERT_TRUE(started);
  ASSERT_EQ(started->status / 100, 2) << started->body;
  const auto answered = Clock::now();  // the execution's clock started before this
  const std::string id = json::parse(started->body).at("execution");
  const std::string base = "ctburton/" + id + "/robot1/";

  // Garbage, then a location robot1 lacks: both refused on the error topic; the run goes on.
  devices.Publish(base + "state", "{not json");
  devices.Publish(base + "state", R"({"location": "onTheMoon", "time": 0})");

  std::ofstream trace(dir + "/reports.txt");  // what the devices reported on their own, and when
  json view;
  bool playing = false;
  for (auto until = Clock::now() + std::chrono::seconds(60);;) {
    auto got = http.Get("/executions/" + id);
    ASSERT_TRUE(got);
    ASSERT_EQ(got->status, 200) << got->body;
    const auto received = Clock::now();
    view = json::parse(got->body);
    devices.Update(view);
    if (!playing) {
      // The team's clock. The server read its "now" before `received`, and its
      // execution began before `answered`: the latest origin those allow keeps the devices' clock
      // at or behind the server's, so no report is ever "after now" however slow the machine
      // (a refused report would never be sent again). Behind only makes reports late, which the
      // executive survives by replanning.
      std::ofstream(dir + "/first.json") << view.dump(1);
      const double now = view.value("now", 0.0);
      auto origin = received - std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(now / speed));
      devices.Play(id, std::min(origin, answered), speed, &trace);
      playing = true;
    }
    if (view.value("state", "") != "running") break;
    ASSERT_LT(Clock::now(), until) << "still running: " << view.dump();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the poll's pace, not a wait
  }
  std::ofstream(dir + "/execution.json") << view.dump(1);
  EXPECT_EQ(view.value("state", ""), "succeeded") << view.value("why", "") << " (" << dir << "/execution.json)";
  ASSERT_TRUE(devices.WaitErrors(2, 10000)) << ReadFile(log);

  // Every dispatched command was published once, on its execution's and automaton's topic.
  std::multiset<std::string> dispatched, published;
  for (const auto& e : view.value("events", json::array()))
    if (e.value("event", "") == "dispatched") {
      const json& d = e["data"];
      dispatched.insert("ctburton/" + id + "/" + d.value("automaton", "") + "/command " +
                        json({{"command", d["command"]}, {"from", d["from"]}, {"to", d["to"]}, {"at", d["at"]}}).dump());
    }
  for (const auto& m : devices.commands()) published.insert(m.topic + " " + m.payload.dump());
  EXPECT_FALSE(dispatched.empty());
  EXPECT_EQ(published, dispatched);

  // The two refusals: the garbage (no pointer) and the unknown location (at /location).
  auto errors = devices.errors();
  ASSERT_EQ(errors.size(), 2u);
  for (const auto& e : errors) {
    EXPECT_EQ(e.topic, base + "error");
    EXPECT_TRUE(e.payload.contains("error") && e.payload.contains("path")) << e.payload.dump();
  }
  EXPECT_EQ(errors[0].payload.value("path", "?"), "");
  EXPECT_EQ(errors[1].payload.value("path", "?"), "/location") << errors[1].payload.dump();
  const std::string text = ReadFile(log);
  EXPECT_NE(text.find("refused: the payload is not JSON"), std::string::npos) << text;
  EXPECT_NE(text.find("onTheMoon"), std::string::npos) << "the unknown location is logged: " << text;
  EXPECT_TRUE(server.Alive());
  EXPECT_EQ(server.Stop(10000), 0) << "SIGTERM drains and stops the adapter: " << ReadFile(log);
  std::printf("mqtt execution test: %.1f s wall\n",
              std::chrono::duration<double>(Clock::now() - t0).count());
}

// Contract 14, precisely: the server's subscription is a persistent session, so a report
// published while it is down is delivered when it is back (same client id), to the execution it
// resumed from the store.
TEST(MqttExecution, AReportPublishedWhileTheServerIsDownIsStoredWhenItIsBack) {
  const std::string dir = TempDir("mqtt-restart");
  Broker broker(dir);
  Devices devices(broker.port(), /*answer=*/false);
  ASSERT_TRUE(devices.WaitSubscribed(10000));
  const std::vector<std::string> args = {"--mqtt-url", "mqtt://127.0.0.1:" + std::to_string(broker.port()),
                                         "--mqtt-client-id", "ctb-test-restart-" + std::to_string(getpid()),
                                         "--data-dir", dir + "/data"};
  std::string id;
  {
    ServerProcess server(json::object(), args, {}, dir + "/server1.log");
    ASSERT_TRUE(WaitForLogLine(dir + "/server1.log", "subscribed to ctburton/+/+/state", 10000));
    json body = {{"domain", "search_rescue"},
                 {"state_plan", json::parse(ReadFile(SourceDir() + "/config/examples/search_rescue/test1.json"))},
                 {"adapter", "mqtt"},
                 {"speed", 1}};
    auto started = server.Client(30).Post("/executions", body.dump(), "application/json");
    ASSERT_TRUE(started);
    ASSERT_EQ(started->status / 100, 2) << started->body;
    id = json::parse(started->body).at("execution");
    ASSERT_TRUE(devices.WaitCommands(1, 10000)) << "no command came";
    ASSERT_EQ(server.Stop(10000), 0);
  }
  // The first command's move, done while no server listens.
  const json first = devices.commands().front().payload;
  const std::string topic = devices.commands().front().topic;
  const std::string automaton = topic.substr(topic.find('/', 9) + 1, topic.rfind('/') - topic.find('/', 9) - 1);
  devices.Publish(topic.substr(0, topic.rfind('/')) + "/state",
                  json({{"location", first.at("to")}, {"time", first.at("at")}}).dump());

  ServerProcess server(json::object(), args, {}, dir + "/server2.log");
  auto http = server.Client(30);
  json view;
  bool stored = false;
  for (auto until = Clock::now() + std::chrono::seconds(20); !stored && Clock::now() < until;) {
    auto got = http.Get("/executions/" + id);
    ASSERT_TRUE(got);
    ASSERT_EQ(got->status, 200) << got->body;
    view = json::parse(got->body);
    for (const auto& h : view.value("history", json::array()))
      stored = stored || (h.value("automaton", "") == automaton && h.value("to", "") == first.value("to", ""));
    if (!stored) std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the poll's pace
  }
  EXPECT_TRUE(stored) << view.dump(1) << ReadFile(dir + "/server2.log");
  EXPECT_EQ(view.value("state", ""), "running") << view.dump(1);
  EXPECT_EQ(server.Stop(10000), 0);
}

}  // namespace
}  // namespace ctb::testing
