#include "app/api_keys.h"

#include <openssl/crypto.h>
#include <openssl/sha.h>

#include <fstream>
#include <variant>

namespace ctb::app {

namespace {

ApiKeys::Digest Sha256(const std::string& s) {
  ApiKeys::Digest d{};
  SHA256(reinterpret_cast<const unsigned char*>(s.data()), s.size(), d.data());
  return d;
}

std::string Trim(const std::string& s) {
  size_t a = s.find_first_not_of(" \t\r\n"), b = s.find_last_not_of(" \t\r\n");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

std::optional<ApiKeys::Digest> FromHex(const std::string& hex) {
  if (hex.size() != 64) return std::nullopt;
  ApiKeys::Digest d{};
  for (size_t i = 0; i < 32; ++i) {
    unsigned v = 0;
    for (size_t k = 0; k < 2; ++k) {
      char c = hex[2 * i + k];
      int x = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10
              : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
      if (x < 0) return std::nullopt;
      v = v * 16 + static_cast<unsigned>(x);
    }
    d[i] = static_cast<unsigned char>(v);
  }
  return d;
}

}  // namespace

std::variant<std::vector<ApiKeys::Digest>, std::string> ApiKeys::ReadFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) return "cannot read the API key file " + path;
  std::vector<Digest> out;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    line = Trim(line);
    if (line.empty() || line[0] == '#') continue;
    if (line.rfind("sha256:", 0) == 0) {
      auto d = FromHex(line.substr(7));
      if (!d) return path + ":" + std::to_string(n) + ": a sha256: line needs 64 hex digits";
      out.push_back(*d);
      continue;
    }
    if (line.size() < 16)
      return path + ":" + std::to_string(n) + ": a key must have at least 16 characters";
    for (char c : line)
      if (c <= ' ' || c > '~')
        return path + ":" + std::to_string(n) + ": a key may hold printable ASCII only";
    out.push_back(Sha256(line));
  }
  if (out.empty()) return "the API key file " + path + " holds no key";
  return out;
}

std::variant<std::unique_ptr<ApiKeys>, std::string> ApiKeys::Load(const std::string& path) {
  auto read = ReadFile(path);
  if (auto* e = std::get_if<std::string>(&read)) return *e;
  std::unique_ptr<ApiKeys> keys(new ApiKeys(path));
  keys->digests_ = std::move(std::get<std::vector<Digest>>(read));
  return keys;
}

std::optional<std::string> ApiKeys::Reload() {
  auto read = ReadFile(path_);
  if (auto* e = std::get_if<std::string>(&read)) return *e;
  std::lock_guard<std::mutex> lock(mu_);
  digests_ = std::move(std::get<std::vector<Digest>>(read));
  return std::nullopt;
}

bool ApiKeys::CheckToken(const std::string& token) const {
  const Digest d = Sha256(token);
  std::lock_guard<std::mutex> lock(mu_);
  bool ok = false;
  // Every digest is compared, each in constant time: the time does not depend on which matched.
  for (const auto& k : digests_) ok |= CRYPTO_memcmp(k.data(), d.data(), d.size()) == 0;
  return ok && !token.empty();
}

bool ApiKeys::CheckHeader(const std::string& authorization) const {
  static const std::string kBearer = "Bearer ";
  if (authorization.size() <= kBearer.size()) return false;
  bool scheme = true;
  for (size_t i = 0; i < kBearer.size(); ++i)
    scheme &= std::tolower(static_cast<unsigned char>(authorization[i])) ==
              std::tolower(static_cast<unsigned char>(kBearer[i]));
  return scheme && CheckToken(Trim(authorization.substr(kBearer.size())));
}

size_t ApiKeys::size() const {
  std::lock_guard<std::mutex> lock(mu_);
  return digests_.size();
}

std::string ApiKeys::HashLine(const std::string& key) {
  static const char* kHex = "0123456789abcdef";
  std::string out = "sha256:";
  for (unsigned char c : Sha256(key)) {
    out += kHex[c >> 4];
    out += kHex[c & 15];
  }
  return out;
}

}  // namespace ctb::app
