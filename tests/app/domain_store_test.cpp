// The domain store (app/domain_store.h) on SQLite (a file in a temporary directory, reopened
// to show persistence) and on a real redis-server on a free loopback port (two store objects as
// two replicas): create, read, list, replace, delete, conflicts, the cap.
#include "app/domain_store.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>


namespace ctb::app {
namespace {

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
  std::string d = "/tmp/ctb-domains-" + std::to_string(getpid()) + "-" +
                  std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
  std::filesystem::create_directories(d);
  return d;
}

// The behaviour both stores share; `other` is a second handle on the same data (a replica, or
// the file reopened).
void ExerciseStore(DomainStore& s, DomainStore& other) {
  StoredDomain a{"team", 0, 0, 0, Doc("team", 2)};
  ASSERT_EQ(s.Create(a), StoreResult::kOk);
  EXPECT_EQ(a.version, 1);
  StoredDomain again{"team", 0, 0, 0, Doc("team", 9)};
  EXPECT_EQ(other.Create(again), StoreResult::kConflict);
  auto got = other.Get("team");
  ASSERT_TRUE(std::holds_alternative<std::optional<StoredDomain>>(got));
  auto& g = std::get<std::optional<StoredDomain>>(got);
  ASSERT_TRUE(g);
  EXPECT_EQ(g->doc, Doc("team", 2));  // as stored, templates and all
  EXPECT_EQ(g->version, 1);
  StoredDomain b{"b_team", 0, 0, 0, Doc("b_team", 1)};
  ASSERT_EQ(other.Create(b), StoreResult::kOk);
  auto list = s.List();
  ASSERT_TRUE(std::holds_alternative<std::vector<std::string>>(list));
  EXPECT_EQ(std::get<std::vector<std::string>>(list), (std::vector<std::string>{"b_team", "team"}));
  StoredDomain up{"team", 0, 0, 0, Doc("team", 8)};
  ASSERT_EQ(other.Replace(up), StoreResult::kOk);
  EXPECT_EQ(up.version, 2);
  EXPECT_EQ(std::get<std::optional<StoredDomain>>(s.Get("team"))->doc["parameters"]["N"], 8);
  StoredDomain missing{"nobody", 0, 0, 0, Doc("nobody", 1)};
  EXPECT_EQ(s.Replace(missing), StoreResult::kNotFound);
  EXPECT_EQ(s.Delete("b_team"), StoreResult::kOk);
  EXPECT_EQ(other.Delete("b_team"), StoreResult::kNotFound);
  EXPECT_FALSE(std::get<std::optional<StoredDomain>>(other.Get("b_team")));
  // The cap (3 in these tests): "team" plus two more.
  StoredDomain c{"c", 0, 0, 0, Doc("c", 1)}, d{"d", 0, 0, 0, Doc("d", 1)}, e{"e", 0, 0, 0, Doc("e", 1)};
  EXPECT_EQ(s.Create(c), StoreResult::kOk);
  EXPECT_EQ(s.Create(d), StoreResult::kOk);
  EXPECT_EQ(s.Create(e), StoreResult::kFull);
}

TEST(DomainStore, SqliteKeepsDomainsAcrossAReopen) {
  std::string dir = TempDir();
  SessionStoreConfig c;
  c.data_dir = dir;
  auto s = OpenDomainStore(c, 3);
  ASSERT_TRUE(std::holds_alternative<std::unique_ptr<DomainStore>>(s)) << std::get<Error>(s).message;
  auto t = OpenDomainStore(c, 3);
  ASSERT_TRUE(std::holds_alternative<std::unique_ptr<DomainStore>>(t));
  ExerciseStore(*std::get<std::unique_ptr<DomainStore>>(s), *std::get<std::unique_ptr<DomainStore>>(t));
  std::get<std::unique_ptr<DomainStore>>(s).reset();
  std::get<std::unique_ptr<DomainStore>>(t).reset();
  // A restart: a new handle on the same file sees what the old ones wrote.
  auto r = OpenDomainStore(c, 3);
  auto& store = *std::get<std::unique_ptr<DomainStore>>(r);
  auto got = std::get<std::optional<StoredDomain>>(store.Get("team"));
  ASSERT_TRUE(got);
  EXPECT_EQ(got->doc["parameters"]["N"], 8);
  EXPECT_EQ(got->version, 2);
  // The sessions of the same file are untouched by the domains table (and the other way round).
  auto sessions = OpenSessionStore(c);
  ASSERT_TRUE(std::holds_alternative<std::unique_ptr<SessionStore>>(sessions));
  EXPECT_EQ(std::get<std::unique_ptr<SessionStore>>(sessions)->Count(), 0);
  std::filesystem::remove_all(dir);
}

TEST(DomainStore, RedisIsSharedByReplicas) {
  ASSERT_EQ(access("/usr/bin/redis-server", X_OK), 0) << "redis-server missing: scripts/install-deps.sh --test";
  std::string dir = TempDir();
  int port = FreePort();
  pid_t redis = fork();
  if (redis == 0) {
    int fd = open((dir + "/redis.log").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    std::string p = std::to_string(port);
    execl("/usr/bin/redis-server", "/usr/bin/redis-server", "--port", p.c_str(), "--bind",
          "127.0.0.1", "--save", "", "--appendonly", "no", "--dir", dir.c_str(), nullptr);
    _exit(127);
  }
  bool up = false;
  for (int i = 0; i < 200 && !(up = Listening(port)); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  ASSERT_TRUE(up) << "redis-server did not start";
  SessionStoreConfig c;
  c.url = "redis://127.0.0.1:" + std::to_string(port) + "/2";
  auto s = OpenDomainStore(c, 3);
  auto t = OpenDomainStore(c, 3);
  ASSERT_TRUE(std::holds_alternative<std::unique_ptr<DomainStore>>(s)) << std::get<Error>(s).message;
  ASSERT_TRUE(std::holds_alternative<std::unique_ptr<DomainStore>>(t));
  ExerciseStore(*std::get<std::unique_ptr<DomainStore>>(s), *std::get<std::unique_ptr<DomainStore>>(t));
  kill(redis, SIGTERM);
  waitpid(redis, nullptr, 0);
  std::filesystem::remove_all(dir);
}

TEST(DomainStore, ABadUrlIsRefused) {
  SessionStoreConfig c;
  c.url = "postgres://x";
  auto s = OpenDomainStore(c);
  ASSERT_TRUE(std::holds_alternative<Error>(s));
  EXPECT_EQ(std::get<Error>(s).code, ErrorCode::kInvalidInput);
}

}  // namespace
}  // namespace ctb::app
