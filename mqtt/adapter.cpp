#include "mqtt/adapter.h"

#include <mosquitto.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>
#include <mutex>

#include "app/ids.h"

namespace ctb::mqtt {

namespace {

constexpr const char* kStateFilter = "ctburton/+/+/state";

// Log lines quote what came from the network as JSON strings (no control characters).
std::string Quote(const std::string& s) {
  return Json(s).dump(-1, ' ', false, Json::error_handler_t::replace);
}

// "ctburton/<execution>/<automaton>/<leaf>" into its two names; false for any other shape.
bool SplitTopic(const std::string& topic, std::string& execution, std::string& automaton, std::string& leaf) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    auto slash = topic.find('/', start);
    parts.push_back(topic.substr(start, slash == std::string::npos ? std::string::npos : slash - start));
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  if (parts.size() != 4 || parts[0] != "ctburton" || parts[1].empty() || parts[2].empty()) return false;
  execution = parts[1];
  automaton = parts[2];
  leaf = parts[3];
  return true;
}

}  // namespace

std::variant<std::shared_ptr<Adapter>, std::string> Adapter::Create(const AdapterOptions& options) {
  auto parsed = ParseMqttUrl(options.url);
  if (auto* e = std::get_if<std::string>(&parsed)) return *e;
  if (options.client_id.empty() || options.client_id.size() > 23 * 8)
    return std::string("the MQTT client id must be 1..184 characters");
  static std::once_flag init;
  std::call_once(init, [] { mosquitto_lib_init(); });
  std::shared_ptr<Adapter> a(new Adapter(options, std::get<BrokerAddress>(parsed)));
  a->mosq_ = mosquitto_new(options.client_id.c_str(), /*clean_session=*/false, a.get());
  if (!a->mosq_) return std::string("libmosquitto could not create a client (id '" + options.client_id + "')");
  mosquitto_int_option(a->mosq_, MOSQ_OPT_PROTOCOL_VERSION, MQTT_PROTOCOL_V311);
  mosquitto_reconnect_delay_set(a->mosq_, 1, 30, true);
  mosquitto_connect_callback_set(a->mosq_, &Adapter::OnConnect);
  mosquitto_disconnect_callback_set(a->mosq_, &Adapter::OnDisconnect);
  mosquitto_message_callback_set(a->mosq_, &Adapter::OnMessage);
  return a;
}

Adapter::Adapter(AdapterOptions options, BrokerAddress address)
    : options_(std::move(options)), address_(std::move(address)) {}

Adapter::~Adapter() {
  Stop();
  if (mosq_) mosquitto_destroy(mosq_);
}

void Adapter::Connect(app::Core& core) {
  std::lock_guard<std::mutex> lock(mu_);
  if (core_ || stopped_) return;
  core_ = &core;
  connector_ = std::thread([this] { ConnectLoop(); });
}

void Adapter::ConnectLoop() {
  std::chrono::seconds delay(1);
  for (bool first = true;; first = false) {
    int rc = mosquitto_connect_async(mosq_, address_.host.c_str(), address_.port, options_.keepalive_s);
    if (rc == MOSQ_ERR_SUCCESS) break;
    if (first)
      spdlog::warn("{}", app::LogText(fmt::format("mqtt: cannot connect to {}:{} yet ({}); retrying in the background", address_.host,
                   address_.port, rc == MOSQ_ERR_ERRNO ? std::strerror(errno) : mosquitto_strerror(rc))));
    std::unique_lock<std::mutex> lock(mu_);
    if (wake_.wait_for(lock, delay, [this] { return stopped_; })) return;
    delay = std::min(delay * 2, std::chrono::seconds(30));
  }
  std::lock_guard<std::mutex> lock(mu_);
  if (stopped_) return;
  int rc = mosquitto_loop_start(mosq_);
  if (rc != MOSQ_ERR_SUCCESS) {
    spdlog::error("{}", app::LogText(fmt::format("mqtt: the network loop did not start: {}", mosquitto_strerror(rc))));
    return;
  }
  looping_ = true;
  for (auto& [topic, payload] : pending_) Publish(topic, payload);  // in the order they were sent
  pending_.clear();
}

void Adapter::Stop() {
  bool looping = false;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (stopped_) return;
    stopped_ = true;
  }
  wake_.notify_all();
  if (connector_.joinable()) connector_.join();
  {
    std::lock_guard<std::mutex> lock(mu_);
    looping = looping_;
  }
  if (looping) {
    mosquitto_disconnect(mosq_);
    mosquitto_loop_stop(mosq_, /*force=*/false);  // the loop ends once disconnected
  }
  std::lock_guard<std::mutex> lock(mu_);
  core_ = nullptr;
}

void Adapter::Publish(const std::string& topic, const std::string& payload) {
  int rc = mosquitto_publish(mosq_, nullptr, topic.c_str(), static_cast<int>(payload.size()), payload.data(),
                             /*qos=*/1, /*retain=*/false);
  if (rc != MOSQ_ERR_SUCCESS) spdlog::error("{}", app::LogText(fmt::format("mqtt: publishing to {} failed: {}", Quote(topic), mosquitto_strerror(rc))));
}

