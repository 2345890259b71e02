#include "planner/model/catalog.h"

#include <cstdlib>
#include <filesystem>

#ifndef CTB_BUILTIN_CONFIG_DIR
#define CTB_BUILTIN_CONFIG_DIR "config"
#endif

namespace ctb {

std::string DefaultConfigDir() {
  if (const char* env = std::getenv("CTB_CONFIG_DIR"); env && *env) return env;
  std::error_code ec;
  if (std::filesystem::is_directory("config/domains", ec)) return "config";
  return CTB_BUILTIN_CONFIG_DIR;
}

std::optional<Domain> LoadDomainByNameOrPath(const std::string& name_or_path,
                                             const std::string& config_dir, Diagnostics& diags,
                                             bool* not_found, const ParseLimits& limits) {
  bool is_path = name_or_path.find('/') != std::string::npos ||
                 (name_or_path.size() > 5 &&
                  name_or_path.compare(name_or_path.size() - 5, 5, ".json") == 0);
  std::string path;
  if (is_path) {
    path = name_or_path;
  } else {
    if (!IsIdentifier(name_or_path)) {
      diags.Error("/domain", "'" + name_or_path + "' is not a domain name");
      if (not_found) *not_found = true;
      return std::nullopt;
    }
    path = config_dir + "/domains/" + name_or_path + ".json";
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    diags.Error("/domain", is_path ? "no domain file '" + path + "'"
                                   : "unknown domain '" + name_or_path + "' (no " + path + ")");
    if (not_found) *not_found = true;
    return std::nullopt;
  }
  return LoadDomainFile(path, diags, limits);
}

}  // namespace ctb
