// What a checked expression reads.
#pragma once

#include <set>

namespace ctb {

// What a checked expression reads; used to classify conditions and to analyse the domain.
struct ExprInfo {
  bool domain_uses_i = false;      // a location/command variable at [i]
  bool domain_uses_i1 = false;     // ... at [i+1]
  bool uses_fixed = false;         // ... at a fixed stage
  int max_fixed = -1;              // the latest fixed stage read (-1: none)
  std::set<int> locations_read;    // automata whose location is read
  std::set<int> commands_read;     // automata whose command is read
  std::set<int> episodes_read;
  std::set<int> temporals_read;
  // A condition that reads domain variables at both [i] and [i+1] describes a change.
  bool IsChange() const { return domain_uses_i && domain_uses_i1; }
};

}  // namespace ctb
