// Redis session store: one hash per session (ctb:session:<id> -> version, created_ms,
// updated_ms, doc) with an EXPIRE of the idle time, and a sorted set ctb:sessions (id by
// updated_ms) for the cap. Create, Update and Delete are Lua scripts, so each is atomic across
// replicas: the compare-and-set on the version and the cap check cannot interleave.
// One connection behind a mutex; a broken connection is reopened on the next call.
#include <hiredis/hiredis.h>

#include <chrono>
#include <mutex>

#include "app/session_store.h"
#include "app/store_common.h"

namespace ctb::app {

namespace {

using store::NowMs;

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

// KEYS: index; ARGV: now, idle_ms, domain, key prefix. The live documents whose domain is ARGV[3].
const char* kCountUsing = R"(
local n = 0
for _, id in ipairs(redis.call('ZRANGEBYSCORE', KEYS[1], tonumber(ARGV[1]) - tonumber(ARGV[2]), '+inf')) do
  local doc = redis.call('HGET', ARGV[4] .. id, 'doc')
  if doc then
    local ok, d = pcall(cjson.decode, doc)
    if ok and type(d) == 'table' and d['domain'] == ARGV[3] then n = n + 1 end
  end
end
return n
)";

class RedisStore : public SessionStore {
 public:
  RedisStore(std::string host, int port, int db, long max_sessions, long idle_s, const std::string& kind)
      : conn_(std::move(host), port, db), prefix_("ctb:" + kind + ":"), index_("ctb:" + kind + "s"),
        max_(max_sessions), idle_ms_(idle_s * 1000) {}

  bool Connect(std::string& error) { return conn_.Connect(error); }

  std::variant<std::optional<StoredSession>, Error> Get(const std::string& id) override {
    std::lock_guard<std::mutex> lock(mu_);
    store::Reply r(conn_.Call({"HMGET", Key(id), "version", "created_ms", "updated_ms", "doc"}));
    if (!r || r->type != REDIS_REPLY_ARRAY || r->elements != 4)
      return Error{ErrorCode::kUnavailable, "the session store failed; retry later", {}};
    auto str = [&](std::size_t i) -> std::optional<std::string> {
      const redisReply* e = r->element[i];
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
    store::Reply r(conn_.Call({"EVAL", kCreate, "2", Key(s.id), index_, s.id, std::to_string(now), std::to_string(idle_ms_),
                  std::to_string(max_), store::Dump(s.doc)}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    if (r->integer == 0) return StoreResult::kFull;
    s.version = 1;
    s.created_ms = s.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Update(StoredSession& s) override {
    std::lock_guard<std::mutex> lock(mu_);
    const long now = NowMs();
    store::Reply r(conn_.Call({"EVAL", kUpdate, "2", Key(s.id), index_, s.id, std::to_string(now), std::to_string(idle_ms_),
                  std::to_string(s.version), store::Dump(s.doc)}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    if (r->integer == -1) return StoreResult::kNotFound;
    if (r->integer == 0) return StoreResult::kConflict;
    ++s.version;
    s.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Delete(const std::string& id) override {
    std::lock_guard<std::mutex> lock(mu_);
    store::Reply r(conn_.Call({"DEL", Key(id)}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    store::Reply z(conn_.Call({"ZREM", index_, id}));
    return r->integer == 1 ? StoreResult::kOk : StoreResult::kNotFound;
  }

  long Count() override {
    std::lock_guard<std::mutex> lock(mu_);
    store::Reply d(conn_.Call({"ZREMRANGEBYSCORE", index_, "-inf", std::to_string(NowMs() - idle_ms_)}));
    store::Reply r(conn_.Call({"ZCARD", index_}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return -1;
    return static_cast<long>(r->integer);
  }

  long CountUsing(const std::string& domain) override {
    std::lock_guard<std::mutex> lock(mu_);
    store::Reply r(conn_.Call({"EVAL", kCountUsing, "1", index_, std::to_string(NowMs()), std::to_string(idle_ms_), domain, prefix_}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return -1;
    return static_cast<long>(r->integer);
  }

  std::variant<std::vector<std::string>, Error> List() override {
    std::lock_guard<std::mutex> lock(mu_);
    store::Reply r(conn_.Call({"ZRANGEBYSCORE", index_, std::to_string(NowMs() - idle_ms_), "+inf"}));
    if (!r || r->type != REDIS_REPLY_ARRAY)
      return Error{ErrorCode::kUnavailable, "the " + index_ + " store failed; retry later", {}};
    std::vector<std::string> ids;
    for (std::size_t i = 0; i < r->elements; ++i)
      if (r->element[i]->type == REDIS_REPLY_STRING) ids.emplace_back(r->element[i]->str, r->element[i]->len);
    return ids;
  }

  bool Probe() override {
    std::lock_guard<std::mutex> lock(mu_);
    return conn_.WriteProbe();
  }
  std::string LastError() const override {
    std::lock_guard<std::mutex> lock(mu_);
    return conn_.last_error();
  }
  std::string Describe() const override {
    return conn_.Describe();
  }

 private:
  std::string Key(const std::string& id) const { return prefix_ + id; }


  mutable std::mutex mu_;
  store::RedisConn conn_;
  std::string prefix_, index_;
  long max_, idle_ms_;
};

}  // namespace

std::unique_ptr<SessionStore> OpenRedisStore(const std::string& host, int port, int db, long max_sessions,
                                             long idle_s, std::string& error, const std::string& kind) {
  auto s = std::make_unique<RedisStore>(host, port, db, max_sessions, idle_s, kind);
  if (!s->Connect(error)) return nullptr;
  return s;
}

}  // namespace ctb::app
