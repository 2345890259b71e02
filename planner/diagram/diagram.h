// Diagrams of an action model as SVG (contract section 12, GET /domains/{name}/diagram).
//
// One panel per automaton, top to bottom. Locations are boxes laid out in columns by their BFS
// depth from the automaton's first location (locations no transition reaches come last);
// transitions are arrows labelled with what fires them: the command (commanded transitions), the
// rest of the guard, and the duration ("after 4 s", "[2, 10] s"). Every automaton, location and
// command is written as text (and escaped); a label cut for space keeps its full text in a
// <title>. No external tool; deterministic output. Never throws.
#pragma once

#include <string>

#include "planner/model/domain.h"

namespace ctb {

struct DiagramOptions {
  std::size_t max_label_chars = 48;  // longer edge labels are cut (the full text in <title>)
};

// The whole domain as one SVG document (UTF-8, starts with "<svg").
std::string DomainSvg(const Domain& d, const DiagramOptions& o = {});

// The label of a transition's arrow: "goToDoor1", "goToPerson1 · door3l[i]==open", "after 4 s",
// "door1l[i]==open", or "" for an unguarded, untimed automatic transition.
std::string TransitionLabel(const Domain& d, const Automaton& a, const Transition& t);

}  // namespace ctb
