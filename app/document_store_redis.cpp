// Redis document store (document_store.h): the hash ctb:<kind>:<id> -> version, created_ms,
// updated_ms, doc, and the index ctb:<kind>s. A kind that expires keeps a sorted set (id by last
// write, for the cap and the expiry) and an EXPIRE of the idle time on each hash; a kind that
// never expires keeps a set of ids. Every call but Get is one Lua script, so each is atomic across
// replicas: the compare-and-set on the version and the cap check cannot interleave. One connection
// behind a mutex; a broken connection is reopened on the next call.
#include <hiredis/hiredis.h>

#include <algorithm>
#include <cstdlib>
#include <mutex>

#include "app/document_store.h"
#include "app/store_common.h"

namespace ctb::app::store {

namespace {

// What every script starts with. KEYS: the document's key, the index; ARGV: id, now, idle_ms
// (0: the kind never expires and its index is a set), then the script's own.
const char* kPrelude = R"(
local now, idle = tonumber(ARGV[2]), tonumber(ARGV[3])
local function expire()
  if idle > 0 then redis.call('ZREMRANGEBYSCORE', KEYS[2], '-inf', now - idle) end
end
local function size()
  expire()
  if idle > 0 then return redis.call('ZCARD', KEYS[2]) end
  return redis.call('SCARD', KEYS[2])
end
local function ids()
  expire()
  if idle > 0 then return redis.call('ZRANGE', KEYS[2], 0, -1) end
  return redis.call('SMEMBERS', KEYS[2])
end
local function touch()
  if idle > 0 then
    redis.call('PEXPIRE', KEYS[1], idle)
    redis.call('ZADD', KEYS[2], ARGV[2], ARGV[1])
  else
    redis.call('SADD', KEYS[2], ARGV[1])
  end
end
)";

// ARGV[4]: max, ARGV[5]: doc. 1 created, 0 exists, -1 full.
const char* kCreate = R"(
if redis.call('EXISTS', KEYS[1]) == 1 then return 0 end
if size() >= tonumber(ARGV[4]) then return -1 end
redis.call('HSET', KEYS[1], 'version', 1, 'created_ms', ARGV[2], 'updated_ms', ARGV[2], 'doc', ARGV[5])
touch()
return 1
)";

// ARGV[4]: the expected version ("" for any), ARGV[5]: doc. The new version, 0 when the version
// changed, -1 when gone.
const char* kWrite = R"(
local v = redis.call('HGET', KEYS[1], 'version')
if not v then return -1 end
if ARGV[4] ~= '' and tonumber(v) ~= tonumber(ARGV[4]) then return 0 end
redis.call('HSET', KEYS[1], 'version', tonumber(v) + 1, 'updated_ms', ARGV[2], 'doc', ARGV[5])
touch()
return tonumber(v) + 1
)";

// 1 deleted, 0 absent.
const char* kDelete = R"(
local n = redis.call('DEL', KEYS[1])
if idle > 0 then redis.call('ZREM', KEYS[2], ARGV[1]) else redis.call('SREM', KEYS[2], ARGV[1]) end
return n
)";

const char* kCount = "return size()";
const char* kList = "return ids()";

// ARGV[4]: field, ARGV[5]: value, ARGV[6]: the documents' key prefix. The live documents whose
// field is the value.
const char* kCountWhere = R"(
local n = 0
for _, id in ipairs(ids()) do
  local doc = redis.call('HGET', ARGV[6] .. id, 'doc')
  if doc then
    local ok, d = pcall(cjson.decode, doc)
    if ok and type(d) == 'table' and d[ARGV[4]] == ARGV[5] then n = n + 1 end
  end
end
return n
)";

class RedisDocuments : public DocumentStore {
 public:
  RedisDocuments(std::string host, int port, int db, const DocumentStoreConfig& c)
      : conn_(std::move(host), port, db),
        kind_(c.kind),
        prefix_("ctb:" + c.kind + ":"),
        index_("ctb:" + c.kind + "s"),
        max_(c.max),
        idle_ms_(c.idle_s * 1000) {}

  bool Connect(std::string& error) { return conn_.Connect(error); }

