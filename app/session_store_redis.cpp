// Redis session store: one hash per session (ctb:session:<id> -> version, created_ms,
// updated_ms, doc) with an EXPIRE of the idle time, and a sorted set ctb:sessions (id by
// updated_ms) for the cap. Create, Update and Delete are Lua scripts, so each is atomic across
// replicas: the compare-and-set on the version and the cap check cannot interleave.
// One connection behind a mutex; a broken connection is reopened on the next call.
#include <hiredis/hiredis.h>

#include <chrono>
#include <mutex>

#include "app/session_store.h"

namespace ctb::app {

namespace {

long NowMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// KEYS: session key, index; ARGV: id, now, idle_ms, max, doc. 1 created, 0 full.
const char* kCreate = R"(
redis.call('ZREMRANGEBYSCORE', KEYS[2], '-inf', tonumber(ARGV[2]) - tonumber(ARGV[3]))
if redis.call('ZCARD', KEYS[2]) >= tonumber(ARGV[4]) then return 0 end
redis.call('HSET', KEYS[1], 'version', 1, 'created_ms', ARGV[2], 'updated_ms', ARGV[2], 'doc', ARGV[5])
redis.call('PEXPIRE', KEYS[1], ARGV[3])
redis.call('ZADD', KEYS[2], ARGV[2], ARGV[1])
return 1
)";

// KEYS: session key, index; ARGV: id, now, idle_ms, expected version, doc.
// 1 written, 0 version changed, -1 gone.
const char* kUpdate = R"(
local v = redis.call('HGET', KEYS[1], 'version')
if not v then return -1 end
if tonumber(v) ~= tonumber(ARGV[4]) then return 0 end
redis.call('HSET', KEYS[1], 'version', tonumber(v) + 1, 'updated_ms', ARGV[2], 'doc', ARGV[5])
redis.call('PEXPIRE', KEYS[1], ARGV[3])
redis.call('ZADD', KEYS[2], ARGV[2], ARGV[1])
return 1
)";

class RedisStore : public SessionStore {
 public:
  RedisStore(std::string host, int port, int db, long max_sessions, long idle_s)
      : host_(std::move(host)), port_(port), db_(db), max_(max_sessions), idle_ms_(idle_s * 1000) {}
  ~RedisStore() override {
    if (c_) redisFree(c_);
  }

  bool Connect(std::string& error) {
    if (c_) redisFree(c_);
    timeval tv{2, 0};
    c_ = redisConnectWithTimeout(host_.c_str(), port_, tv);
    if (!c_ || c_->err) {
      error = "cannot connect to redis at " + host_ + ":" + std::to_string(port_) + ": " +
              (c_ ? c_->errstr : "out of memory");
      if (c_) redisFree(c_);
      c_ = nullptr;
      return false;
    }
    redisSetTimeout(c_, tv);
    Reply r(Command({"SELECT", std::to_string(db_)}));
    if (!r.p || r.p->type == REDIS_REPLY_ERROR) {
      error = "cannot select redis database " + std::to_string(db_);
      return false;
    }
    return true;
  }

  std::variant<std::optional<StoredSession>, Error> Get(const std::string& id) override {
    std::lock_guard<std::mutex> lock(mu_);
    Reply r(Call({"HMGET", Key(id), "version", "created_ms", "updated_ms", "doc"}));
    if (!r.p || r.p->type != REDIS_REPLY_ARRAY || r.p->elements != 4)
      return Error{ErrorCode::kUnavailable, "the session store failed; retry later", {}};
    auto str = [&](std::size_t i) -> std::optional<std::string> {
      const redisReply* e = r.p->element[i];
      if (e->type != REDIS_REPLY_STRING) return std::nullopt;
      return std::string(e->str, e->len);
    };
    if (!str(0) || !str(3)) return std::optional<StoredSession>();
    StoredSession s;
    s.id = id;
    s.version = std::atol(str(0)->c_str());
    s.created_ms = std::atol(str(1).value_or("0").c_str());
    s.updated_ms = std::atol(str(2).value_or("0").c_str());
    s.doc = Json::parse(*str(3), nullptr, false);
    if (s.doc.is_discarded()) return Error{ErrorCode::kUnavailable, "the session store holds a bad record", {}};
    return std::optional<StoredSession>(std::move(s));
  }