void Adapter::Send(const std::string& execution, const Json& command) {
  try {
    const std::string topic = "ctburton/" + execution + "/" + command.value("automaton", "") + "/command";
    Json payload = {{"command", command.value("command", "")},
                    {"from", command.value("from", "")},
                    {"to", command.value("to", "")},
                    {"at", command.value("at", Json(0))}};
    const std::string text = payload.dump(-1, ' ', false, Json::error_handler_t::replace);
    std::lock_guard<std::mutex> lock(mu_);
    if (stopped_) {
      spdlog::warn("{}", app::LogText(fmt::format("mqtt: stopped; command not published to {}", Quote(topic))));
      return;
    }
    if (!looping_) {
      if (!pending_.empty() && pending_.size() >= 10000) pending_.erase(pending_.begin());  // bounded
      pending_.emplace_back(topic, text);
      return;
    }
    Publish(topic, text);
  } catch (const std::exception& e) {
    spdlog::error("{}", app::LogText(fmt::format("mqtt: execution {}: command not published: {}", Quote(execution), e.what())));
  }
}

void Adapter::OnConnect(mosquitto* m, void* self, int rc) {
  try {
    auto* a = static_cast<Adapter*>(self);
    if (rc != 0) {
      spdlog::warn("{}", app::LogText(fmt::format("mqtt: the broker {}:{} refused the connection: {}", a->address_.host, a->address_.port,
                   mosquitto_connack_string(rc))));
      return;
    }
    int s = mosquitto_subscribe(m, nullptr, kStateFilter, 1);
    if (s != MOSQ_ERR_SUCCESS)
      spdlog::error("{}", app::LogText(fmt::format("mqtt: cannot subscribe to {}: {}", kStateFilter, mosquitto_strerror(s))));
    else
      spdlog::info("{}", app::LogText(fmt::format("mqtt: connected to {}:{}, subscribed to {}", a->address_.host, a->address_.port, kStateFilter)));
  } catch (...) {
  }
}

void Adapter::OnDisconnect(mosquitto*, void* self, int rc) {
  try {
    auto* a = static_cast<Adapter*>(self);
    if (rc != 0)
      spdlog::warn("{}", app::LogText(fmt::format("mqtt: lost the broker {}:{} ({}); reconnecting", a->address_.host, a->address_.port,
                   mosquitto_strerror(rc))));
  } catch (...) {
  }
}

void Adapter::OnMessage(mosquitto*, void* self, const mosquitto_message* msg) {
  try {
    if (!msg || !msg->topic) return;
    std::string payload;
    if (msg->payload && msg->payloadlen > 0)
      payload.assign(static_cast<const char*>(msg->payload), static_cast<std::size_t>(msg->payloadlen));
    static_cast<Adapter*>(self)->HandleMessage(msg->topic, payload);
  } catch (const std::exception& e) {
    try {
      spdlog::error("{}", app::LogText(fmt::format("mqtt: a message could not be handled: {}", e.what())));
    } catch (...) {
    }
  } catch (...) {
  }
}

void Adapter::Refuse(const std::string& topic, const std::string& execution, const std::string& automaton,
                     const std::string& message, const std::string& path) {
  spdlog::warn("{}", app::LogText(fmt::format("mqtt: report on {} refused: {}{}", Quote(topic), message, path.empty() ? "" : " (at " + path + ")")));
  if (!options_.publish_errors) return;
  Json body = {{"error", message}, {"path", path}};
  Publish("ctburton/" + execution + "/" + automaton + "/error",
          body.dump(-1, ' ', false, Json::error_handler_t::replace));
}

void Adapter::HandleMessage(const std::string& topic, const std::string& payload) {
  std::string execution, automaton, leaf;
  if (!SplitTopic(topic, execution, automaton, leaf) || leaf != "state") {
    spdlog::warn("{}", app::LogText(fmt::format("mqtt: ignored a message on {}: not ctburton/<execution>/<automaton>/state", Quote(topic))));
    return;
  }
  Json body = Json::parse(payload, nullptr, /*allow_exceptions=*/false);
  if (body.is_discarded()) return Refuse(topic, execution, automaton, "the payload is not JSON", "");
  if (!body.is_object())
    return Refuse(topic, execution, automaton,
                  "the payload must be an object {\"location\", \"time\"} or {\"failed\", \"time\"}", "");
  if (body.contains("automaton")) {
    if (!body["automaton"].is_string() || body["automaton"].get<std::string>() != automaton)
      return Refuse(topic, execution, automaton, "the automaton is the topic's: leave it out of the payload",
                    "/automaton");
  }
  body["automaton"] = automaton;
  app::Core* core = nullptr;
  {
    std::lock_guard<std::mutex> lock(mu_);
    core = core_;
  }
  if (!core) return;
  auto r = core->ReportExecution(execution, body);
  if (auto* e = std::get_if<Error>(&r)) {
    std::string message = e->message;
    std::string path;
    if (!e->details.empty()) {
      path = e->details.front().pointer;
      message += ": " + e->details.front().message;
    }
    return Refuse(topic, execution, automaton, message, path);
  }
  const Json& answer = std::get<Json>(r);
  spdlog::debug("mqtt: report on {} stored{}", Quote(topic), answer.value("duplicate", false) ? " (duplicate)" : "");
}

}  // namespace ctb::mqtt
