// Where domains live: `config/domains/<name>.json` under a configuration directory.
#pragma once

#include <optional>
#include <string>

#include "planner/model/domain.h"

namespace ctb {

// The default configuration directory: $CTB_CONFIG_DIR, else ./config when it has a domains/
// folder, else the source tree's config/ baked in at build time.
std::string DefaultConfigDir();

// Loads a domain given as a NAME (an identifier: config_dir/domains/NAME.json; unknown names are
// kNotFound-style errors at pointer "/domain") or as a PATH (contains '/' or ends in ".json"),
// read under `limits` (the command line passes LocalFileLimits()).
std::optional<Domain> LoadDomainByNameOrPath(const std::string& name_or_path,
                                             const std::string& config_dir, Diagnostics& diags,
                                             bool* not_found = nullptr,
                                             const ParseLimits& limits = {});

}  // namespace ctb
