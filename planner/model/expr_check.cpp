#include "planner/model/expr_check.h"

#include <algorithm>
#include <set>

namespace ctb {

const char* const kEpisodeVarPrefix = "epAcceptAutomatonTraj_";
const char* const kTemporalVarPrefix = "temporalAcceptConstraint_Traj_";

const std::vector<std::string>& EpisodeStateNames() {
  static const std::vector<std::string> names = {"epWaiting", "epActive", "epAccepted",
                                                 "epFailed"};
  return names;
}

const std::vector<std::string>& TemporalStateNames() {
  static const std::vector<std::string> names = {"tempWaiting", "tempActive", "tempAccepted",
                                                 "tempFailed"};
  return names;
}

namespace {

std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      std::size_t sub = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string DidYouMean(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best = NearestName(word, candidates);
  return best.empty() ? "" : " (did you mean '" + best + "'?)";
}

int Find(const std::vector<std::string>& v, const std::string& s) {
  auto it = std::find(v.begin(), v.end(), s);
  return it == v.end() ? -1 : static_cast<int>(it - v.begin());
}

class Checker {
 public:
  Checker(const Scope& scope, ExprContext ctx, const std::string& pointer, Diagnostics& diags,
          ExprInfo& info)
      : scope_(scope), ctx_(ctx), pointer_(pointer), diags_(diags), info_(info) {}

  bool Visit(Expr& e) {
    if (e.op == Expr::Op::kAtom && !e.binding.empty()) {
      // An atom a quantifier made: one error per place in the text, not one per value.
      if (bad_offsets_.count(e.var_offset)) return false;
      current_ = &e;
      const std::size_t errors = diags_.errors().size();
      const bool ok = Atom(e);
      current_ = nullptr;
      if (diags_.errors().size() > errors) bad_offsets_.insert(e.var_offset);
      return ok;
    }
    if (e.op != Expr::Op::kAtom) {
      bool ok = true;
      for (auto& k : e.kids) ok = Visit(k) && ok;
      return ok;
    }
    return Atom(e);
  }

 private:
  bool Err(std::size_t offset, std::string msg) {
    if (current_) msg += " (where " + current_->binding + ")";
    diags_.Error(pointer_, std::move(msg), offset);
    return false;
  }

  std::vector<std::string> AllVariableNames() const {
    std::vector<std::string> names;
    for (const auto& a : scope_.domain->automata) {
      names.push_back(a.name + "l");
      names.push_back(a.name + "u");
      names.push_back(a.name);
    }
    for (const auto& n : scope_.episodes) names.push_back(kEpisodeVarPrefix + n);
    for (const auto& n : scope_.temporals) names.push_back(kTemporalVarPrefix + n);
    return names;
  }

  int AutomatonIndex(const std::string& name) const {
    if (!scope_.automaton_index) return scope_.domain->AutomatonIndex(name);
    auto it = scope_.automaton_index->find(name);
    return it == scope_.automaton_index->end() ? -1 : it->second;
  }

  // Resolves e.var into (var_kind, target).
  bool ResolveVar(Expr& e) {
    const Domain& d = *scope_.domain;
    const std::string& v = e.var;
    const std::string ep_prefix = kEpisodeVarPrefix, tc_prefix = kTemporalVarPrefix;
    if (v.rfind(ep_prefix, 0) == 0 || v.rfind(tc_prefix, 0) == 0) {
      bool is_ep = v.rfind(ep_prefix, 0) == 0;
      if (ctx_ == ExprContext::kGuard)
        return Err(e.var_offset, "a guard cannot read the state-plan automaton '" + v + "'");
      std::string name = v.substr((is_ep ? ep_prefix : tc_prefix).size());
      const auto& names = is_ep ? scope_.episodes : scope_.temporals;
      int idx = Find(names, name);
      if (idx < 0)
        return Err(e.var_offset, std::string("unknown ") + (is_ep ? "episode" : "temporal constraint") +
                                     " '" + name + "'" + DidYouMean(name, names));
      e.var_kind = is_ep ? VarKind::kEpisodeState : VarKind::kTemporalState;
      e.target = idx;
      return true;
    }
    int a = AutomatonIndex(v);
    if (a >= 0) {
      e.var_kind = VarKind::kLocation;
      e.target = a;
      return true;
    }
    if (v.size() > 1) {
      int base = AutomatonIndex(v.substr(0, v.size() - 1));
      if (base >= 0 && (v.back() == 'l' || v.back() == 'u')) {
        e.var_kind = v.back() == 'l' ? VarKind::kLocation : VarKind::kCommand;
        e.target = base;
        return true;
      }
    }
    return Err(e.var_offset, "unknown variable '" + v + "'" + DidYouMean(v, AllVariableNames()));
  }

