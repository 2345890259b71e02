// Replanning (planner/replan, contract section 11): a fixed history at the start of the run, the
// "keep started" rule, and the "min_change" objective. The history's events 0..P are data (HE,
// HL, HN, HX); the automata's rules apply from event P on (encode_automata.cpp), the state plan's
// to the whole run.
#include <string>

#include "planner/encode/emit.h"

namespace ctb::encode {

void EmitHistory(const Context& c) {
  const History& h = *c.opts.history;
  std::string& o = c.out;
  o += "% fixed history (replanning): events 0..P as reported; the future from NOW on\n";
  o += "int: P; int: NOW;\n";
  o += "array[0..P] of int: HE;\narray[1..NA, 0..P] of int: HL;\narray[1..NA, 0..P] of int: HN;\n";
  o += "constraint H >= P /\\ g >= P;\n";
  o += "constraint forall(k in 0..P)(e[k] = HE[k]);\n";
  o += "constraint forall(a in 1..NA, k in 0..P)(L[a,k] = HL[a,k] /\\ N[a,k] = HN[a,k]);\n";
  if (h.events() > 0) {
    o += "array[1..NA, 0..P-1] of int: HX;\n";
    o += "constraint forall(a in 1..NA, k in 0..P-1)(X[a,k] = HX[a,k]);\n";
  }
  o += "constraint forall(k in P..H-1)(k < g -> e[k+1] >= NOW);\n";
  // keep "started": the automaton's first transition after the history is this one.
  for (auto [a, ti] : h.keep_next) {
    std::string A = std::to_string(a + 1), id = std::to_string(c.info.transitions_of[a][ti]);
    o += "constraint exists(k in P..H-1)(X[" + A + ",k] = " + id + " /\\ forall(j in P..k-1)(X[" +
         A + ",j] = 0));  % keep: started\n";
  }
  o += "\n";
}

void AddHistoryData(const Context& c, Json& data) {
  const History& h = *c.opts.history;
  const int p = h.events();
  const std::size_t na = c.d.automata.size();
  data["P"] = p;
  data["NOW"] = h.now;
  data["HE"] = h.times;
  Json hl = Json::array(), hn = Json::array(), hx = Json::array();
  for (std::size_t a = 0; a < na; ++a) {
    hl.push_back(h.locations[a]);
    hn.push_back(h.entry[a]);
    hx.push_back(std::vector<int>(p, 0));
  }
  for (const auto& f : h.fired)
    hx[f.automaton][f.event - 1] = c.info.transitions_of[f.automaton][f.transition];
  data["HL"] = hl;
  data["HN"] = hn;
  if (p > 0) data["HX"] = hx;
}

// changes = added + dropped + moved = n_new + n_base - keymatched - kept, where a baseline
// transition is key-matched when the future takes it at any time and kept when at its time.
std::string MinChangeSolve(const Context& c) {
  std::string o = "% keep: min_change (among plans at most as good as the optimum)\n";
  o += "constraint objective <= " + std::to_string(c.opts.objective_at_most) + ";\n";
  std::string matched = "0";
  for (auto [id, time] : c.opts.baseline) {
    const int a = c.info.owner[id] + 1;
    std::string A = std::to_string(a), I = std::to_string(id), T = std::to_string(time);
    matched += " + bool2int(exists(k in " + c.K0() + "..H-1)(X[" + A + ",k] = " + I + "))";
    matched += " + bool2int(exists(k in " + c.K0() + "..H-1)(X[" + A + ",k] = " + I +
               " /\\ e[k+1] = " + T + "))";
  }
  o += "var int: changes = sum(a in 1..NA, k in " + c.K0() + "..H-1)(bool2int(X[a,k] > 0)) + " +
       std::to_string(c.opts.baseline.size()) + " - (" + matched + ");\n";
  o += "solve " + TimeOrderSearch(c) + " minimize changes;\n";
  return o;
}

}  // namespace ctb::encode
