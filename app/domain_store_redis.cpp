// Redis domain store: ctb:domain:<name> (hash: version, created_ms, updated_ms, doc) and the set
// ctb:domains of names (domain_store.h). Create and Replace are Lua scripts: atomic across
// replicas. One connection behind a mutex, reopened once when broken.
#include <hiredis/hiredis.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <mutex>

#include "app/domain_store.h"

namespace ctb::app {

namespace {

long NowMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

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
      : host_(std::move(host)), port_(port), db_(db), max_(max_domains) {}
  ~RedisDomainStore() override {
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

  std::variant<std::optional<StoredDomain>, Error> Get(const std::string& name) override {
    std::lock_guard<std::mutex> lock(mu_);
    Reply r(Call({"HMGET", Key(name), "version", "created_ms", "updated_ms", "doc"}));
    if (!r.p || r.p->type != REDIS_REPLY_ARRAY || r.p->elements != 4) return Unavailable();
    auto str = [&](std::size_t i) -> std::optional<std::string> {
      const redisReply* e = r.p->element[i];
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
    Reply r(Call({"SMEMBERS", kIndex}));
    if (!r.p || r.p->type != REDIS_REPLY_ARRAY) return Unavailable();
    std::vector<std::string> out;
    for (std::size_t i = 0; i < r.p->elements; ++i)
      if (r.p->element[i]->type == REDIS_REPLY_STRING)
        out.emplace_back(r.p->element[i]->str, r.p->element[i]->len);
    std::sort(out.begin(), out.end());
    return out;
  }

  StoreResult Create(StoredDomain& d) override {
    std::lock_guard<std::mutex> lock(mu_);
    const long now = NowMs();
    Reply r(Call({"EVAL", kCreate, "2", Key(d.name), kIndex, d.name, std::to_string(now),
                  std::to_string(max_), Dump(d.doc)}));
    if (!r.p || r.p->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    if (r.p->integer == 0) return StoreResult::kConflict;
    if (r.p->integer < 0) return StoreResult::kFull;
    d.version = 1;
    d.created_ms = d.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Replace(StoredDomain& d) override {
    std::lock_guard<std::mutex> lock(mu_);
    const long now = NowMs();
    Reply r(Call({"EVAL", kReplace, "1", Key(d.name), std::to_string(now), Dump(d.doc)}));
    if (!r.p || r.p->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    if (r.p->integer < 0) return StoreResult::kNotFound;
    d.version = static_cast<long>(r.p->integer);
    d.updated_ms = now;
    return StoreResult::kOk;
  }

  StoreResult Delete(const std::string& name) override {
    std::lock_guard<std::mutex> lock(mu_);
    Reply r(Call({"EVAL", kDelete, "2", Key(name), kIndex, name}));
    if (!r.p || r.p->type != REDIS_REPLY_INTEGER) return StoreResult::kUnavailable;
    return r.p->integer == 1 ? StoreResult::kOk : StoreResult::kNotFound;
  }

  std::string Describe() const override {
    return "redis://" + host_ + ":" + std::to_string(port_) + "/" + std::to_string(db_) +
           " (domains)";
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
  static std::string Key(const std::string& name) { return "ctb:domain:" + name; }
  static constexpr const char* kIndex = "ctb:domains";
  static std::string Dump(const Json& j) {
    return j.dump(-1, ' ', false, Json::error_handler_t::replace);
  }
  static Error Unavailable() {
    return Error{ErrorCode::kUnavailable, "the domain store failed; retry later", {}};
  }

  redisReply* Command(const std::vector<std::string>& args) {
    if (!c_) return nullptr;
    std::vector<const char*> argv;
    std::vector<size_t> lens;
    for (const auto& a : args) {
      argv.push_back(a.data());
      lens.push_back(a.size());
    }
    return static_cast<redisReply*>(
        redisCommandArgv(c_, static_cast<int>(argv.size()), argv.data(), lens.data()));
  }
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
