// The SQLite file's integrity at start (storage.h CheckSqliteFile): PRAGMA quick_check on a
// read-only connection (no checkpoint, nothing written); a damaged file is moved aside with its
// -wal and -shm, and what reads of each table is copied into a new file (a truncated file is read
// from a copy padded with zeros to its recorded size).
#include <sqlite3.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include "app/storage.h"
#include "app/store_common.h"

namespace ctb::app {

namespace {

namespace fs = std::filesystem;
using store::Stmt;

bool IsDamage(int rc) {
  rc &= 0xff;
  return rc == SQLITE_CORRUPT || rc == SQLITE_NOTADB;
}

// SQLite's words for the damage, "" when the file is sound or cannot be read for another
// reason (a read-only directory, a lock: not damage, and the stores will say so).
std::string Damage(const std::string& path) {
  sqlite3* db = nullptr;
  int rc = sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  std::string problem;
  if (rc != SQLITE_OK) {
    if (IsDamage(rc)) problem = db ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
    sqlite3_close(db);
    return problem;
  }
  {
    Stmt check(db, "PRAGMA quick_check");
    if (!check.ok()) {
      if (IsDamage(sqlite3_errcode(db))) problem = sqlite3_errmsg(db);
    } else {
      rc = check.Step();
      if (rc == SQLITE_ROW && check.Text(0) != "ok") problem = check.Text(0);
      else if (rc != SQLITE_ROW && IsDamage(rc)) problem = sqlite3_errmsg(db);
    }
  }
  sqlite3_close(db);
  return problem;
}

std::string UtcStamp() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y%m%dT%H%M%SZ", &tm);
  return buf;
}

// Copies the rows of `table` that read: forwards until the first damaged page, then row by row
// past it (until 1000 rowids in a row read nothing), then backwards from the end. Returns the
// rows inserted.
long CopyRows(sqlite3* from, sqlite3* to, const std::string& table, const std::string& key) {
  const std::string columns = "SELECT rowid, " + key + ", version, created_ms, updated_ms, doc FROM " + table;
  Stmt write(to, "INSERT OR IGNORE INTO " + table + "(" + key +
                     ", version, created_ms, updated_ms, doc) VALUES (?, ?, ?, ?, ?)");
  if (!write.ok()) return 0;
  long n = 0;
  long last = 0;
  // One row read (rowid, key, version, created_ms, updated_ms, doc) into the new file.
  auto copy = [&](Stmt& read) {
    sqlite3_reset(write.get());
    const std::string doc = read.Text(5);
    if (Json::parse(doc, nullptr, false).is_discarded()) return;
    write.Bind(1, read.Text(1)).Bind(2, read.Int(2)).Bind(3, read.Int(3)).Bind(4, read.Int(4)).Bind(5, doc);
    if (write.Step() == SQLITE_DONE) n += sqlite3_changes(to);
  };
  {
    Stmt forward(from, columns + " ORDER BY rowid");
    if (!forward.ok()) return 0;
    while (forward.Step() == SQLITE_ROW) {
      last = forward.Int(0);
      copy(forward);
    }
  }
  for (long rowid = last + 1, misses = 0; misses < 1000; ++rowid) {
    Stmt one(from, columns + " WHERE rowid = ?");
    if (!one.ok()) break;
    one.Bind(1, rowid);
    if (one.Step() == SQLITE_ROW) {
      copy(one);
      misses = 0;
    } else {
      ++misses;
    }
  }
  Stmt backward(from, columns + " ORDER BY rowid DESC");
  if (backward.ok())
    while (backward.Step() == SQLITE_ROW) copy(backward);
  return n;
}

// A truncated file made whole again with zeros (in a copy), so that SQLite reads the pages it
// still has instead of refusing every query. Returns the file to read from.
std::string Padded(const std::string& file, const std::string& copy) {
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  unsigned char head[100] = {};
  FILE* f = ec ? nullptr : std::fopen(file.c_str(), "rb");
  const bool read = f && std::fread(head, 1, sizeof head, f) == sizeof head;
  if (f) std::fclose(f);
  if (!read) return file;
  unsigned long page = (head[16] << 8) | head[17];
  if (page == 1) page = 65536;
  const unsigned long pages = (head[28] << 24) | (head[29] << 16) | (head[30] << 8) | head[31];
  if (page < 512 || pages * page <= size || pages * page > (1ul << 34)) return file;
  fs::copy_file(file, copy, fs::copy_options::overwrite_existing, ec);
  if (!ec) fs::resize_file(copy, pages * page, ec);
  return ec ? file : copy;
}

// What reads of the damaged file at `from`, copied into a new file at `to`.
long Salvage(const std::string& from, const std::string& to) {
  const std::string padded = Padded(from, to + ".salvage");
  sqlite3* src = nullptr;
  sqlite3* dst = nullptr;
  long n = 0;
  if (sqlite3_open_v2(padded.c_str(), &src, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK &&
      sqlite3_open_v2(to.c_str(), &dst, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) == SQLITE_OK) {
    sqlite3_exec(dst, "PRAGMA journal_mode=WAL; BEGIN", nullptr, nullptr, nullptr);
    for (const auto& k : store::kKinds)  // the tables of versioned documents (document_store.h)
      if (sqlite3_exec(dst, store::TableSql(k.table, k.key).c_str(), nullptr, nullptr, nullptr) == SQLITE_OK)
        n += CopyRows(src, dst, k.table, k.key);
    sqlite3_exec(dst, "COMMIT", nullptr, nullptr, nullptr);
  }
  sqlite3_close(src);
  sqlite3_close(dst);
  if (padded != from) {
    std::error_code ec;
    for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(padded + suffix, ec);
  }
  return n;
}

}  // namespace

std::variant<SqliteFileCheck, Error> CheckSqliteFile(const std::string& path) {
  SqliteFileCheck out;
  std::error_code ec;
  if (!fs::exists(path, ec)) return out;
  out.problem = Damage(path);
  if (out.problem.empty()) return out;
  out.damaged = true;
  out.kept_at = path + ".damaged-" + UtcStamp();
  for (const char* suffix : {"", "-wal", "-shm"}) {
    if (!fs::exists(path + suffix, ec)) continue;
    fs::rename(path + suffix, out.kept_at + suffix, ec);
    if (ec && *suffix == '\0')
      return Error{ErrorCode::kUnavailable,
                   "the database file " + path + " is damaged (" + out.problem +
                       ") and cannot be moved aside (" + ec.message() +
                       "): move it away or restore a copy, then start again",
                   {}};
  }
  out.salvaged = Salvage(out.kept_at, path);
  return out;
}

}  // namespace ctb::app
