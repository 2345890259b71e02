#include "translator/prompt_files.h"

#include <fstream>
#include <sstream>

#include "translator/text.h"

namespace ctb {

std::optional<std::string> ReadPromptFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string FillPrompt(std::string text, const std::vector<std::pair<std::string, std::string>>& vars) {
  for (const auto& [name, value] : vars) {
    const std::string key = "{{" + name + "}}";
    std::string out;
    std::size_t pos = 0, at;
    while ((at = text.find(key, pos)) != std::string::npos) {
      out += text.substr(pos, at - pos) + value;
      pos = at + key.size();
    }
    text = out + text.substr(pos);
  }
  return text;
}

std::string ListProblems(const std::vector<Diagnostic>& problems, std::size_t max_listed) {
  std::string out;
  for (std::size_t i = 0; i < problems.size() && i < max_listed; ++i)
    out += Cut(problems[i].ToString(), 400) + "\n";
  if (problems.size() > max_listed)
    out += "(and " + std::to_string(problems.size() - max_listed) + " more)\n";
  return out;
}

}  // namespace ctb