  StoreResult Create(StoredSession& s) override {
    std::lock_guard<std::mutex> lock(mu_);
    const long now = NowMs();
    Reply r(Call({"EVAL", kCreate, "2", Key(s.id), kIndex, s.id, std::to_string(now), std::to_string(idle_ms_),
                  std::to_string(max_), s.doc.dump(-1, ' ', false, Json::error_handler_t::replace)}));
    if (!r.p || r.p->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    if (r.p->integer == 0) return StoreResult::kFull;
    s.version = 1;
    s.created_ms = s.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Update(StoredSession& s) override {
    std::lock_guard<std::mutex> lock(mu_);
    const long now = NowMs();
    Reply r(Call({"EVAL", kUpdate, "2", Key(s.id), kIndex, s.id, std::to_string(now), std::to_string(idle_ms_),
                  std::to_string(s.version), s.doc.dump(-1, ' ', false, Json::error_handler_t::replace)}));
    if (!r.p || r.p->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    if (r.p->integer == -1) return StoreResult::kNotFound;
    if (r.p->integer == 0) return StoreResult::kConflict;
    ++s.version;
    s.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Delete(const std::string& id) override {
    std::lock_guard<std::mutex> lock(mu_);
    Reply r(Call({"DEL", Key(id)}));
    if (!r.p || r.p->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    Reply z(Call({"ZREM", kIndex, id}));
    return r.p->integer == 1 ? StoreResult::kOk : StoreResult::kNotFound;
  }

  long Count() override {
    std::lock_guard<std::mutex> lock(mu_);
    Reply d(Call({"ZREMRANGEBYSCORE", kIndex, "-inf", std::to_string(NowMs() - idle_ms_)}));
    Reply r(Call({"ZCARD", kIndex}));
    if (!r.p || r.p->type != REDIS_REPLY_INTEGER) return -1;
    return static_cast<long>(r.p->integer);
  }

  std::string Describe() const override {
    return "redis://" + host_ + ":" + std::to_string(port_) + "/" + std::to_string(db_);
  }

 private:
  struct Reply {
    explicit Reply(redisReply* r) : p(r) {}
    ~Reply() {
      if (p) freeReplyObject(p);
    }
    Reply(const Reply&) = delete;
    Reply& operator=(const Reply&) = delete;
    redisReply* p;
  };
  static std::string Key(const std::string& id) { return "ctb:session:" + id; }
  static constexpr const char* kIndex = "ctb:sessions";

  redisReply* Command(const std::vector<std::string>& args) {
    if (!c_) return nullptr;
    std::vector<const char*> argv;
    std::vector<size_t> lens;
    for (const auto& a : args) {
      argv.push_back(a.data());
      lens.push_back(a.size());
    }
    return static_cast<redisReply*>(redisCommandArgv(c_, static_cast<int>(argv.size()), argv.data(), lens.data()));
  }
  // One command; on a broken connection, reconnect once and retry.
  redisReply* Call(const std::vector<std::string>& args) {
    redisReply* r = Command(args);
    if (r) return r;
    std::string error;
    if (!Connect(error)) return nullptr;
    return Command(args);
  }

  std::mutex mu_;
  redisContext* c_ = nullptr;
  std::string host_;
  int port_, db_;
  long max_, idle_ms_;
};

}  // namespace

std::unique_ptr<SessionStore> OpenRedisStore(const std::string& host, int port, int db, long max_sessions,
                                             long idle_s, std::string& error) {
  auto s = std::make_unique<RedisStore>(host, port, db, max_sessions, idle_s);
  if (!s->Connect(error)) return nullptr;
  return s;
}

}  // namespace ctb::app
