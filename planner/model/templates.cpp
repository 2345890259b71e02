#include "planner/model/templates.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <set>
#include <string_view>

namespace ctb {

namespace {

constexpr long kMaxRange = 1000;         // values of one range
constexpr long kMaxAutomata = 2000;      // automata after expansion
constexpr long kMaxItems = 200000;       // locations, commands and transitions after expansion
constexpr long kMaxAbsValue = 1000000;   // parameters and arithmetic results

struct Value {
  bool is_int = true;
  long i = 0;
  std::string s;
  std::string Text() const { return is_int ? std::to_string(i) : s; }
};
using Env = std::map<std::string, Value>;

bool IsNameChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

bool IsFragment(const std::string& s) {
  return !s.empty() && s.size() <= 64 && std::all_of(s.begin(), s.end(), IsNameChar);
}

bool IsPlainIdentifier(const std::string& s) {
  if (s.empty() || s.size() > 64 || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  for (char c : s)
    if (!IsNameChar(c)) return false;
  return true;
}

// Integer arithmetic over the environment: + - * unary minus, parentheses; a lone variable may
// hold a name fragment.
class Arith {
 public:
  Arith(std::string_view text, const Env& env) : t_(text), env_(env) {}
  std::optional<Value> Run(std::string& err) {
    auto v = Sum(err);
    Skip();
    if (v && pos_ != t_.size()) {
      err = "unexpected '" + std::string(1, t_[pos_]) + "' in \"" + std::string(t_) + "\"";
      return std::nullopt;
    }
    return v;
  }

 private:
  void Skip() {
    while (pos_ < t_.size() && t_[pos_] == ' ') ++pos_;
  }
  bool Int(const std::optional<Value>& v, std::string& err) {
    if (!v) return false;
    if (!v->is_int) {
      err = "'" + v->s + "' is a name, not a number, in \"" + std::string(t_) + "\"";
      return false;
    }
    return true;
  }
  bool Bounded(long v, std::string& err) {
    if (v > kMaxAbsValue || v < -kMaxAbsValue) {
      err = "value out of range in \"" + std::string(t_) + "\"";
      return false;
    }
    return true;
  }
  std::optional<Value> Sum(std::string& err) {
    auto l = Product(err);
    for (;;) {
      Skip();
      if (!l || pos_ >= t_.size() || (t_[pos_] != '+' && t_[pos_] != '-')) return l;
      char op = t_[pos_++];
      auto r = Product(err);
      if (!Int(l, err) || !Int(r, err)) return std::nullopt;
      long v = op == '+' ? l->i + r->i : l->i - r->i;
      if (!Bounded(v, err)) return std::nullopt;
      l = Value{true, v, ""};
    }
  }
  std::optional<Value> Product(std::string& err) {
    auto l = Unary(err);
    for (;;) {
      Skip();
      if (!l || pos_ >= t_.size() || t_[pos_] != '*') return l;
      ++pos_;
      auto r = Unary(err);
      if (!Int(l, err) || !Int(r, err)) return std::nullopt;
      long v = l->i * r->i;  // both bounded by kMaxAbsValue: no overflow in 64 bits
      if (!Bounded(v, err)) return std::nullopt;
      l = Value{true, v, ""};
    }
  }
  std::optional<Value> Unary(std::string& err) {
    Skip();
    if (pos_ < t_.size() && t_[pos_] == '-') {
      ++pos_;
      auto v = Unary(err);
      if (!Int(v, err)) return std::nullopt;
      return Value{true, -v->i, ""};
    }
    return Atom(err);
  }
  std::optional<Value> Atom(std::string& err) {
    Skip();
    if (pos_ >= t_.size()) {
      err = "expected a number or a name in \"" + std::string(t_) + "\"";
      return std::nullopt;
    }
    if (t_[pos_] == '(') {
      ++pos_;
      auto v = Sum(err);
      Skip();
      if (!v) return std::nullopt;
      if (pos_ >= t_.size() || t_[pos_] != ')') {
        err = "missing ')' in \"" + std::string(t_) + "\"";
        return std::nullopt;
      }
      ++pos_;
      return v;
    }
    std::size_t start = pos_;
    while (pos_ < t_.size() && IsNameChar(t_[pos_])) ++pos_;
    std::string word(t_.substr(start, pos_ - start));
    if (word.empty()) {
      err = "unexpected '" + std::string(1, t_[pos_]) + "' in \"" + std::string(t_) + "\"";
      return std::nullopt;
    }
    if (std::isdigit(static_cast<unsigned char>(word[0]))) {
      if (word.size() > 7 || word.find_first_not_of("0123456789") != std::string::npos) {
        err = "bad number '" + word + "'";
        return std::nullopt;
      }
      return Value{true, std::stol(word), ""};
    }
    auto it = env_.find(word);
    if (it == env_.end()) {
      std::string known;
      for (const auto& [k, v] : env_) known += (known.empty() ? "" : ", ") + k;
      err = "unknown name '" + word + "' (known here: " + (known.empty() ? "none" : known) + ")";
      return std::nullopt;
    }
    return it->second;
  }

  std::string_view t_;
  const Env& env_;
  std::size_t pos_ = 0;
};

// Replaces every "{expr}" of s.
std::optional<std::string> Substitute(const std::string& s, const Env& env, std::string& err) {
  std::string out;
  std::size_t pos = 0;
  while (pos < s.size()) {
    std::size_t open = s.find('{', pos);
    if (open == std::string::npos) break;
    std::size_t close = s.find('}', open);
    if (close == std::string::npos) {
      err = "'{' without '}'";
      return std::nullopt;
    }
    auto v = Arith(std::string_view(s).substr(open + 1, close - open - 1), env).Run(err);
    if (!v) return std::nullopt;
    out += s.substr(pos, open - pos) + v->Text();
    pos = close + 1;
  }
  return out + s.substr(pos);
}

class Expander {
 public:
  Expander(Diagnostics& diags, Expansion& x) : diags_(diags), x_(x) {}

  // Top-level parameters with overrides.
  bool ReadParameters(const Json& doc, const ExpandOptions& o) {
    bool ok = true;
    if (doc.contains("parameters")) {
      const Json& p = doc["parameters"];
      if (!p.is_object()) {
        diags_.Error("/parameters", "expected an object of integer parameters, got " +
                                        std::string(JsonTypeName(p)));
        return false;
      }
      for (const auto& [k, v] : p.items()) {
        std::string ptr = "/parameters/" + PointerToken(k);
        if (!IsPlainIdentifier(k) || k == "self") {
          diags_.Error(ptr, "'" + k + "' is not a usable parameter name");
          ok = false;
        } else if (!v.is_number_integer() || std::labs(v.get<long>()) > kMaxAbsValue) {
          diags_.Error(ptr, "a parameter must be an integer between -1000000 and 1000000");
          ok = false;
        } else {
          params_[k] = Value{true, v.get<long>(), ""};
        }
      }
    }
    for (const auto& [k, v] : o.parameters) {
      if (!params_.count(k)) {
        diags_.Error("/parameters", "no parameter '" + k + "' to set");
        ok = false;
      } else if (std::labs(v) > kMaxAbsValue) {
        diags_.Error("/parameters/" + PointerToken(k), "value out of range");
        ok = false;
      } else {
        params_[k].i = v;
      }
    }
    return ok;
  }

  // The values of a range: "A..B", a template's name, or an array.
  std::optional<std::vector<Value>> Range(const Json& spec, const Env& env, std::string& err) {
    std::vector<Value> out;
    if (spec.is_array()) {
      for (const auto& v : spec) {
        if (v.is_number_integer() && std::labs(v.get<long>()) <= kMaxAbsValue) {
          out.push_back({true, v.get<long>(), ""});
        } else if (v.is_string() && IsFragment(v.get<std::string>())) {
          out.push_back({false, 0, v.get<std::string>()});
        } else {
          err = "a range's values are integers or name fragments (letters, digits, '_')";
          return std::nullopt;
        }
      }
      if (static_cast<long>(out.size()) > kMaxRange) {
        err = "a range has at most 1000 values";
        return std::nullopt;
      }
      return out;
    }
    if (!spec.is_string()) {
      err = "expected a range: \"A..B\", a template's name, or an array of values";
      return std::nullopt;
    }
    // Placeholders first: "1..{b}" in a guard reads like "1..b".
    auto substituted = Substitute(spec.get<std::string>(), env, err);
    if (!substituted) return std::nullopt;
    const std::string s = *substituted;
    std::size_t dots = s.find("..");
    if (dots == std::string::npos) {
      auto it = instances_.find(s);
      if (it == instances_.end()) {
        err = "'" + s + "' is neither a range \"A..B\" nor a template declared before this point";
        return std::nullopt;
      }
      return it->second;
    }
    auto lo = Arith(std::string_view(s).substr(0, dots), env).Run(err);
    if (!lo || !lo->is_int) {
      if (lo) err = "a range's bounds must be integers";
      return std::nullopt;
    }
    auto hi = Arith(std::string_view(s).substr(dots + 2), env).Run(err);
    if (!hi || !hi->is_int) {
      if (hi) err = "a range's bounds must be integers";
      return std::nullopt;
    }
    if (hi->i - lo->i + 1 > kMaxRange) {
      err = "a range has at most 1000 values";
      return std::nullopt;
    }
    for (long v = lo->i; v <= hi->i; ++v) out.push_back({true, v, ""});
    return out;
  }

  // A guard: any(...)/every(...) expanded, then placeholders.
  std::optional<std::string> Guard(const std::string& s, const Env& env, std::string& err,
                                   int depth = 0) {
    if (depth > 8) {
      err = "any/every nested more than 8 deep";
      return std::nullopt;
    }
    std::string out;
    std::size_t pos = 0;
    while (pos < s.size()) {
      std::size_t at = std::string::npos, open = 0;
      bool every = false;
      for (std::size_t k = pos; k < s.size(); ++k) {
        if (k > 0 && IsNameChar(s[k - 1])) continue;
        for (std::string_view w : {std::string_view("any"), std::string_view("every")}) {
          if (s.compare(k, w.size(), w) != 0) continue;
          std::size_t p = k + w.size();
          while (p < s.size() && s[p] == ' ') ++p;
          if (p < s.size() && s[p] == '(') {
            at = k;
            open = p;
            every = w == "every";
          }
        }
        if (at != std::string::npos) break;
      }
      if (at == std::string::npos) break;
      auto head = Substitute(s.substr(pos, at - pos), env, err);
      if (!head) return std::nullopt;
      out += *head;
      std::size_t colon = s.find(':', open);
      int level = 0;
      std::size_t close = std::string::npos;
      for (std::size_t k = open; k < s.size(); ++k) {
        if (s[k] == '(') ++level;
        if (s[k] == ')' && --level == 0) {
          close = k;
          break;
        }
      }
      const char* what = every ? "every" : "any";
      if (close == std::string::npos || colon == std::string::npos || colon > close) {
        err = std::string(what) + "(VAR in RANGE: CONDITION) expected, with its closing ')'";
        return std::nullopt;
      }
      std::string header = s.substr(open + 1, colon - open - 1);
      std::size_t b = header.find_first_not_of(' ');
      std::size_t e = header.find(" in ");
      if (b == std::string::npos || e == std::string::npos || e < b) {
        err = std::string(what) + "(VAR in RANGE: CONDITION) expected, got \"" + header + "\"";
        return std::nullopt;
      }
      std::string var = header.substr(b, e - b);
      while (!var.empty() && var.back() == ' ') var.pop_back();
      std::string range = header.substr(e + 4);
      range.erase(0, range.find_first_not_of(' '));
      while (!range.empty() && range.back() == ' ') range.pop_back();
      if (!IsPlainIdentifier(var) || env.count(var)) {
        err = "'" + var + "' cannot be the variable of " + what + "(...)" +
              (env.count(var) ? ": the name is taken here" : "");
        return std::nullopt;
      }
      auto values = Range(Json(range), env, err);
      if (!values) return std::nullopt;
      std::string body = s.substr(colon + 1, close - colon - 1);
      std::string joined;
      for (const Value& v : *values) {
        Env inner = env;
        inner[var] = v;
        auto part = Guard(body, inner, err, depth + 1);
        if (!part) return std::nullopt;
        std::size_t f = part->find_first_not_of(' ');
        joined += (joined.empty() ? "" : every ? " /\\ " : " \\/ ") + std::string("(") +
                  (f == std::string::npos ? "" : part->substr(f)) + ")";
        if (!Spend(part->size(), joined.size(), err))
          return std::nullopt;
      }
      if (values->empty()) joined = every ? "true" : "false";
      out += values->size() > 1 ? "(" + joined + ")" : joined;
      pos = close + 1;
    }
    auto tail = Substitute(s.substr(pos), env, err);
    if (!tail) return std::nullopt;
    return out + *tail;
  }

  // Counts `chars` more of expanded guards; false with err when this guard (`length` so far) or
  // all of them together grew beyond their bounds.
  bool Spend(std::size_t chars, std::size_t length, std::string& err) {
    guard_chars_ += chars;
    if (length > kMaxExpandedGuard) {
      err = "any/every expands this guard to more than " + std::to_string(kMaxExpandedGuard) +
            " characters";
      return false;
    }
    if (guard_chars_ > kMaxExpandedGuards) {
      err = "any/every expand the guards to more than " + std::to_string(kMaxExpandedGuards) +
            " characters in all";
      return false;
    }
    return true;
  }

  // Expands one list ("locations", "commands" or "transitions") into out.
  void List(const Json& list, const std::string& src, const Env& env, const std::string& label,
            bool transitions, Json& out, const std::string& dst_base) {
    for (std::size_t i = 0; i < list.size(); ++i)
      Item(list[i], src + "/" + std::to_string(i), env, label, transitions, out, dst_base);
  }

  void Item(const Json& item, const std::string& src, const Env& env, const std::string& label,
            bool transitions, Json& out, const std::string& dst_base) {
    if (++items_ > kMaxItems) {
      if (items_ == kMaxItems + 1) diags_.Error(src, "the expansion has more than 200000 items");
      return;
    }
    if (item.is_object() && item.contains("for")) {
      ObjectReader r(item, src, diags_);
      r.CheckKeys({"for", "in", "each"});
      auto var = r.String("for", true);
      const Json* in = r.Get("in");
      const Json* each = r.Get("each");
      if (!in) diags_.Error(r.Child("in"), "missing required field \"in\"");
      if (!each) diags_.Error(r.Child("each"), "missing required field \"each\"");
      if (!var || !in || !each) return;
      if (!IsPlainIdentifier(*var) || env.count(*var)) {
        diags_.Error(r.Child("for"), Label(label) + "'" + *var + "' cannot be a loop variable" +
                                         (env.count(*var) ? ": the name is taken here" : ""));
        return;
      }
      std::string err;
      auto values = Range(*in, env, err);
      if (!values) {
        diags_.Error(r.Child("in"), Label(label) + err);
        return;
      }
      for (const Value& v : *values) {
        Env inner = env;
        inner[*var] = v;
        std::string l = label + (label.empty() ? "" : ", ") + *var + "=" + v.Text();
        if (each->is_array())
          List(*each, r.Child("each"), inner, l, transitions, out, dst_base);
        else
          Item(*each, r.Child("each"), inner, l, transitions, out, dst_base);
      }
      return;
    }
    std::string dst = dst_base + "/" + std::to_string(out.size());
    Json copy = item;
    std::string err;
    if (item.is_string()) {
      auto s = Substitute(item.get<std::string>(), env, err);
      if (!s) diags_.Error(src, Label(label) + err);
      else copy = *s;
    } else if (transitions && item.is_object()) {
      for (const char* key : {"from", "to", "guard"}) {
        if (!item.contains(key) || !item[key].is_string()) continue;
        auto s = std::string(key) == "guard" ? Guard(item[key].get<std::string>(), env, err)
                                             : Substitute(item[key].get<std::string>(), env, err);
        if (!s) diags_.Error(src + "/" + key, Label(label) + err);
        else copy[key] = *s;
      }
    }
    x_.source.push_back({dst, src, label});
    out.push_back(std::move(copy));
  }

  // One automaton (plain or an instance) from the object a at src.
  void Automaton(const Json& a, const std::string& src, const Env& env, const std::string& label,
                 const std::string& name, Json& automata) {
    std::string dst = "/automata/" + std::to_string(automata.size());
    x_.source.push_back({dst, src, label});
    if (!a.is_object()) {  // LoadDomain reports it
      automata.push_back(a);
      return;
    }
    Json out = Json::object();
    for (const auto& [k, v] : a.items()) {
      if (k == "template" || k == "parameter" || k == "instances") continue;
      bool list = k == "locations" || k == "commands" || k == "transitions";
      if (!list || !v.is_array()) {
        out[k] = v;
        continue;
      }
      Json items = Json::array();
      List(v, src + "/" + k, env, label, k == "transitions", items, dst + "/" + k);
      out[k] = std::move(items);
    }
    if (a.contains("template")) {
      out["name"] = name;
      x_.source.push_back({dst + "/name", src + "/template", label});
    } else if (a.contains("name") && a["name"].is_string()) {
      std::string err;
      auto s = Substitute(a["name"].get<std::string>(), env, err);
      if (!s) diags_.Error(src + "/name", err);
      else out["name"] = *s;
    }
    if (static_cast<long>(automata.size()) >= kMaxAutomata) {
      if (static_cast<long>(automata.size()) == kMaxAutomata)
        diags_.Error(src, "the expansion has more than 2000 automata");
      automata.push_back(Json());
      return;
    }
    automata.push_back(std::move(out));
  }

  void Automata(const Json& list, Json& automata) {
    // Pass 1: every template's instance values (a guard may quantify over any template; a
    // template's "instances" may name a template declared before it).
    struct Declared {
      std::string name, param;
      std::vector<Value> values;
    };
    std::vector<std::optional<Declared>> declared(list.size());
    for (std::size_t i = 0; i < list.size(); ++i) {
      const Json& a = list[i];
      if (!a.is_object() || !a.contains("template")) continue;
      ObjectReader r(a, "/automata/" + std::to_string(i), diags_);
      r.CheckKeys({"template", "parameter", "instances", "locations", "commands", "transitions"});
      auto name = r.String("template", true);
      auto param = r.String("parameter", true);
      const Json* in = r.Get("instances");
      if (!in) diags_.Error(r.Child("instances"), "missing required field \"instances\"");
      if (!name || !param || !in) continue;
      if (!IsPlainIdentifier(*name)) {
        diags_.Error(r.Child("template"), "'" + *name + "' is not a valid template name");
        continue;
      }
      if (instances_.count(*name)) {
        diags_.Error(r.Child("template"), "duplicate template '" + *name + "'");
        continue;
      }
      if (!IsPlainIdentifier(*param) || *param == "self" || params_.count(*param)) {
        diags_.Error(r.Child("parameter"),
                     "'" + *param + "' cannot be a template parameter" +
                         (params_.count(*param) ? ": it is a parameter of the domain" : ""));
        continue;
      }
      std::string err;
      auto values = Range(*in, params_, err);
      if (!values) {
        diags_.Error(r.Child("instances"), err);
        continue;
      }
      instances_[*name] = *values;
      declared[i] = Declared{*name, *param, *values};
      TemplateRange range{*name, {}};
      for (const Value& v : *values) range.values.push_back(v.Text());
      x_.templates.push_back(std::move(range));
    }
    // Pass 2: the automata, in the document's order.
    for (std::size_t i = 0; i < list.size(); ++i) {
      const Json& a = list[i];
      std::string src = "/automata/" + std::to_string(i);
      if (!a.is_object() || !a.contains("template")) {
        Automaton(a, src, params_, "", "", automata);
        continue;
      }
      if (!declared[i]) continue;
      for (const Value& v : declared[i]->values) {
        Env env = params_;
        env[declared[i]->param] = v;
        std::string instance = declared[i]->name + v.Text();
        env["self"] = Value{false, 0, instance};
        Automaton(a, src, env, "instance '" + instance + "' (" + declared[i]->param + "=" + v.Text(),
                  instance, automata);
      }
    }
  }

  const Env& params() const { return params_; }

 private:
  // "in instance 'robot3' (k=3, p=2): " or "with p=2: " or "".
  static std::string Label(const std::string& label) {
    if (label.empty()) return "";
    if (label.rfind("instance ", 0) == 0) return "in " + label + "): ";
    return "with " + label + ": ";
  }

  Diagnostics& diags_;
  Expansion& x_;
  Env params_;
  std::map<std::string, std::vector<Value>> instances_;
  long items_ = 0;
  std::size_t guard_chars_ = 0;  // characters of guards any/every wrote, all guards together
};

// No "for" or "template" item and no brace in any string below `j`.
bool NoTemplateSyntax(const Json& j) {
  if (j.is_string()) return j.get_ref<const std::string&>().find_first_of("{}") == std::string::npos;
  if (j.is_array()) return std::all_of(j.begin(), j.end(), NoTemplateSyntax);
  if (!j.is_object()) return true;
  if (j.contains("for") || j.contains("template")) return false;
  return std::all_of(j.begin(), j.end(), NoTemplateSyntax);
}

}  // namespace

bool ObviouslyPlain(const Json& doc) {
  if (!doc.is_object() || doc.contains("parameters")) return false;
  auto automata = doc.find("automata");
  return automata == doc.end() || NoTemplateSyntax(*automata);
}

bool UsesTemplates(const Json& doc) {
  if (ObviouslyPlain(doc)) return false;
  Diagnostics d;
  auto x = ExpandTemplates(doc, d);
  return !x || x->had_templates;
}

std::optional<Expansion> ExpandTemplates(const Json& doc, Diagnostics& diags,
                                         const ExpandOptions& options) {
  std::size_t errors_before = diags.errors().size();
  Expansion x;
  if (!doc.is_object()) {
    x.document = doc;
    return x;
  }
  Expander e(diags, x);
  if (!e.ReadParameters(doc, options)) return std::nullopt;
  x.document = Json::object();
  for (const auto& [k, v] : doc.items()) {
    if (k == "parameters") continue;
    if (k == "automata" && v.is_array()) {
      Json automata = Json::array();
      e.Automata(v, automata);
      x.document[k] = std::move(automata);
    } else if (k == "description" && v.is_string()) {
      std::string err;
      auto s = Substitute(v.get<std::string>(), e.params(), err);
      x.document[k] = s ? Json(*s) : v;  // a description is prose: braces that are not ours stay
    } else {
      x.document[k] = v;
    }
  }
  if (diags.errors().size() > errors_before) return std::nullopt;
  x.had_templates = doc.contains("parameters") || x.document != doc;
  return x;
}

void MapDiagnostics(const Expansion& x, const Json& original, const Diagnostics& in,
                    Diagnostics& out) {
  auto map = [&](const Diagnostic& d) {
    const SourceMapEntry* best = nullptr;
    for (const auto& e : x.source) {
      bool prefix = d.pointer == e.expanded ||
                    (d.pointer.size() > e.expanded.size() &&
                     d.pointer.compare(0, e.expanded.size(), e.expanded) == 0 &&
                     d.pointer[e.expanded.size()] == '/');
      if (prefix && (!best || e.expanded.size() > best->expanded.size())) best = &e;
    }
    Diagnostic m = d;
    if (!best) return m;
    m.pointer = best->source + d.pointer.substr(best->expanded.size());
    std::string label = best->instance;
    if (!label.empty())
      m.message = (label.rfind("instance ", 0) == 0 ? "in " + label + "): " : "with " + label + ": ") +
                  m.message;
    if (d.offset) {
      std::string expanded_text, written;
      try {
        Json::json_pointer ep(d.pointer), op(m.pointer);
        if (x.document.contains(ep) && x.document.at(ep).is_string())
          expanded_text = x.document.at(ep).get<std::string>();
        if (original.contains(op) && original.at(op).is_string())
          written = original.at(op).get<std::string>();
      } catch (const std::exception&) {
      }
      if (expanded_text != written) {
        m.message += " (offset " + std::to_string(*d.offset) + " of the expanded text \"" +
                     (expanded_text.size() > 300 ? expanded_text.substr(0, 300) + "..." : expanded_text) +
                     "\")";
        m.offset.reset();
      }
    }
    return m;
  };
  for (const auto& d : in.errors()) {
    Diagnostic m = map(d);
    out.Error(m.pointer, m.message, m.offset);
  }
  for (const auto& d : in.warnings()) {
    Diagnostic m = map(d);
    out.Warning(m.pointer, m.message, m.offset);
  }
}

}  // namespace ctb
