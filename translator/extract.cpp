#include "translator/extract.h"

#include <cctype>
#include <set>

#include "translator/text.h"

namespace ctb {

namespace {

constexpr std::string_view kLeftDouble = "\xE2\x80\x9C";   // “
constexpr std::string_view kRightDouble = "\xE2\x80\x9D";  // ”
constexpr std::string_view kLowDouble = "\xE2\x80\x9E";    // „
constexpr std::string_view kLeftSingle = "\xE2\x80\x98";   // ‘
constexpr std::string_view kRightSingle = "\xE2\x80\x99";  // ’

bool StartsAt(std::string_view t, std::size_t i, std::string_view s) {
  return t.substr(i, s.size()) == s;
}

bool IsBlank(std::string_view t) {
  for (char c : t)
    if (!std::isspace(static_cast<unsigned char>(c))) return false;
  return true;
}

std::string Trim(std::string_view t) {
  std::size_t a = 0, b = t.size();
  while (a < b && std::isspace(static_cast<unsigned char>(t[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(t[b - 1]))) --b;
  return std::string(t.substr(a, b - a));
}

bool LooksLikePlan(const std::string& block) {
  return block.find("initial_state") != std::string::npos ||
         block.find("state_plan") != std::string::npos;
}

// A parse error for people: nlohmann's "last read: '...'" (raw bytes, possibly half a
// character) is replaced by the text around the error, quoted.
std::string Humanize(const Diagnostic& e, std::string_view text) {
  std::string m = e.message;
  auto lr = m.find("; last read: '");
  if (lr != std::string::npos) {
    auto end = m.find("'; expected", lr + 14);
    m.erase(lr, end == std::string::npos ? std::string::npos : end + 1 - lr);
  }
  m = ValidUtf8(m);
  if (e.offset) m += ", near: `" + Around(text, *e.offset) + "`";
  return m;
}

}  // namespace

std::string StripThinking(std::string_view answer, bool* stripped) {
  std::string s(answer);
  bool any = false;
  for (const char* tag : {"think", "thinking"}) {
    const std::string open = std::string("<") + tag + ">", close = std::string("</") + tag + ">";
    for (;;) {
      auto o = s.find(open), c = s.find(close);
      if (c != std::string::npos && (o == std::string::npos || c < o)) {
        s.erase(0, c + close.size());  // the opening tag was left out by the server
        any = true;
        continue;
      }
      if (o == std::string::npos) break;
      c = s.find(close, o);
      any = true;
      if (c == std::string::npos) {
        s.erase(o);
        break;
      }
      s.erase(o, c + close.size() - o);
    }
  }
  if (stripped) *stripped = any;
  return s;
}

JsonBlocks FindJsonBlocks(std::string_view t) {
  JsonBlocks out;
  enum class Str { kNone, kDouble, kSingle, kSmart } str = Str::kNone;
  bool escaped = false;
  int depth = 0;
  std::size_t start = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    char c = t[i];
    if (str == Str::kDouble || str == Str::kSingle) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == (str == Str::kDouble ? '"' : '\''))
        str = Str::kNone;
      continue;
    }
    if (str == Str::kSmart) {
      if (c == '"')
        str = Str::kNone;
      else if (StartsAt(t, i, kRightDouble) || StartsAt(t, i, kLeftDouble))
        str = Str::kNone, i += 2;
      continue;
    }
    if (depth > 0) {  // strings count only inside a block: prose has stray quotes
      if (c == '"') {
        str = Str::kDouble;
        continue;
      }
      if (c == '\'') {
        str = Str::kSingle;
        continue;
      }
      if (StartsAt(t, i, kLeftDouble) || StartsAt(t, i, kRightDouble)) {
        str = Str::kSmart;
        i += 2;
        continue;
      }
    }
    if (c == '{') {
      if (depth++ == 0) start = i;
    } else if (c == '}' && depth > 0) {
      if (--depth == 0) out.complete.emplace_back(t.substr(start, i - start + 1));
    }
  }
  if (depth > 0) out.unclosed = std::string(t.substr(start));
  return out;
}

