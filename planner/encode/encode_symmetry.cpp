// Symmetry breaking (issue 18, lever 4): the units of each orbit of interchangeable automata
// (analyze/symmetry.h) in lexicographic order of their runs.
//
// The key of a unit is its members' locations at events 1..H, then their entry times (L[a,k],
// N[a,k]), both fixed by the plan itself (its transitions and event times). Every
// permutation of an orbit's units is a symmetry that keeps the cost, the makespan and the number
// of events, so every plan in the model has an image in it whose keys are sorted: requiring
// key(unit j) <=lex key(unit j+1) loses no objective value, only symmetric copies. Orbits are
// disjoint and each exchange fixes everything outside its orbit, so sorting one orbit leaves the
// others' keys alone and the constraints of all orbits hold together.
#include <string>

#include "planner/encode/emit.h"

namespace ctb::encode {

namespace {

// [L[u1,1], L[u2,1], ..., L[ur,H]] ++ [N[u1,1], ..., N[ur,H]] for unit `unit` of the orbit
// table `table`: locations event by event first (they propagate from the transitions the search
// fixes), entry times to break the ties (measured: bench/results/symmetry.md).
std::string Key(const std::string& table, const std::string& unit) {
  auto row = [&](const char* var) {
    const std::string member = table + "[" + unit + ",u]";
    return std::string("[") + var + "[" + member + ",k] | k in 1..H, u in index_set_2of2(" + table +
           ")]";
  };
  return "(" + row("L") + " ++ " + row("N") + ")";
}

}  // namespace

void EmitSymmetry(const Context& c) {
  if (!c.opts.symmetry || c.opts.history || c.opts.minimize_changes) return;
  if (c.info.symmetries.empty() || c.H < 1) return;
  std::string& o = c.out;
  o += "% symmetry: the units of each orbit of interchangeable automata in lexicographic order\n";
  o += "include \"lex_lesseq.mzn\";\n";
  for (std::size_t i = 0; i < c.info.symmetries.size(); ++i) {
    const auto& units = c.info.symmetries[i].units;
    const std::string table = "SYM" + std::to_string(i + 1);
    std::string rows;
    for (const auto& unit : units)
      for (int a : unit) rows += (rows.empty() ? "" : ", ") + std::to_string(a + 1);
    const std::string m = std::to_string(units.size()), r = std::to_string(units[0].size());
    o += "array[1.." + m + ", 1.." + r + "] of int: " + table + " = array2d(1.." + m + ", 1.." + r +
         ", [" + rows + "]);\n";
    o += "constraint forall(j in 1.." + std::to_string(units.size() - 1) + ")(lex_lesseq(" +
         Key(table, "j") + ", " + Key(table, "j+1") + "));\n";
  }
}

}  // namespace ctb::encode
