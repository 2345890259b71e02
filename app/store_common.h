// What the document stores (document_store.h) share inside app/: the clock, the document's text,
// the kinds and their tables, an SQLite statement, a Redis connection, and the backends' openers.
#pragma once

#include <hiredis/hiredis.h>
#include <sqlite3.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "app/document_store.h"
#include "planner/model/json_io.h"

namespace ctb::app::store {

inline long NowMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// A stored document's text (invalid UTF-8 replaced, never throws).
inline std::string Dump(const Json& j) { return WireText(j); }

// The kinds of document, their SQLite tables and key columns (the stores and the salvage of a
// damaged file share them).
struct Kind {
  const char* kind;
  const char* table;
  const char* key;
};
inline constexpr Kind kKinds[] = {
    {"session", "sessions", "id"}, {"execution", "executions", "id"}, {"domain", "domains", "name"}};
// The key column of `kind`'s table ("id" for a kind not listed).
inline std::string KeyColumn(const std::string& kind) {
  for (const auto& k : kKinds)
    if (kind == k.kind) return k.key;
  return "id";
}

// The SQL that creates a table of versioned documents keyed by `key`.
inline std::string TableSql(const std::string& table, const std::string& key) {
  return "CREATE TABLE IF NOT EXISTS " + table + "(" + key + " TEXT PRIMARY KEY, version INTEGER NOT NULL,"
         " created_ms INTEGER NOT NULL, updated_ms INTEGER NOT NULL, doc TEXT NOT NULL);";
}

// The heartbeat row that DocumentStore::Probe writes.
inline const std::string kProbeTableSql = "CREATE TABLE IF NOT EXISTS ctb_probe(id INTEGER PRIMARY KEY, at_ms INTEGER NOT NULL);";

// One prepared SQLite statement, finalized on destruction.
class Stmt {
 public:
  Stmt(sqlite3* db, const char* sql) { sqlite3_prepare_v2(db, sql, -1, &s_, nullptr); }
  Stmt(sqlite3* db, const std::string& sql) : Stmt(db, sql.c_str()) {}
  ~Stmt() { sqlite3_finalize(s_); }
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;
  bool ok() const { return s_ != nullptr; }
  sqlite3_stmt* get() const { return s_; }
  Stmt& Bind(int i, const std::string& v) {
    sqlite3_bind_text(s_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  Stmt& Bind(int i, long v) {
    sqlite3_bind_int64(s_, i, v);
    return *this;
  }
  int Step() { return sqlite3_step(s_); }
  long Int(int i) { return static_cast<long>(sqlite3_column_int64(s_, i)); }
  std::string Text(int i) {
    const auto* t = sqlite3_column_text(s_, i);
    return t ? std::string(reinterpret_cast<const char*>(t), sqlite3_column_bytes(s_, i))
             : std::string();
  }

 private:
  sqlite3_stmt* s_ = nullptr;
};

// The heartbeat write of DocumentStore::Probe on an SQLite connection.
inline bool WriteProbe(sqlite3* db) {
  Stmt up(db, "INSERT OR REPLACE INTO ctb_probe(id, at_ms) VALUES (1, ?)");
  return up.ok() && up.Bind(1, NowMs()).Step() == SQLITE_DONE;
}

struct ReplyFree {
  void operator()(redisReply* r) const {
    if (r) freeReplyObject(r);
  }
};
using Reply = std::unique_ptr<redisReply, ReplyFree>;

// One Redis connection (not thread-safe: callers hold their own mutex); a broken connection is
// reopened once per call.
class RedisConn {
 public:
  RedisConn(std::string host, int port, int db) : host_(std::move(host)), port_(port), db_(db) {}
  ~RedisConn() {
    if (c_) redisFree(c_);
  }
  RedisConn(const RedisConn&) = delete;
  RedisConn& operator=(const RedisConn&) = delete;

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
    if (!r || r->type == REDIS_REPLY_ERROR) {
      error = "cannot select redis database " + std::to_string(db_);
      return false;
    }
    return true;
  }

  // One command; on a broken connection, reconnect once and retry. Null when it failed.
  Reply Call(const std::vector<std::string>& args) {
    Reply r(Command(args));
    if (!r) {
      std::string error;
      if (!Connect(error)) {
        last_error_ = error;
        return nullptr;
      }
      r.reset(Command(args));
    }
    if (!r) last_error_ = c_ && c_->err ? c_->errstr : "no reply from redis";
    else if (r->type == REDIS_REPLY_ERROR) last_error_ = std::string(r->str, r->len);
    return r;
  }

  // The heartbeat write of the stores' Probe() (the caller holds its mutex).
  bool WriteProbe() {
    Reply r(Call({"SET", "ctb:probe", std::to_string(NowMs())}));
    return r && r->type != REDIS_REPLY_ERROR;
  }

  // Why the last call failed, or what the caller found wrong in a reply (the caller holds its mutex).
  const std::string& last_error() const { return last_error_; }
  void set_last_error(std::string why) { last_error_ = std::move(why); }

 private:
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

  redisContext* c_ = nullptr;
  std::string last_error_;
  std::string host_;
  int port_, db_;
};

// The backends (document_store_sqlite.cpp, document_store_redis.cpp): null with `error` set when
// the store cannot be opened.
std::unique_ptr<DocumentStore> OpenSqliteDocuments(const std::string& path, const DocumentStoreConfig& c,
                                                   std::string& error);
std::unique_ptr<DocumentStore> OpenRedisDocuments(const std::string& host, int port, int db,
                                                  const DocumentStoreConfig& c, std::string& error);

}  // namespace ctb::app::store
