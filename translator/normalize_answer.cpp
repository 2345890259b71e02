#include "translator/normalize_answer.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <set>

#include "translator/extract.h"
#include "translator/text.h"

namespace ctb {

namespace {

bool IsWordChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

std::set<std::string> DomainNames(const Domain& d) {
  std::set<std::string> names;
  for (const auto& a : d.automata) {
    names.insert(a.name);
    names.insert(a.locations.begin(), a.locations.end());
    names.insert(a.commands.begin(), a.commands.end());
  }
  return names;
}

std::string Lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string Join(const std::vector<std::string>& parts) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? ", " : "") + parts[i];
  return out;
}

// A JSON value that is a string holding JSON: decoded (tolerantly), else nullopt.
std::optional<Json> Decoded(const Json& v) {
  if (!v.is_string()) return std::nullopt;
  Extraction x = ExtractJson(v.get<std::string>());
  if (x.json && x.json->is_object()) return x.json;
  return std::nullopt;
}

void NormalizeCondition(Json& obj, const std::string& key, const std::string& pointer,
                        const Domain& d, std::vector<Diagnostic>& notes) {
  if (!obj.is_object() || !obj.contains(key) || !obj[key].is_string()) return;
  std::vector<std::string> changes;
  std::string text = NormalizeOperators(obj[key].get<std::string>(), d, changes);
  if (changes.empty()) return;
  obj[key] = text;
  notes.push_back({pointer + "/" + PointerToken(key), std::nullopt, "read " + Join(changes)});
}

void NormalizeBound(Json& obj, const std::string& key, const std::string& pointer,
                    std::vector<Diagnostic>& notes) {
  if (!obj.is_object() || !obj.contains(key) || !obj[key].is_string()) return;
  std::string text = obj[key].get<std::string>();
  auto secs = ParseDuration(text);
  if (!secs) return;  // the checker reports the wrong type; the repair loop asks again
  obj[key] = *secs == std::floor(*secs) ? Json(static_cast<long long>(*secs)) : Json(*secs);
  notes.push_back({pointer + "/" + PointerToken(key), std::nullopt,
                   "read the string \"" + Cut(text, 40) + "\" as " + obj[key].dump() + " seconds"});
}

}  // namespace

std::optional<double> ParseDuration(const std::string& raw) {
  std::string t = raw;
  while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back()))) t.pop_back();
  std::size_t a = 0;
  while (a < t.size() && std::isspace(static_cast<unsigned char>(t[a]))) ++a;
  t = t.substr(a);
  if (t.empty() || !(std::isdigit(static_cast<unsigned char>(t[0])) || t[0] == '.'))
    return std::nullopt;
  char* end = nullptr;
  double v = std::strtod(t.c_str(), &end);
  if (!end || !std::isfinite(v) || v < 0) return std::nullopt;
  std::string unit = Lower(std::string(end));
  while (!unit.empty() && std::isspace(static_cast<unsigned char>(unit[0]))) unit.erase(0, 1);
  if (!unit.empty() && unit.back() == '.') unit.pop_back();
  double scale;
  if (unit.empty() || unit == "s" || unit == "sec" || unit == "secs" || unit == "second" ||
      unit == "seconds")
    scale = 1;
  else if (unit == "ms" || unit == "millisecond" || unit == "milliseconds")
    scale = 0.001;
  else if (unit == "min" || unit == "mins" || unit == "minute" || unit == "minutes")
    scale = 60;
  else if (unit == "h" || unit == "hr" || unit == "hrs" || unit == "hour" || unit == "hours")
    scale = 3600;
  else
    return std::nullopt;
  return v * scale;
}

