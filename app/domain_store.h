// Where domains created through the API live (contract section 12): the same SQLite file or
// Redis server as the sessions (session_store.h), so that they survive restarts and every
// replica sees the same ones. SQLite: table domains(name, version, created_ms, updated_ms, doc)
// in <data_dir>/sessions.db. Redis: one hash per domain, ctb:domain:<name> -> version,
// created_ms, updated_ms, doc, and the set ctb:domains of names; create and replace are Lua
// scripts (atomic across replicas).
//
// The document is stored as the client sent it (templates and guards as written); checking it
// is the caller's job. Domains never expire. Thread-safe; never throws; a store that cannot be
// reached gives kUnavailable.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "app/session_store.h"

namespace ctb::app {

struct StoredDomain {
  std::string name;
  long version = 0;  // 1 on creation, +1 per replacement
  long created_ms = 0;
  long updated_ms = 0;
  Json doc = Json::object();
};

class DomainStore {
 public:
  virtual ~DomainStore() = default;
  // The domain, nullopt when unknown, or kUnavailable.
  virtual std::variant<std::optional<StoredDomain>, Error> Get(const std::string& name) = 0;
  // Every stored name, sorted, or kUnavailable.
  virtual std::variant<std::vector<std::string>, Error> List() = 0;
  // kConflict when the name exists, kFull at max_domains.
  virtual StoreResult Create(StoredDomain& d) = 0;
  // kNotFound when the name does not exist; d.version is set to the new version on kOk.
  virtual StoreResult Replace(StoredDomain& d) = 0;
  virtual StoreResult Delete(const std::string& name) = 0;
  virtual std::string Describe() const = 0;
  // The backend's words for the last failure; "" when unknown.
  virtual std::string LastError() const { return {}; }
  // A small write that changes no document (a heartbeat row or key): false when it fails. Tells
  // /healthz whether a store that failed to write writes again.
  virtual bool Probe() = 0;
};

// Opens the domain store beside the session store of this configuration.
std::variant<std::unique_ptr<DomainStore>, Error> OpenDomainStore(const SessionStoreConfig& c,
                                                                 long max_domains = 1000);

std::unique_ptr<DomainStore> OpenSqliteDomainStore(const std::string& path, long max_domains,
                                                   std::string& error);
std::unique_ptr<DomainStore> OpenRedisDomainStore(const std::string& host, int port, int db,
                                                  long max_domains, std::string& error);

}  // namespace ctb::app
