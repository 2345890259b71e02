// Symmetries of a planning problem (issue 18, lever 4): interchangeable automata, detected from
// the checked trees and never declared by the user.
//
// A symmetry here exchanges automata pairwise (an involution on the automata) together with
// a bijection on the episodes and one on the temporal constraints, such that
//   - each automaton and its image have the same locations, commands, initial location and
//     transitions (in order: ends, durations, costs, kinds), and every guard, with the exchange
//     applied to the automata it reads, equals the image's guard up to the order of the operands
//     of /\, \/ and <->;
//   - the goal and the maintenance constraint map to themselves in the same sense, each episode
//     and temporal constraint to one with the same bounds, the same change/state classification
//     and the same conditions (episode and temporal states renamed by the bijections), and the
//     shared events onto the shared events.
// Such a map takes every plan to a plan of equal cost and makespan (the objective only sums).
//
// An orbit is a set of units (groups of automata, e.g. a computer, its connection and its
// projector) every two of which can be exchanged member by member, each exchange checked as
// above: the exchanges of unit 0 with unit j generate every permutation of the units, so every
// plan has a symmetric image whose units come in any chosen order (the encoder orders them
// lexicographically, planner/encode/encode_symmetry.cpp).
//
// Conservative: what cannot be proven symmetric is not. Units are found by closure from one
// automaton (exchanging a and b forces exchanging what their guards read in the same places), so
// a unit whose members are tied together only by the state plan, or only by guards that read
// into the unit from outside it, is not found. Depends on the model and the expression language
// only. Thread-safe: no shared state.
#pragma once

#include <vector>

#include "planner/model/domain.h"
#include "planner/model/state_plan.h"

namespace ctb {

struct SymmetryOrbit {
  // units[j][i]: automaton i of unit j. All units have the same size (1 for single automata);
  // exchanging units[0][i] with units[j][i] for every i, everything else fixed, is a symmetry.
  std::vector<std::vector<int>> units;
};

// The orbits of d and sp: pairwise disjoint, each with at least two units. Empty when none is
// found (always a valid answer).
std::vector<SymmetryOrbit> FindSymmetries(const Domain& d, const StatePlan& sp);

// True when exchanging a with perm[a] for every automaton a (perm must be an involution: perm[a]
// = b exactly when perm[b] = a) is a symmetry of d and sp in the sense above. False for anything
// else, including a perm of the wrong size.
bool IsSymmetry(const Domain& d, const StatePlan& sp, const std::vector<int>& perm);

}  // namespace ctb
