// The MQTT adapter of the executive (contract section 14): carries the commands of "mqtt"
// executions to a broker and the devices' reports back into the core.
//
//   commands: published QoS 1 to ctburton/<execution>/<automaton>/command as
//             {"command", "from", "to", "at"};
//   reports:  subscribed QoS 1 on ctburton/+/+/state; a payload {"location", "time"} or
//             {"failed", "time"} gets "automaton" from the topic and goes to
//             Core::ReportExecution(execution, report);
//   errors:   a payload that is not such an object, an unknown execution or a refused report is
//             logged (one line naming the topic and the error) and published to
//             ctburton/<execution>/<automaton>/error as {"error": message, "path": pointer}.
//
// libmosquitto runs its network loop in a thread of its own (mosquitto_loop_start) and
// reconnects by itself; the session is persistent (clean session false, the configured client
// id), so reports published while the server was away are delivered when it is back.
//
// Lifetime: Create() before the core opens (so that executions resumed from the store find the
// sink; commands sent before Connect() are kept and published once connected), Connect(core)
// once it is open, Stop() before the core is destroyed. Thread-safe; never throws; no exception
// leaves a mosquitto callback.
#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "app/core.h"
#include "mqtt/url.h"

struct mosquitto;
struct mosquitto_message;

namespace ctb::mqtt {

struct AdapterOptions {
  std::string url;                     // mqtt://host[:port]
  std::string client_id = "ctburton";  // stable: the broker keeps the session under it
  int keepalive_s = 30;
  bool publish_errors = true;          // also publish refused reports to .../error
};

class Adapter : public app::CommandSink {
 public:
  // Checks the URL and prepares the client; does not connect. The error message says what is
  // wrong (a bad URL, or libmosquitto refusing the client id).
  static std::variant<std::shared_ptr<Adapter>, std::string> Create(const AdapterOptions& options);
  ~Adapter() override;
  Adapter(const Adapter&) = delete;
  Adapter& operator=(const Adapter&) = delete;

  // Starts the network loop and connects (retrying in the background while the broker is away);
  // reports go to `core`, which must outlive Stop().
  void Connect(app::Core& core);
  // Disconnects and joins the network thread; later Sends are dropped (logged). Idempotent.
  void Stop();

  // {"automaton", "command", "from", "to", "at"}: published QoS 1 (queued by libmosquitto while
  // the broker is away).
  void Send(const std::string& execution, const Json& command) override;

  const BrokerAddress& address() const { return address_; }

 private:
  Adapter(AdapterOptions options, BrokerAddress address);
  static void OnConnect(mosquitto* m, void* self, int rc);
  static void OnDisconnect(mosquitto* m, void* self, int rc);
  static void OnMessage(mosquitto* m, void* self, const mosquitto_message* msg);
  void HandleMessage(const std::string& topic, const std::string& payload);
  void Refuse(const std::string& topic, const std::string& execution, const std::string& automaton,
              const std::string& message, const std::string& path);
  void Publish(const std::string& topic, const std::string& payload);

  AdapterOptions options_;
  BrokerAddress address_;
  mosquitto* mosq_ = nullptr;
  void ConnectLoop();

  std::mutex mu_;  // guards the fields below, and mosq_ against Stop()
  std::condition_variable wake_;
  app::Core* core_ = nullptr;
  bool looping_ = false;  // the first connection was made and the network loop runs
  bool stopped_ = false;
  // Until the broker first answers, libmosquitto's loop would not retry a refused connection:
  // this thread does, backing off from 1 s to 30 s, then starts the loop (which reconnects).
  std::thread connector_;
  std::vector<std::pair<std::string, std::string>> pending_;  // (topic, payload) sent before Connect()
};

}  // namespace ctb::mqtt
