// The document store (app/document_store.h) on SQLite (a file in a temporary directory, reopened
// to show persistence) and on a real redis-server on a free loopback port (two store objects as
// two replicas): domains (never expire, a set index) and sessions (expire, capped, a sorted-set
// index), and the layouts the stores before issue 31 wrote, read and written by this one.
#include "app/document_store.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "app/store_common.h"

namespace ctb::app {
namespace {

using Store = std::unique_ptr<DocumentStore>;

Json Doc(const std::string& name, int n) {
  return {{"name", name}, {"parameters", {{"N", n}}}, {"automata", Json::array()}};
}

int FreePort() {
  int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
  close(s);
  return ntohs(a.sin_port);
}

bool Listening(int port) {
  int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bool ok = connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  close(s);
  return ok;
}

std::string TempDir() {
  std::string d = "/tmp/ctb-documents-" + std::to_string(getpid()) + "-" +
                  std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
  std::filesystem::create_directories(d);
  return d;
}

// A redis-server of the test's own on a free port, stopped at the end of the scope.
class RedisServer {
 public:
  RedisServer() : dir_(TempDir()), port_(FreePort()) {
    pid_ = fork();
    if (pid_ == 0) {
      int fd = open((dir_ + "/redis.log").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(fd, 1);
      dup2(fd, 2);
      std::string p = std::to_string(port_);
      execl("/usr/bin/redis-server", "/usr/bin/redis-server", "--port", p.c_str(), "--bind",
            "127.0.0.1", "--save", "", "--appendonly", "no", "--dir", dir_.c_str(), nullptr);
      _exit(127);
    }
    for (int i = 0; i < 200 && !(up_ = Listening(port_)); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  ~RedisServer() {
    kill(pid_, SIGTERM);
    waitpid(pid_, nullptr, 0);
    std::filesystem::remove_all(dir_);
  }
  bool up() const { return up_; }
  int port() const { return port_; }
  std::string Url(int db) const {
    return "redis://127.0.0.1:" + std::to_string(port_) + "/" + std::to_string(db);
  }

 private:
  std::string dir_;
  int port_;
  pid_t pid_ = -1;
  bool up_ = false;
};

Store Open(const std::string& url, const std::string& dir, const std::string& kind, long max,
           long idle_s) {
  DocumentStoreConfig c{url, dir, kind, max, idle_s};
  auto s = OpenDocumentStore(c);
  if (auto* e = std::get_if<Error>(&s)) {
    ADD_FAILURE() << e->message;
    return nullptr;
  }
  return std::move(std::get<Store>(s));
}

std::optional<StoredDocument> Got(DocumentStore& s, const std::string& id) {
  auto got = s.Get(id);
  EXPECT_TRUE(std::holds_alternative<std::optional<StoredDocument>>(got)) << s.LastError();
  return got.index() == 0 ? std::get<0>(got) : std::nullopt;
}

std::vector<std::string> Ids(DocumentStore& s) {
  auto list = s.List();
  EXPECT_TRUE(std::holds_alternative<std::vector<std::string>>(list)) << s.LastError();
  return list.index() == 0 ? std::get<0>(list) : std::vector<std::string>{};
}

// Domains (a cap of 3, no expiry); `other` is a second handle on the same data (a replica, or the
// file reopened).
void ExerciseDomains(DocumentStore& s, DocumentStore& other) {
  StoredDocument a{"team", 0, 0, 0, Doc("team", 2)};
  ASSERT_EQ(s.Create(a), StoreResult::kOk);
  EXPECT_EQ(a.version, 1);
  StoredDocument again{"team", 0, 0, 0, Doc("team", 9)};
  EXPECT_EQ(other.Create(again), StoreResult::kConflict);
  auto g = Got(other, "team");
  ASSERT_TRUE(g);
  EXPECT_EQ(g->doc, Doc("team", 2));  // as stored, templates and all
  EXPECT_EQ(g->version, 1);
  StoredDocument b{"b_team", 0, 0, 0, Doc("b_team", 1)};
  ASSERT_EQ(other.Create(b), StoreResult::kOk);
  EXPECT_EQ(Ids(s), (std::vector<std::string>{"b_team", "team"}));  // sorted, not by age
  StoredDocument up{"team", 0, 0, 0, Doc("team", 8)};
  ASSERT_EQ(other.Replace(up), StoreResult::kOk);
  EXPECT_EQ(up.version, 2);
  EXPECT_EQ(Got(s, "team")->doc["parameters"]["N"], 8);
  StoredDocument missing{"nobody", 0, 0, 0, Doc("nobody", 1)};
  EXPECT_EQ(s.Replace(missing), StoreResult::kNotFound);
  EXPECT_EQ(s.Delete("b_team"), StoreResult::kOk);
  EXPECT_EQ(other.Delete("b_team"), StoreResult::kNotFound);
  EXPECT_FALSE(Got(other, "b_team"));
  // The cap (3 in these tests): "team" plus two more.
  StoredDocument c{"c", 0, 0, 0, Doc("c", 1)}, d{"d", 0, 0, 0, Doc("d", 1)},
      e{"e", 0, 0, 0, Doc("e", 1)};
  EXPECT_EQ(s.Create(c), StoreResult::kOk);
  EXPECT_EQ(s.Create(d), StoreResult::kOk);
  EXPECT_EQ(s.Create(e), StoreResult::kFull);
  EXPECT_EQ(other.Count(), 3);
}

// Sessions (a cap of 2): compare-and-set writes, the cap, CountWhere, oldest first.
void ExerciseSessions(DocumentStore& s, DocumentStore& other) {
  StoredDocument a{"s1", 0, 0, 0, {{"domain", "presentation"}, {"turns", Json::array()}}};
  ASSERT_EQ(s.Create(a), StoreResult::kOk);
  EXPECT_EQ(a.version, 1);
  auto read = Got(other, "s1");
  ASSERT_TRUE(read);
  StoredDocument mine = *read, theirs = *read;
  mine.doc["turns"].push_back("mine");
  theirs.doc["turns"].push_back("theirs");
  ASSERT_EQ(s.Update(mine), StoreResult::kOk);
  EXPECT_EQ(mine.version, 2);
  EXPECT_EQ(other.Update(theirs), StoreResult::kConflict)
      << "the loser of a race must not overwrite a turn";
  EXPECT_EQ(Got(other, "s1")->doc["turns"], Json::array({"mine"}));
  StoredDocument ghost{"nobody", 1, 0, 0, Json::object()};
  EXPECT_EQ(s.Update(ghost), StoreResult::kNotFound);
  std::this_thread::sleep_for(std::chrono::milliseconds(5));  // a later creation time
  StoredDocument b{"a2", 0, 0, 0, {{"domain", "drones"}}};
  ASSERT_EQ(other.Create(b), StoreResult::kOk);
  EXPECT_EQ(Ids(s), (std::vector<std::string>{"s1", "a2"}));  // oldest first, not sorted
  EXPECT_EQ(s.CountWhere("domain", "presentation"), 1);
  EXPECT_EQ(s.CountWhere("domain", "drones"), 1);
  EXPECT_EQ(s.CountWhere("domain", "nothing"), 0);
  StoredDocument c{"s3", 0, 0, 0, Json::object()};
  EXPECT_EQ(s.Create(c), StoreResult::kFull);
  EXPECT_EQ(s.Count(), 2);
  EXPECT_EQ(other.Delete("s1"), StoreResult::kOk);
  EXPECT_EQ(s.Delete("s1"), StoreResult::kNotFound);
  EXPECT_EQ(s.Create(c), StoreResult::kOk);
}

// A session idle longer than idle_s (1 s here) is gone for every call, and frees its place.
void ExerciseExpiry(DocumentStore& s) {
  StoredDocument a{"old", 0, 0, 0, {{"domain", "presentation"}}};
  ASSERT_EQ(s.Create(a), StoreResult::kOk);
  std::this_thread::sleep_for(std::chrono::milliseconds(1300));
  EXPECT_FALSE(Got(s, "old"));
  EXPECT_EQ(s.Update(a), StoreResult::kNotFound);
  EXPECT_EQ(s.CountWhere("domain", "presentation"), 0);
  EXPECT_TRUE(Ids(s).empty());
  EXPECT_EQ(s.Count(), 0);
  StoredDocument b{"new", 0, 0, 0, Json::object()};
  EXPECT_EQ(s.Create(b), StoreResult::kOk) << "the cap (1) counts live sessions only";
}

TEST(DocumentStore, SqliteKeepsDomainsAcrossAReopen) {
  std::string dir = TempDir();
  Store s = Open("", dir, "domain", 3, 0), t = Open("", dir, "domain", 3, 0);
  ASSERT_TRUE(s && t);
  ExerciseDomains(*s, *t);
  s.reset();
  t.reset();
  // A restart: a new handle on the same file sees what the old ones wrote.
  Store r = Open("sqlite", dir, "domain", 3, 0);
  auto got = Got(*r, "team");
  ASSERT_TRUE(got);
  EXPECT_EQ(got->doc["parameters"]["N"], 8);
  EXPECT_EQ(got->version, 2);
  // The sessions of the same file are untouched by the domains table (and the other way round).
  EXPECT_EQ(Open("", dir, "session", 10, 60)->Count(), 0);
  std::filesystem::remove_all(dir);
}

TEST(DocumentStore, SqliteSessionsRefuseAStaleWriteAreCappedAndExpire) {
  std::string dir = TempDir();
  Store s = Open("", dir, "session", 2, 60), t = Open("", dir, "session", 2, 60);
  ASSERT_TRUE(s && t);
  ExerciseSessions(*s, *t);
  EXPECT_EQ(Open("", dir, "execution", 2, 60)->Count(), 0)
      << "executions have a table of their own";
  ExerciseExpiry(*Open("memory", dir, "session", 1, 1));
  std::filesystem::remove_all(dir);
}

TEST(DocumentStore, RedisIsSharedByReplicas) {
  ASSERT_EQ(access("/usr/bin/redis-server", X_OK), 0)
      << "redis-server missing: scripts/install-deps.sh --test";
  RedisServer redis;
  ASSERT_TRUE(redis.up()) << "redis-server did not start";
  Store s = Open(redis.Url(2), "", "domain", 3, 0), t = Open(redis.Url(2), "", "domain", 3, 0);
  ASSERT_TRUE(s && t);
  ExerciseDomains(*s, *t);
  Store u = Open(redis.Url(2), "", "session", 2, 60), v = Open(redis.Url(2), "", "session", 2, 60);
  ASSERT_TRUE(u && v);
  ExerciseSessions(*u, *v);
  ExerciseExpiry(*Open(redis.Url(3), "", "session", 1, 1));
}

// A data directory written before issue 31 (the statements of session_store_sqlite.cpp and
// domain_store_sqlite.cpp of that time): read, written, and still of the same layout.
TEST(DocumentStore, SqliteReadsAndWritesTheEarlierLayout) {
  std::string dir = TempDir();
  const long now = store::NowMs();
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open((dir + "/sessions.db").c_str(), &db), SQLITE_OK);
    const std::string setup =
        "PRAGMA journal_mode=WAL;"
        "CREATE TABLE sessions(id TEXT PRIMARY KEY, version INTEGER NOT NULL, created_ms INTEGER "
        "NOT NULL,"
        " updated_ms INTEGER NOT NULL, doc TEXT NOT NULL);"
        "CREATE INDEX sessions_updated ON sessions(updated_ms);"
        "CREATE TABLE domains(name TEXT PRIMARY KEY, version INTEGER NOT NULL, created_ms INTEGER "
        "NOT NULL,"
        " updated_ms INTEGER NOT NULL, doc TEXT NOT NULL);";
    ASSERT_EQ(sqlite3_exec(db, setup.c_str(), nullptr, nullptr, nullptr), SQLITE_OK)
        << sqlite3_errmsg(db);
    store::Stmt s(db,
                  "INSERT INTO sessions VALUES ('old-session', 4, ?, ?, '{\"domain\":\"team\"}')");
    ASSERT_EQ(s.Bind(1, now - 1000).Bind(2, now - 1000).Step(), SQLITE_DONE);
    store::Stmt d(db, "INSERT INTO domains VALUES ('team', 2, ?, ?, ?)");
    ASSERT_EQ(d.Bind(1, now - 1000).Bind(2, now - 1000).Bind(3, Doc("team", 5).dump()).Step(),
              SQLITE_DONE);
    sqlite3_close(db);
  }
  Store sessions = Open("", dir, "session", 10, 60), domains = Open("", dir, "domain", 10, 0);
  ASSERT_TRUE(sessions && domains);
  auto old = Got(*sessions, "old-session");
  ASSERT_TRUE(old);
  EXPECT_EQ(old->version, 4);
  EXPECT_EQ(sessions->CountWhere("domain", "team"), 1);
  ASSERT_EQ(sessions->Update(*old), StoreResult::kOk);
  EXPECT_EQ(old->version, 5);
  auto team = Got(*domains, "team");
  ASSERT_TRUE(team);
  EXPECT_EQ(team->doc, Doc("team", 5));
  ASSERT_EQ(domains->Replace(*team), StoreResult::kOk);
  EXPECT_EQ(team->version, 3);
  StoredDocument fresh{"fresh", 0, 0, 0, Doc("fresh", 1)};
  ASSERT_EQ(domains->Create(fresh), StoreResult::kOk);
  sessions.reset();
  domains.reset();
  // What an earlier server would read: the same tables and columns, no new ones.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open((dir + "/sessions.db").c_str(), &db), SQLITE_OK);
  store::Stmt q(db, "SELECT name, version FROM domains ORDER BY name");
  ASSERT_EQ(q.Step(), SQLITE_ROW);
  EXPECT_EQ(q.Text(0), "fresh");
  ASSERT_EQ(q.Step(), SQLITE_ROW);
  EXPECT_EQ(q.Text(0), "team");
  EXPECT_EQ(q.Int(1), 3);
  store::Stmt t(db, "SELECT group_concat(name) FROM sqlite_master WHERE type = 'table'");
  ASSERT_EQ(t.Step(), SQLITE_ROW);
  EXPECT_EQ(t.Text(0), "sessions,domains,ctb_probe");
  sqlite3_close(db);
  std::filesystem::remove_all(dir);
}

// Keys written before issue 31 (session_store_redis.cpp and domain_store_redis.cpp of that time):
// a hash with an expiry and a sorted set for sessions, a hash and a set for domains.
TEST(DocumentStore, RedisReadsAndWritesTheEarlierKeys) {
  ASSERT_EQ(access("/usr/bin/redis-server", X_OK), 0)
      << "redis-server missing: scripts/install-deps.sh --test";
  RedisServer redis;
  ASSERT_TRUE(redis.up()) << "redis-server did not start";
  store::RedisConn raw("127.0.0.1", redis.port(), 4);
  std::string error;
  ASSERT_TRUE(raw.Connect(error)) << error;
  const std::string now = std::to_string(store::NowMs());
  auto call = [&](const std::vector<std::string>& args) {
    store::Reply r(raw.Call(args));
    EXPECT_TRUE(r && r->type != REDIS_REPLY_ERROR) << args[0] << ": " << raw.last_error();
    return r;
  };
  call({"HSET", "ctb:session:old", "version", "4", "created_ms", now, "updated_ms", now, "doc",
        "{\"domain\":\"team\"}"});
  call({"PEXPIRE", "ctb:session:old", "60000"});
  call({"ZADD", "ctb:sessions", now, "old"});
  call({"HSET", "ctb:domain:team", "version", "2", "created_ms", now, "updated_ms", now, "doc",
        Doc("team", 5).dump()});
  call({"SADD", "ctb:domains", "team"});
  Store sessions = Open(redis.Url(4), "", "session", 10, 60),
        domains = Open(redis.Url(4), "", "domain", 10, 0);
  ASSERT_TRUE(sessions && domains);
  auto old = Got(*sessions, "old");
  ASSERT_TRUE(old);
  EXPECT_EQ(old->version, 4);
  EXPECT_EQ(sessions->Count(), 1);
  EXPECT_EQ(sessions->CountWhere("domain", "team"), 1);
  ASSERT_EQ(sessions->Update(*old), StoreResult::kOk);
  EXPECT_EQ(old->version, 5);
  EXPECT_EQ(Ids(*domains), std::vector<std::string>{"team"});
  auto team = Got(*domains, "team");
  ASSERT_TRUE(team);
  ASSERT_EQ(domains->Replace(*team), StoreResult::kOk);
  EXPECT_EQ(team->version, 3);
  StoredDocument fresh{"fresh", 0, 0, 0, Doc("fresh", 1)};
  ASSERT_EQ(domains->Create(fresh), StoreResult::kOk);
  // The same types of key as before, as an earlier replica beside this one reads them.
  EXPECT_EQ(std::string(call({"TYPE", "ctb:sessions"})->str), "zset");
  EXPECT_EQ(std::string(call({"TYPE", "ctb:domains"})->str), "set");
  EXPECT_EQ(call({"SCARD", "ctb:domains"})->integer, 2);
  EXPECT_GT(call({"PTTL", "ctb:session:old"})->integer, 0);
  EXPECT_EQ(call({"PTTL", "ctb:domain:fresh"})->integer, -1) << "domains never expire";
  EXPECT_EQ(std::string(call({"HGET", "ctb:domain:team", "version"})->str), "3");
}

TEST(DocumentStore, ABadUrlIsRefused) {
  DocumentStoreConfig c;
  c.url = "postgres://x";
  auto s = OpenDocumentStore(c);
  ASSERT_TRUE(std::holds_alternative<Error>(s));
  EXPECT_EQ(std::get<Error>(s).code, ErrorCode::kInvalidInput);
}

}  // namespace
}  // namespace ctb::app