  bool CheckIndex(Expr& e) {
    const Index& idx = e.index;
    bool accepting = e.var_kind == VarKind::kEpisodeState || e.var_kind == VarKind::kTemporalState;
    if (ctx_ == ExprContext::kGuard) {
      if (idx.kind != IndexKind::kI)
        return Err(idx.offset, "a guard is read on the stage before its transition: write '" +
                                   e.var + "[i]'");
      return true;
    }
    if (accepting) {
      if (idx.kind != IndexKind::kI)
        return Err(idx.offset, "a state-plan automaton can only be read at [i] (its state before "
                               "the event): write '" + e.var + "[i]'");
      return true;
    }
    if (idx.kind == IndexKind::kFixed) {
      if (!current_ || warned_offsets_.insert(idx.offset).second)  // once per place in the text
        diags_.Warning(pointer_, "fixed stage index [" + std::to_string(idx.fixed) + "] on '" +
                                     e.var + "': did you mean [i] or [i+1]?", idx.offset);
      info_.uses_fixed = true;
      info_.max_fixed = std::max(info_.max_fixed, idx.fixed);
    } else if (idx.kind == IndexKind::kI) {
      info_.domain_uses_i = true;
    } else {
      info_.domain_uses_i1 = true;
    }
    return true;
  }

  bool ResolveValue(Expr& e) {
    const Domain& d = *scope_.domain;
    switch (e.var_kind) {
      case VarKind::kLocation: {
        const Automaton& a = d.automata[e.target];
        int loc = a.LocationIndex(e.value);
        if (loc < 0)
          return Err(e.value_offset, "unknown location '" + e.value + "' of automaton '" + a.name +
                                         "'" + DidYouMean(e.value, a.locations));
        e.value_code = loc;
        info_.locations_read.insert(e.target);
        return true;
      }
      case VarKind::kCommand: {
        const Automaton& a = d.automata[e.target];
        int c = a.CommandCode(e.value);
        if (c < 0) {
          if (a.commands.empty())
            return Err(e.value_offset, "automaton '" + a.name + "' has no commands");
          return Err(e.value_offset, "unknown command '" + e.value + "' of automaton '" + a.name +
                                         "'" + DidYouMean(e.value, a.commands));
        }
        e.value_code = c;
        info_.commands_read.insert(e.target);
        return true;
      }
      case VarKind::kEpisodeState:
      case VarKind::kTemporalState: {
        bool is_ep = e.var_kind == VarKind::kEpisodeState;
        const auto& names = is_ep ? EpisodeStateNames() : TemporalStateNames();
        int s = Find(names, e.value);
        if (s < 0)
          return Err(e.value_offset, "unknown state '" + e.value + "' of '" + e.var + "'" +
                                         DidYouMean(e.value, names));
        e.value_code = s;
        (is_ep ? info_.episodes_read : info_.temporals_read).insert(e.target);
        return true;
      }
      case VarKind::kUnresolved: break;
    }
    return false;
  }

  bool Atom(Expr& e) {
    if (!ResolveVar(e)) return false;
    if (!CheckIndex(e)) return false;
    return ResolveValue(e);
  }

