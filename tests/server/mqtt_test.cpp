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

// The device side: one MQTT client that subscribes to every command and error topic, answers
// each command at once with its transition done, and publishes what the test asks.
class Devices {
 public:
  explicit Devices(int port) {
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
    mosquitto_disconnect(m_);
    mosquitto_loop_stop(m_, false);
    mosquitto_destroy(m_);
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
    {
      std::lock_guard<std::mutex> lock(mu_);
      (command ? commands_ : errors_).push_back({topic, payload});
      cv_.notify_all();
    }
    if (!command || !payload.is_object()) return;
    // The device does what it was told at once: the transition is done at the command's time.
    const std::string state = topic.substr(0, topic.size() - 8) + "/state";
    json report = {{"location", payload.value("to", "")}, {"time", payload.value("at", json(0))}};
    Publish(state, report.dump());
  }

  mosquitto* m_ = nullptr;
  std::mutex mu_;
  std::condition_variable cv_;
  int subscribed_ = 0;
  std::vector<Message> commands_, errors_;
};

bool WaitForLogLine(const std::string& path, const std::string& needle, long ms) {
  for (auto until = Clock::now() + std::chrono::milliseconds(ms); Clock::now() < until;) {
    if (ReadFile(path).find(needle) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

std::string Key(const json& t) {
  return t.value("automaton", "") + "|" + t.value("from", "") + "|" + t.value("to", "");
}

// The transitions of the current plan that no command causes, due at `now` given what happened,
// in plan order: once every transition of an earlier event (and the commands of its own) has
// happened; at the planned time, or later as far as what came before was late (its automaton's
// previous transition plus the planned gap, the latest of the earlier ones).
std::vector<std::pair<json, double>> DuePassive(const json& view, std::map<std::string, double>& happened) {
  std::vector<std::pair<json, double>> due;
  const double now = view.value("now", 0.0);
  for (const auto& h : view.value("history", json::array())) happened[Key(h)] = h.value("time", 0.0);
  const json transitions = view.value("plan", json::object()).value("transitions", json::array());
  for (std::size_t i = 0; i < transitions.size(); ++i) {
    const json& t = transitions[i];
    if (t.value("executed", false) || !t.value("command", std::string()).empty() || happened.count(Key(t))) continue;
    const double planned = t.value("time", 0.0);
    const long event = t.value("event", 0L);
    double at = planned;
    bool ready = true;
    for (std::size_t j = 0; j < transitions.size() && ready; ++j) {
      const json& c = transitions[j];
      const long ce = c.value("event", 0L);
      if (!(ce < event || (ce == event && !c.value("command", std::string()).empty()))) continue;
      auto it = happened.find(Key(c));
      if (it == happened.end()) {
        ready = false;
        break;
      }
      at = std::max(at, it->second);
      if (j < i && c.value("automaton", "") == t.value("automaton", "")) {
        bool last = true;  // the automaton's previous transition: keep the planned gap after it
        for (std::size_t k = j + 1; k < i; ++k)
          if (transitions[k].value("automaton", "") == t.value("automaton", "")) last = false;
        if (last) at = std::max(at, it->second + (planned - c.value("time", 0.0)));
      }
    }
    if (ready && now >= at) {
      due.push_back({t, at});
      happened[Key(t)] = at;
    }
  }
  return due;
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
  json body = {{"domain", "search_rescue"},
               {"state_plan", json::parse(ReadFile(SourceDir() + "/config/examples/search_rescue/test1.json"))},
               {"adapter", "mqtt"},
               {"speed", 20}};
  auto started = http.Post("/executions", body.dump(), "application/json");
  ASSERT_TRUE(started);
  ASSERT_EQ(started->status / 100, 2) << started->body;
  const std::string id = json::parse(started->body).at("execution");
  const std::string base = "ctburton/" + id + "/robot1/";

  // Garbage, then a location robot1 lacks: both refused on the error topic; the run goes on.
  devices.Publish(base + "state", "{not json");
  devices.Publish(base + "state", R"({"location": "onTheMoon", "time": 0})");
  ASSERT_TRUE(devices.WaitErrors(2, 10000)) << ReadFile(log);

  std::map<std::string, double> happened;
  json view;
  for (auto until = Clock::now() + std::chrono::seconds(60);;) {
    auto got = http.Get("/executions/" + id);
    ASSERT_TRUE(got);
    ASSERT_EQ(got->status, 200) << got->body;
    view = json::parse(got->body);
    if (view.value("state", "") != "running") break;
    ASSERT_LT(Clock::now(), until) << "still running: " << view.dump();
    for (const auto& [t, at] : DuePassive(view, happened)) {
      json report = {{"location", t.value("to", "")}, {"time", at}};
      devices.Publish("ctburton/" + id + "/" + t.value("automaton", "") + "/state", report.dump());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));  // the poll's pace, not a wait
  }
  EXPECT_EQ(view.value("state", ""), "succeeded") << view.dump(1);

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
  std::printf("mqtt execution test: %.1f s wall\n",
              std::chrono::duration<double>(Clock::now() - t0).count());
}

}  // namespace
}  // namespace ctb::testing
