// Access control shared by both front ends (contract section 10): bearer keys read from a file,
// one per line ("# ..." comments and blank lines ignored), either the key itself or its
// SHA-256 as "sha256:<64 hex digits>". Keys are kept only as SHA-256 digests; a presented token
// is hashed and compared with every digest in constant time, so neither the comparison's
// duration nor the logs reveal a key. Reload() re-reads the file (the server calls it on
// SIGHUP): a file that does not load leaves the old keys in place.
//
// Thread-safe: Check() may run on every request thread while Reload() swaps the set.
#pragma once

#include <array>
#include <variant>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace ctb::app {

class ApiKeys {
 public:
  using Digest = std::array<unsigned char, 32>;

  // Loads `path`; an error message (never quoting a key) when it cannot be read, holds a line
  // that is neither a key nor a digest, or holds no key.
  static std::variant<std::unique_ptr<ApiKeys>, std::string> Load(const std::string& path);

  // True when `authorization` is "Bearer <a key of the set>".
  bool CheckHeader(const std::string& authorization) const;
  bool CheckToken(const std::string& token) const;
  // Re-reads the file; returns an error message (the old keys stay) or nullopt.
  std::optional<std::string> Reload();
  size_t size() const;

  // "sha256:<hex>" of a key, for writing a hashed key file.
  static std::string HashLine(const std::string& key);

 private:
  explicit ApiKeys(std::string path) : path_(std::move(path)) {}
  static std::variant<std::vector<Digest>, std::string> ReadFile(const std::string& path);

  const std::string path_;
  mutable std::mutex mu_;
  std::vector<Digest> digests_;
};

}  // namespace ctb::app