  const Scope& scope_;
  ExprContext ctx_;
  const std::string& pointer_;
  Diagnostics& diags_;
  ExprInfo& info_;
  const Expr* current_ = nullptr;       // the expanded atom being checked, for messages
  std::set<std::size_t> bad_offsets_;     // places of expanded atoms already reported
  std::set<std::size_t> warned_offsets_;  // ... already warned about
};

}  // namespace

std::string NearestName(const std::string& word, const std::vector<std::string>& candidates) {
  // A suggestion is a courtesy, so its cost is capped (issue 14): none for long words, candidates
  // whose length alone rules them out are skipped, and at most kMaxCells edit-distance cells per
  // call (many unknown names against many candidates cost seconds of CPU otherwise).
  constexpr std::size_t kMaxWord = 64, kMaxCells = 1 << 15;
  std::string best;
  if (word.size() > kMaxWord) return best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;
  std::size_t cells = 0;
  for (const auto& c : candidates) {
    const std::size_t gap = c.size() > word.size() ? c.size() - word.size() : word.size() - c.size();
    if (gap >= best_d) continue;
    cells += (word.size() + 1) * (c.size() + 1);
    if (cells > kMaxCells) break;
    std::size_t d = EditDistance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

std::unordered_map<std::string, int> AutomatonIndexOf(const Domain& d) {
  std::unordered_map<std::string, int> out;
  for (std::size_t a = 0; a < d.automata.size(); ++a)
    out.emplace(d.automata[a].name, static_cast<int>(a));
  return out;
}

bool CheckExpr(Expr& e, const Scope& scope, ExprContext ctx, const std::string& pointer,
               Diagnostics& diags, ExprInfo* info) {
  if (HasQuantifier(e)) {
    QuantifierBudget own;
    const Domain* d = scope.domain;
    TemplateValues values = [d](const std::string& name) -> const std::vector<std::string>* {
      const TemplateRange* t = d ? d->Template(name) : nullptr;
      return t ? &t->values : nullptr;
    };
    TemplateNames names = [d]() {
      std::vector<std::string> out;
      if (d)
        for (const auto& t : d->templates) out.push_back(t.name);
      return out;
    };
    if (auto err = ExpandQuantifiers(e, values, names, scope.budget ? *scope.budget : own)) {
      diags.Error(pointer, err->message, err->offset);
      return false;
    }
  }
  ExprInfo local;
  Checker c(scope, ctx, pointer, diags, info ? *info : local);
  return c.Visit(e);
}

std::optional<Expr> ParseChecked(const std::string& text, const Scope& scope, ExprContext ctx,
                                 const std::string& pointer, Diagnostics& diags, ExprInfo* info) {
  ExprError err;
  auto e = Parse(text, err, scope.max_length);
  if (!e) {
    diags.Error(pointer, err.message, err.offset);
    return std::nullopt;
  }
  if (!CheckExpr(*e, scope, ctx, pointer, diags, info)) return std::nullopt;
  return e;
}

DomainValueNames::DomainValueNames(const Domain& d) : d_(d) {
  for (const auto& a : d.automata) {
    std::vector<std::string> names{"(no command)"};
    names.insert(names.end(), a.commands.begin(), a.commands.end());
    commands_.push_back(std::move(names));
  }
}

ValueNames DomainValueNames::Function() const {
  return [this](VarKind kind, int target) -> const std::vector<std::string>* {
    const int na = static_cast<int>(d_.automata.size());
    switch (kind) {
      case VarKind::kLocation:
        return target >= 0 && target < na ? &d_.automata[target].locations : nullptr;
      case VarKind::kCommand:
        return target >= 0 && target < na ? &commands_[target] : nullptr;
      case VarKind::kEpisodeState: return &EpisodeStateNames();
      case VarKind::kTemporalState: return &TemporalStateNames();
      case VarKind::kUnresolved: return nullptr;
    }
    return nullptr;
  };
}

}  // namespace ctb