namespace {

// The chosen block, and how many complete blocks looked like a state plan.
std::optional<std::string> Choose(const JsonBlocks& b, int* plan_like, bool* unclosed) {
  *plan_like = 0;
  *unclosed = false;
  const std::string* last_plan = nullptr;
  for (const auto& block : b.complete)
    if (LooksLikePlan(block)) {
      ++*plan_like;
      last_plan = &block;
    }
  if (last_plan) return *last_plan;
  if (!b.complete.empty()) return b.complete.back();
  if (b.unclosed) {
    *unclosed = true;
    return b.unclosed;
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> FindJson(const std::string& answer) {
  bool stripped = false;
  JsonBlocks b = FindJsonBlocks(StripThinking(answer, &stripped));
  if (stripped && b.complete.empty() && !b.unclosed) b = FindJsonBlocks(answer);
  int plan_like;
  bool unclosed;
  return Choose(b, &plan_like, &unclosed);
}

std::string RelaxJson(std::string_view t, std::vector<std::string>& applied) {
  std::set<std::string> seen;
  auto note = [&](const char* s) {
    if (seen.insert(s).second) applied.emplace_back(s);
  };
  std::string out;
  out.reserve(t.size() + 16);
  std::size_t i = 0;
  const std::size_t n = t.size();
  // Copies a string body up to one of `closers`, re-quoted with '"'.
  auto copy_string = [&](std::initializer_list<std::string_view> closers, bool double_quoted) {
    out += '"';
    while (i < n) {
      char c = t[i];
      if (c == '\\' && i + 1 < n) {
        if (!double_quoted && t[i + 1] == '\'')
          out += '\'';
        else
          out += t.substr(i, 2);
        i += 2;
        continue;
      }
      for (auto cl : closers)
        if (StartsAt(t, i, cl)) {
          i += cl.size();
          out += '"';
          return;
        }
      if (c == '"')
        out += "\\\"";
      else if (c == '\n')
        out += "\\n", note("raw line breaks inside strings were escaped");
      else if (c == '\t')
        out += "\\t", note("raw line breaks inside strings were escaped");
      else if (static_cast<unsigned char>(c) < 0x20)
        note("raw line breaks inside strings were escaped");
      else
        out += c;
      ++i;
    }
  };
  // Skips blanks and comments from k; returns the next position.
  auto skip_blank = [&](std::size_t k) {
    for (;;) {
      while (k < n && std::isspace(static_cast<unsigned char>(t[k]))) ++k;
      if (StartsAt(t, k, "//") || (k < n && t[k] == '#')) {
        while (k < n && t[k] != '\n') ++k;
      } else if (StartsAt(t, k, "/*")) {
        auto e = t.find("*/", k + 2);
        k = e == std::string_view::npos ? n : e + 2;
      } else {
        return k;
      }
    }
  };
  while (i < n) {
    char c = t[i];
    if (c == '"') {
      ++i;
      copy_string({"\""}, true);
    } else if (c == '\'') {
      ++i;
      note("single-quoted strings were read as double-quoted");
      copy_string({"'"}, false);
    } else if (StartsAt(t, i, kLeftDouble) || StartsAt(t, i, kRightDouble) ||
               StartsAt(t, i, kLowDouble)) {
      i += 3;
      note("typographic quotes (\xE2\x80\x9C\xE2\x80\x9D) were read as '\"'");
      copy_string({kRightDouble, kLeftDouble, "\""}, false);
    } else if (StartsAt(t, i, kLeftSingle) || StartsAt(t, i, kRightSingle)) {
      i += 3;
      note("typographic quotes (\xE2\x80\x98\xE2\x80\x99) were read as '\"'");
      copy_string({kRightSingle, kLeftSingle}, false);
    } else if (StartsAt(t, i, "//") || StartsAt(t, i, "/*") || c == '#') {
      note("comments were removed");
      i = skip_blank(i);
      out += ' ';
    } else if (c == ',') {
      std::size_t k = skip_blank(i + 1);
      if (k < n && (t[k] == '}' || t[k] == ']'))
        note("trailing commas were removed");
      else
        out += c;
      ++i;
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      std::size_t k = i;
      while (k < n && (std::isalnum(static_cast<unsigned char>(t[k])) || t[k] == '_')) ++k;
      std::string_view word = t.substr(i, k - i);
      if (word == "True" || word == "False" || word == "None") {
        note("Python literals True/False/None were read as true/false/null");
        out += word == "True" ? "true" : word == "False" ? "false" : "null";
      } else {
        out += word;
      }
      i = k;
    } else {
      out += c;
      ++i;
    }
  }
  return out;
}

Extraction ExtractJson(const std::string& answer) {
  Extraction x;
  // A whole answer that is one JSON string holding the object: double-encoded.
  std::string trimmed = Trim(answer);
  if (trimmed.size() >= 2 && trimmed.front() == '"' && trimmed.back() == '"') {
    Diagnostics d;
    auto s = ParseJsonStrict(trimmed, d);
    if (s && s->is_string()) {
      Extraction inner = ExtractJson(s->get<std::string>());
      if (inner.json) {
        inner.notes.insert(inner.notes.begin(),
                           {"", std::nullopt,
                            "the answer was a JSON string holding the state plan "
                            "(double-encoded); it was decoded"});
        return inner;
      }
    }
  }
  bool stripped = false;
  std::string text = StripThinking(answer, &stripped);
  JsonBlocks blocks = FindJsonBlocks(text);
  if (stripped && blocks.complete.empty() && !blocks.unclosed) {
    blocks = FindJsonBlocks(answer);  // the JSON was inside the reasoning
    text = answer;
  } else if (stripped) {
    x.notes.push_back({"", std::nullopt, "reasoning between <think> tags was left out"});
  }
  int plan_like = 0;
  bool unclosed = false;
  auto chosen = Choose(blocks, &plan_like, &unclosed);
  if (!chosen) {
    if (IsBlank(answer))
      x.errors.push_back({"", std::nullopt, "the answer was empty"});
    else
      x.errors.push_back({"", std::nullopt,
                          "the answer holds no JSON object; it reads: \"" +
                              Cut(Trim(IsBlank(text) ? answer : text)) + "\""});
    return x;
  }
  if (plan_like > 1)
    x.notes.push_back({"", std::nullopt,
                       "the answer holds " + std::to_string(plan_like) +
                           " state plans (a draft and a final one?); the last "
                           "one was read"});
  Diagnostics strict;
  if (auto j = ParseJsonStrict(*chosen, strict)) {
    x.json = std::move(j);
    return x;
  }
  std::vector<std::string> applied;
  std::string relaxed = RelaxJson(*chosen, applied);
  if (!applied.empty()) {
    Diagnostics d;
    if (auto j = ParseJsonStrict(relaxed, d)) {
      x.json = std::move(j);
      for (const auto& a : applied) x.notes.push_back({"", std::nullopt, a});
      return x;
    }
  }
  for (const auto& e : strict.errors())
    x.errors.push_back({"", std::nullopt, Humanize(e, *chosen)});
  if (unclosed)
    x.errors.push_back({"", std::nullopt,
                        "the JSON object is never closed: the answer looks cut "
                        "off; answer with the complete, shorter object"});
  return x;
}

}  // namespace ctb
