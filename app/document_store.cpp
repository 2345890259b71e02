// Opening a document store (document_store.h): the URL read, the backend chosen.
#include "app/document_store.h"

#include <filesystem>

#include "app/store_common.h"

namespace ctb::app {

std::optional<Error> ParseRedisUrl(const std::string& url, std::string& host, int& port, int& db) {
  const std::string prefix = "redis://";
  if (url.rfind(prefix, 0) != 0)
    return Error{
        ErrorCode::kInvalidInput, "session store must be \"sqlite\" or redis://host:port/db", {}};
  std::string rest = url.substr(prefix.size());
  db = 0;
  if (auto slash = rest.find('/'); slash != std::string::npos) {
    const std::string d = rest.substr(slash + 1);
    if (!d.empty() && (d.size() > 3 || d.find_first_not_of("0123456789") != std::string::npos))
      return Error{ErrorCode::kInvalidInput, "redis database must be a small number", {}};
    if (!d.empty()) db = std::stoi(d);
    rest = rest.substr(0, slash);
  }
  port = 6379;
  if (auto colon = rest.rfind(':'); colon != std::string::npos) {
    const std::string p = rest.substr(colon + 1);
    if (p.empty() || p.size() > 5 || p.find_first_not_of("0123456789") != std::string::npos ||
        std::stoi(p) > 65535)
      return Error{ErrorCode::kInvalidInput, "redis port must be 1..65535", {}};
    port = std::stoi(p);
    rest = rest.substr(0, colon);
  }
  host = rest.empty() ? "127.0.0.1" : rest;
  return std::nullopt;
}

std::variant<std::unique_ptr<DocumentStore>, Error> OpenDocumentStore(
    const DocumentStoreConfig& c) {
  std::string error;
  std::unique_ptr<DocumentStore> s;
  if (c.url == "memory") {  // the CLI's local mode: documents die with the process
    s = store::OpenSqliteDocuments(":memory:", c, error);
  } else if (c.url.empty() || c.url == "sqlite") {
    std::error_code ec;
    std::filesystem::create_directories(c.data_dir, ec);
    s = store::OpenSqliteDocuments(c.data_dir + "/sessions.db", c, error);
  } else {
    std::string host;
    int port = 6379, db = 0;
    if (auto e = ParseRedisUrl(c.url, host, port, db)) return *e;
    s = store::OpenRedisDocuments(host, port, db, c, error);
  }
  if (!s) return Error{ErrorCode::kUnavailable, error, {}};
  return s;
}

}  // namespace ctb::app
