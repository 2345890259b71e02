#include "planner/encode/emit.h"

#include <algorithm>
#include <cmath>

#include "planner/expr/expr_print.h"

namespace ctb {

namespace {

long ToTicks(double seconds, long ticks_per_second) {
  return std::lround(seconds * static_cast<double>(ticks_per_second));
}

void MarkCommandsRead(const ExprInfo& info, int self, std::vector<bool>& out) {
  for (int a : info.commands_read)
    if (a != self) out[a] = true;
}

}  // namespace

ProblemInfo Analyze(const Domain& d, const StatePlan& sp) {
  ProblemInfo info;
  info.ticks_per_second = std::lround(1.0 / d.time_resolution);
  info.lo.push_back(0);
  info.hi.push_back(-1);
  info.owner.push_back(-1);
  info.transitions_of.resize(d.automata.size());
  info.command_public.assign(d.automata.size(), false);
  bool any = false;
  for (std::size_t a = 0; a < d.automata.size(); ++a) {
    for (const auto& t : d.automata[a].transitions) {
      int id = static_cast<int>(info.owner.size());
      info.owner.push_back(static_cast<int>(a));
      info.transitions_of[a].push_back(id);
      long lo = ToTicks(t.duration.lo, info.ticks_per_second);
      info.lo.push_back(lo);
      info.hi.push_back(t.duration.hi ? ToTicks(*t.duration.hi, info.ticks_per_second) : -1);
      info.max_lo = std::max(info.max_lo, lo);
      info.min_cost = any ? std::min(info.min_cost, t.cost) : t.cost;
      any = true;
      // A command read by another automaton's guard, or a guard that reads its own command in
      // a way other than "==c" in a conjunction, needs the general (free command) encoding.
      MarkCommandsRead(t.guard_info, static_cast<int>(a), info.command_public);
      if (t.commanded && t.command <= 0) info.command_public[a] = true;
    }
  }
  auto conds = [&](const Condition& c) { MarkCommandsRead(c.info, -1, info.command_public); };
  conds(sp.goal);
  conds(sp.maintenance);
  for (const auto& e : sp.episodes) {
    conds(e.accepting);
    conds(e.state);
    info.bound_sum += ToTicks(e.lower, info.ticks_per_second);
  }
  for (const auto& t : sp.temporals) {
    conds(t.event1);
    conds(t.event2);
    info.bound_sum += ToTicks(t.lower, info.ticks_per_second);
  }
  // Orders (contract section 15): their conditions may read commands, and their lower bounds
  // may make a plan wait (the time bound T must leave room for it).
  for (const auto& o : sp.orders) {
    for (const OrderEnd* e : {&o.first, &o.second})
      if (e->action < 0) conds(e->condition);
    info.bound_sum += ToTicks(o.lower, info.ticks_per_second);
  }
  return info;
}

namespace encode {

std::string PrintCondition(const Context& c, const Expr& e, const ExprInfo& info, CondMode mode) {
  const bool change = mode == CondMode::kEvent && info.IsChange();
  auto stage = [&](const Index& idx) -> std::string {
    if (idx.kind == IndexKind::kFixed) return std::to_string(std::min(idx.fixed, c.H));
    if (change && idx.kind == IndexKind::kI) return "k-1";
    return "k";
  };
  VarPrinter var = [&](const Expr& atom) -> std::string {
    switch (atom.var_kind) {
      case VarKind::kLocation:
        return "L[" + std::to_string(atom.target + 1) + "," + stage(atom.index) + "]";
      case VarKind::kCommand:
        return "U[" + std::to_string(atom.target + 1) + "," + stage(atom.index) + "]";
      case VarKind::kEpisodeState:
        return "(if k = 0 then 0 else EPSTATE[" + std::to_string(atom.target + 1) +
               ",k-1] endif)";
      case VarKind::kTemporalState:
        return "(if k = 0 then 0 else TCSTATE[" + std::to_string(atom.target + 1) +
               ",k-1] endif)";
      case VarKind::kUnresolved: break;
    }
    return "false";  // unreachable for checked trees
  };
  std::string body = PrintMiniZinc(e, var);
  if (change) return "(if k = 0 then false else " + body + " endif)";
  return body;
}

void EmitHeader(const Context& c) {
  std::string& o = c.out;
  o += "% ctburton encoding: generated, do not edit. Times are integer ticks.\n";
  o += "include \"table.mzn\";\n";
  o += "int: H;  % horizon: events e[1..H] after e[0]\n";
  o += "int: T;  % latest event time any plan with H events needs\n";
  o += "int: NA; int: NT; int: MAXL; int: MAXU; int: MAXCOST; int: MINCOST;\n";
  o += "array[1..NA] of int: INIT;\narray[1..NA] of int: NLOC;\narray[1..NA] of int: NCMD;\n";
  o += "array[0..NT] of int: LO;\narray[0..NT] of int: HI;\narray[0..NT] of int: COST;\n";
  o += "array[0..NT] of int: CMD;\narray[0..NT] of int: FROM;\n";
  o += "array[1..NA] of set of int: TRS;\narray[int, 1..4] of int: TAB;\n";
  o += "array[1..NA, 0..MAXL, 0..MAXL] of int: DIST;  % min time between entering locations\n";
  o += "array[1..NA, 0..MAXL, 0..MAXL] of int: CDIST;  % min cost between locations\n\n";
  o += "array[0..H] of var 0..T: e;\n";
  o += "array[1..NA, 0..H] of var 0..MAXL: L;\n";
  o += "array[1..NA, 0..H-1] of var 0..NT: X;\n";
  o += "array[1..NA, 0..H] of var 0..T: N;\n";
  o += "array[1..NA, 0..H] of var 0..MAXU: U;\n";
  o += "var 0..H: g;  % the event at which the end state is accepted\n\n";
}

}  // namespace encode

Encoding Encode(const Domain& d, const StatePlan& sp, const ProblemInfo& info,
                const EncodeOptions& opts) {
  Encoding enc;
  const int H = opts.horizon;
  enc.time_bound = info.TimeBound(H);
  encode::Context c{d, sp, info, opts, enc.model, H};
  encode::EmitHeader(c);
  encode::EmitAutomata(c);
  if (opts.history) encode::EmitHistory(c);
  encode::EmitStatePlan(c);
  encode::EmitObjectiveAndSearch(c, enc);

  // Data file.
  Json& data = enc.data;
  const int NT = static_cast<int>(info.owner.size()) - 1;
  long max_cost = 0;
  int max_l = 0, max_u = 0;
  Json init = Json::array(), nloc = Json::array(), ncmd = Json::array(), trs = Json::array();
  Json lo = {0}, hi = {enc.time_bound}, cost = {0}, cmd = {0}, from = {0};
  Json tab = Json::array();
  for (std::size_t a = 0; a < d.automata.size(); ++a) {
    const Automaton& au = d.automata[a];
    init.push_back(sp.initial[a]);
    nloc.push_back(au.locations.size());
    ncmd.push_back(au.commands.size());
    max_l = std::max<int>(max_l, static_cast<int>(au.locations.size()) - 1);
    max_u = std::max<int>(max_u, static_cast<int>(au.commands.size()));
    Json ids = {0};
    for (std::size_t l = 0; l < au.locations.size(); ++l)
      tab.push_back({a + 1, l, 0, l});
    for (std::size_t k = 0; k < au.transitions.size(); ++k) {
      const Transition& t = au.transitions[k];
      int id = info.transitions_of[a][k];
      ids.push_back(id);
      tab.push_back({a + 1, t.from, id, t.to});
      lo.push_back(info.lo[id]);
      hi.push_back(info.hi[id] < 0 ? enc.time_bound : std::min(info.hi[id], enc.time_bound));
      cost.push_back(t.cost);
      cmd.push_back(t.commanded ? t.command : 0);
      from.push_back(t.from);
      max_cost = std::max(max_cost, t.cost);
    }
    trs.push_back({{"set", ids}});
  }
  // DIST / CDIST: all-pairs shortest time from entering one location to entering another, and
  // cheapest way between them (guards ignored: a relaxation, valid for every run).
  const long inf = enc.time_bound + 1, cinf = max_cost * std::max(H, 1) + 1;
  auto all_pairs = [&](std::size_t a, bool by_cost) {
    const Automaton& au = d.automata[a];
    const std::size_t n = au.locations.size();
    const long big = by_cost ? cinf : inf;
    std::vector<std::vector<long>> m(max_l + 1, std::vector<long>(max_l + 1, big));
    for (std::size_t l = 0; l < n; ++l) m[l][l] = 0;
    for (std::size_t k = 0; k < au.transitions.size(); ++k) {
      const Transition& t = au.transitions[k];
      long w = by_cost ? t.cost : info.lo[info.transitions_of[a][k]];
      m[t.from][t.to] = std::min(m[t.from][t.to], w);
    }
    for (std::size_t v = 0; v < n; ++v)
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) m[i][j] = std::min(m[i][j], m[i][v] + m[v][j]);
    for (auto& row : m)
      for (auto& x : row) x = std::min(x, big);
    return m;
  };
  Json dist = Json::array(), cdist = Json::array();
  for (std::size_t a = 0; a < d.automata.size(); ++a) {
    dist.push_back(all_pairs(a, false));
    cdist.push_back(all_pairs(a, true));
  }
  data = {{"H", H}, {"DIST", dist}, {"CDIST", cdist}, {"T", enc.time_bound}, {"NA", d.automata.size()}, {"NT", NT},
          {"MAXL", max_l}, {"MAXU", max_u}, {"MAXCOST", max_cost * std::max(H, 1)},
          {"MINCOST", info.min_cost}, {"INIT", init}, {"NLOC", nloc}, {"NCMD", ncmd},
          {"LO", lo}, {"HI", hi}, {"COST", cost}, {"CMD", cmd}, {"FROM", from}, {"TRS", trs},
          {"TAB", tab}};
  if (opts.history) encode::AddHistoryData(c, data);
  return enc;
}

}  // namespace ctb
