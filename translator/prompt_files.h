// Prompt files and the text the translator's LLM loops share: reading a prompt, filling its
// {{placeholders}}, and listing a checker's problems for a repair request.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "planner/model/error.h"

namespace ctb {

// The whole file, or nullopt when it cannot be read.
std::optional<std::string> ReadPromptFile(const std::string& path);

// text with every {{name}} replaced by its value.
std::string FillPrompt(std::string text, const std::vector<std::pair<std::string, std::string>>& vars);

// One line per problem, "pointer: message" (each cut at 400 characters), at most max_listed
// lines and a count of the rest.
std::string ListProblems(const std::vector<Diagnostic>& problems, std::size_t max_listed = 40);

}  // namespace ctb