std::string NormalizeOperators(const std::string& text, const Domain& d,
                               std::vector<std::string>& changes) {
  static const std::set<std::string> kAnd = {"and", "AND", "And"}, kOr = {"or", "OR", "Or"},
                                     kNot = {"NOT", "Not"};
  std::set<std::string> seen;
  auto note = [&](const std::string& what) {
    if (seen.insert(what).second) changes.push_back(what);
  };
  std::set<std::string> names;  // filled on first need
  auto is_name = [&](const std::string& w) {
    if (names.empty()) names = DomainNames(d);
    return names.count(w) > 0;
  };
  std::string out;
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n;) {
    auto at = [&](std::string_view s) { return std::string_view(text).substr(i, s.size()) == s; };
    if (at("&&"))
      out += "/\\", i += 2, note("'&&' as '/\\'");
    else if (at("||"))
      out += "\\/", i += 2, note("'||' as '\\/'");
    else if (at("\xE2\x88\xA7"))
      out += "/\\", i += 3, note("'\xE2\x88\xA7' as '/\\'");
    else if (at("\xE2\x88\xA8"))
      out += "\\/", i += 3, note("'\xE2\x88\xA8' as '\\/'");
    else if (at("\xC2\xAC"))
      out += "not ", i += 2, note("'\xC2\xAC' as 'not'");
    else if (at("\xE2\x89\xA0"))
      out += "!=", i += 3, note("'\xE2\x89\xA0' as '!='");
    else if (at("!") && !at("!="))
      out += "not ", i += 1, note("'!' as 'not'");
    else if (std::isalpha(static_cast<unsigned char>(text[i])) || text[i] == '_') {
      std::size_t k = i;
      while (k < n && IsWordChar(text[k])) ++k;
      std::string w = text.substr(i, k - i);
      if (kAnd.count(w) && !is_name(w))
        out += "/\\", note("'" + w + "' as '/\\'");
      else if (kOr.count(w) && !is_name(w))
        out += "\\/", note("'" + w + "' as '\\/'");
      else if (kNot.count(w) && !is_name(w))
        out += "not", note("'" + w + "' as 'not'");
      else
        out += w;
      i = k;
    } else {
      out += text[i++];
    }
  }
  return out;
}

Json NormalizeAnswer(Json j, const Domain& d, std::vector<Diagnostic>& notes) {
  for (int round = 0; round < 3; ++round) {
    if (auto inner = Decoded(j)) {
      notes.push_back(
          {"", std::nullopt, "the state plan was a JSON string (double-encoded); it was decoded"});
      j = std::move(*inner);
      continue;
    }
    if (j.is_object() && !j.contains("initial_state")) {
      bool unwrapped = false;
      for (const char* key : {"state_plan", "statePlan", "state_plan.json", "plan"}) {
        if (!j.contains(key)) continue;
        Json inner = j[key];
        if (auto decoded = Decoded(inner)) inner = std::move(*decoded);
        if (!inner.is_object()) continue;
        notes.push_back({"", std::nullopt,
                         std::string("the state plan was wrapped in {\"") + key +
                             "\": ...}; the inner object was read"});
        j = std::move(inner);
        unwrapped = true;
        break;
      }
      if (unwrapped) continue;
    }
    break;
  }
  if (!j.is_object()) return j;
  if (j.contains("end_state") && j["end_state"].is_object()) {
    NormalizeCondition(j["end_state"], "maintenance_constraint", "/end_state", d, notes);
    NormalizeCondition(j["end_state"], "goal_constraint", "/end_state", d, notes);
  }
  if (!j.contains("constraints") || !j["constraints"].is_object()) return j;
  Json& c = j["constraints"];
  struct Group {
    const char* name;
    std::vector<const char*> conditions;
  };
  for (const Group& g :
       {Group{"episodes", {"accepting_constraint", "state_constraint"}},
        Group{"temporal", {"accepting_event1_constraint", "accepting_event2_constraint"}}}) {
    if (!c.contains(g.name) || !c[g.name].is_object()) continue;
    Json& group = c[g.name];
    for (auto it = group.begin(); it != group.end(); ++it) {
      Json& item = it.value();
      const std::string p = std::string("/constraints/") + g.name + "/" + PointerToken(it.key());
      for (const char* key : g.conditions) NormalizeCondition(item, key, p, d, notes);
      NormalizeBound(item, "lower_bound", p, notes);
      NormalizeBound(item, "upper_bound", p, notes);
    }
  }
  return j;
}

}  // namespace ctb
