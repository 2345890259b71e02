// Redis domain store: ctb:domain:<name> (hash: version, created_ms, updated_ms, doc) and the set
// ctb:domains of names (domain_store.h). Create and Replace are Lua scripts: atomic across
// replicas. One connection behind a mutex, reopened once when broken.
#include <hiredis/hiredis.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <mutex>

#include "app/domain_store.h"
#include "app/store_common.h"

namespace ctb::app {

namespace {

using store::Dump;
using store::NowMs;

// KEYS: domain key, index; ARGV: name, now, max, doc. 1 created, 0 exists, -1 full.
const char* kCreate = R"(
if redis.call('EXISTS', KEYS[1]) == 1 then return 0 end
if redis.call('SCARD', KEYS[2]) >= tonumber(ARGV[3]) then return -1 end
redis.call('HSET', KEYS[1], 'version', 1, 'created_ms', ARGV[2], 'updated_ms', ARGV[2], 'doc', ARGV[4])
redis.call('SADD', KEYS[2], ARGV[1])
return 1
)";

// KEYS: domain key; ARGV: now, doc. The new version, or -1 when absent.
const char* kReplace = R"(
local v = redis.call('HGET', KEYS[1], 'version')
if not v then return -1 end
redis.call('HSET', KEYS[1], 'version', tonumber(v) + 1, 'updated_ms', ARGV[1], 'doc', ARGV[2])
return tonumber(v) + 1
)";

// KEYS: domain key, index; ARGV: name. 1 deleted, 0 absent.
const char* kDelete = R"(
local n = redis.call('DEL', KEYS[1])
redis.call('SREM', KEYS[2], ARGV[1])
return n
)";

class RedisDomainStore : public DomainStore {
 public:
  RedisDomainStore(std::string host, int port, int db, long max_domains)
      : conn_(std::move(host), port, db), max_(max_domains) {}

  bool Connect(std::string& error) { return conn_.Connect(error); }

  std::variant<std::optional<StoredDomain>, Error> Get(const std::string& name) override {
    std::lock_guard<std::mutex> lock(mu_);
    store::Reply r(conn_.Call({"HMGET", Key(name), "version", "created_ms", "updated_ms", "doc"}));
    if (!r || r->type != REDIS_REPLY_ARRAY || r->elements != 4) return Unavailable();
    auto str = [&](std::size_t i) -> std::optional<std::string> {
      const redisReply* e = r->element[i];
      if (e->type != REDIS_REPLY_STRING) return std::nullopt;
      return std::string(e->str, e->len);
    };
    if (!str(0) || !str(3)) return std::optional<StoredDomain>();
    StoredDomain d;
    d.name = name;
    d.version = std::atol(str(0)->c_str());
    d.created_ms = std::atol(str(1).value_or("0").c_str());
    d.updated_ms = std::atol(str(2).value_or("0").c_str());
    d.doc = Json::parse(*str(3), nullptr, false);
    if (d.doc.is_discarded()) return Unavailable();
    return std::optional<StoredDomain>(std::move(d));
  }

  std::variant<std::vector<std::string>, Error> List() override {
    std::lock_guard<std::mutex> lock(mu_);
    store::Reply r(conn_.Call({"SMEMBERS", kIndex}));
    if (!r || r->type != REDIS_REPLY_ARRAY) return Unavailable();
    std::vector<std::string> out;
    for (std::size_t i = 0; i < r->elements; ++i)
      if (r->element[i]->type == REDIS_REPLY_STRING)
        out.emplace_back(r->element[i]->str, r->element[i]->len);
    std::sort(out.begin(), out.end());
    return out;
  }

  StoreResult Create(StoredDomain& d) override {
    std::lock_guard<std::mutex> lock(mu_);
    const long now = NowMs();
    store::Reply r(conn_.Call({"EVAL", kCreate, "2", Key(d.name), kIndex, d.name, std::to_string(now),
                  std::to_string(max_), Dump(d.doc)}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    if (r->integer == 0) return StoreResult::kConflict;
    if (r->integer < 0) return StoreResult::kFull;
    d.version = 1;
    d.created_ms = d.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Replace(StoredDomain& d) override {
    std::lock_guard<std::mutex> lock(mu_);
    const long now = NowMs();
    store::Reply r(conn_.Call({"EVAL", kReplace, "1", Key(d.name), std::to_string(now), Dump(d.doc)}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    if (r->integer < 0) return StoreResult::kNotFound;
    d.version = static_cast<long>(r->integer);
    d.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Delete(const std::string& name) override {
    std::lock_guard<std::mutex> lock(mu_);
    store::Reply r(conn_.Call({"EVAL", kDelete, "2", Key(name), kIndex, name}));
    if (!r || r->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    return r->integer == 1 ? StoreResult::kOk : StoreResult::kNotFound;
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
    return conn_.Describe() + " (domains)";
  }

 private:
  static std::string Key(const std::string& name) { return "ctb:domain:" + name; }
  static constexpr const char* kIndex = "ctb:domains";
  static Error Unavailable() {
    return Error{ErrorCode::kUnavailable, "the domain store failed; retry later", {}};
  }


  mutable std::mutex mu_;
  store::RedisConn conn_;
  long max_;
};

}  // namespace

std::unique_ptr<DomainStore> OpenRedisDomainStore(const std::string& host, int port, int db,
                                                  long max_domains, std::string& error) {
  auto s = std::make_unique<RedisDomainStore>(host, port, db, max_domains);
  if (!s->Connect(error)) return nullptr;
  return s;
}

}  // namespace ctb::app