  std::variant<std::optional<StoredDocument>, Error> Get(const std::string& id) override {
    std::lock_guard<std::mutex> lock(mu_);
    Reply r(conn_.Call({"HMGET", prefix_ + id, "version", "created_ms", "updated_ms", "doc"}));
    if (!r || r->type != REDIS_REPLY_ARRAY || r->elements != 4) return Unavailable();
    auto str = [&](std::size_t i) -> std::optional<std::string> {
      const redisReply* e = r->element[i];
      if (e->type != REDIS_REPLY_STRING) return std::nullopt;
      return std::string(e->str, e->len);
    };
    if (!str(0) || !str(3)) return std::optional<StoredDocument>();
    StoredDocument d{id, std::atol(str(0)->c_str()), std::atol(str(1).value_or("0").c_str()),
                     std::atol(str(2).value_or("0").c_str()), Json::parse(*str(3), nullptr, false)};
    if (d.doc.is_discarded()) return Unavailable("a stored document is not JSON");
    return std::optional<StoredDocument>(std::move(d));
  }

  StoreResult Create(StoredDocument& d) override {
    std::lock_guard<std::mutex> lock(mu_);
    const long now = NowMs();
    Reply r(Eval(kCreate, d.id, now, {std::to_string(max_), Dump(d.doc)}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    if (r->integer == 0) return StoreResult::kConflict;
    if (r->integer < 0) return StoreResult::kFull;
    d.version = 1;
    d.created_ms = d.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Write(StoredDocument& d, bool any_version) override {
    std::lock_guard<std::mutex> lock(mu_);
    const long now = NowMs();
    Reply r(Eval(kWrite, d.id, now, {any_version ? "" : std::to_string(d.version), Dump(d.doc)}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    if (r->integer < 0) return StoreResult::kNotFound;
    if (r->integer == 0) return StoreResult::kConflict;
    d.version = static_cast<long>(r->integer);
    d.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Delete(const std::string& id) override {
    std::lock_guard<std::mutex> lock(mu_);
    Reply r(Eval(kDelete, id, NowMs(), {}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    return r->integer == 1 ? StoreResult::kOk : StoreResult::kNotFound;
  }

  long Count() override {
    std::lock_guard<std::mutex> lock(mu_);
    Reply r(Eval(kCount, "", NowMs(), {}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return -1;
    return static_cast<long>(r->integer);
  }

  long CountWhere(const std::string& field, const std::string& value) override {
    std::lock_guard<std::mutex> lock(mu_);
    Reply r(Eval(kCountWhere, "", NowMs(), {field, value, prefix_}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return -1;
    return static_cast<long>(r->integer);
  }

  std::variant<std::vector<std::string>, Error> List() override {
    std::lock_guard<std::mutex> lock(mu_);
    Reply r(Eval(kList, "", NowMs(), {}));
    if (!r || r->type != REDIS_REPLY_ARRAY) return Unavailable();
    std::vector<std::string> ids;
    for (std::size_t i = 0; i < r->elements; ++i)
      if (r->element[i]->type == REDIS_REPLY_STRING)
        ids.emplace_back(r->element[i]->str, r->element[i]->len);
    if (idle_ms_ <= 0) std::sort(ids.begin(), ids.end());  // a set has no order of its own
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

 private:
  // One script on the document `id` ("" for the whole kind) with the prelude's arguments first.
  Reply Eval(const char* script, const std::string& id, long now, std::vector<std::string> own) {
    std::vector<std::string> args{"EVAL",
                                  std::string(kPrelude) + script,
                                  "2",
                                  prefix_ + id,
                                  index_,
                                  id,
                                  std::to_string(now),
                                  std::to_string(idle_ms_)};
    for (auto& a : own) args.push_back(std::move(a));
    return conn_.Call(args);
  }
  Error Unavailable(const char* why = nullptr) {
    if (why) conn_.set_last_error(why);
    return Error{ErrorCode::kUnavailable, "the " + kind_ + " store failed; retry later", {}};
  }

  mutable std::mutex mu_;
  RedisConn conn_;
  std::string kind_, prefix_, index_;
  long max_, idle_ms_;
};

}  // namespace

std::unique_ptr<DocumentStore> OpenRedisDocuments(const std::string& host, int port, int db,
                                                  const DocumentStoreConfig& c,
                                                  std::string& error) {
  auto s = std::make_unique<RedisDocuments>(host, port, db, c);
  if (!s->Connect(error)) return nullptr;
  return s;
}

}  // namespace ctb::app::store
