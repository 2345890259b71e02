#include "planner/model/plan_cut.h"

#include <numeric>

namespace ctb {

namespace {

int Find(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace

CutShape ShapeOf(const PlanCut& cut) {
  const int n = static_cast<int>(cut.points.size());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (auto [x, y] : cut.same) parent[Find(parent, x)] = Find(parent, y);
  CutShape s;
  s.class_of.assign(n, -1);
  std::vector<int> root_class(n, -1);
  int classes = 0;
  for (int p = 0; p < n; ++p) {
    const int r = Find(parent, p);
    if (root_class[r] < 0) root_class[r] = classes++;
    s.class_of[p] = root_class[r];
  }
  s.pins.assign(classes, CutPin{});
  std::vector<bool> pinned(classes, false);
  auto pin = [&](int c, CutPin p) {
    if (pinned[c]) return;
    pinned[c] = true;
    s.pins[c] = p;
    s.order.push_back(c);
  };
  for (int p = 0; p < n; ++p)
    if (cut.points[p].automaton < 0) pin(s.class_of[p], CutPin{CutPin::Kind::kOrigin});
  for (std::size_t m = 0; m < cut.marks.size(); ++m) {
    const CutMark& mk = cut.marks[m];
    CutPin p;
    p.kind = mk.kind == CutMark::Kind::kGoal ? CutPin::Kind::kGoal : CutPin::Kind::kMark;
    p.mark = static_cast<int>(m);
    pin(s.class_of[mk.point], p);
  }
  // Propagate through `next`; where nothing is left to propagate and a class is still free, it
  // becomes a loop class (pinned by the loop) and propagation goes on from it.
  for (;;) {
    for (bool changed = true; changed;) {
      changed = false;
      for (auto [x, y] : cut.next) {
        const int cx = s.class_of[x], cy = s.class_of[y], a = cut.points[y].automaton;
        if (pinned[cx] && !pinned[cy]) {
          pin(cy, CutPin{CutPin::Kind::kAfter, -1, cx, a});
          changed = true;
        } else if (pinned[cy] && !pinned[cx]) {
          pin(cx, CutPin{CutPin::Kind::kBefore, -1, cy, a});
          changed = true;
        }
      }
    }
    int free_class = -1;
    for (int c = 0; c < classes && free_class < 0; ++c)
      if (!pinned[c]) free_class = c;
    if (free_class < 0) break;
    s.loops.push_back(free_class);
    pin(free_class, CutPin{CutPin::Kind::kLoop});
  }
  return s;
}

std::vector<std::pair<int, int>> DistinctPairs(const PlanCut& cut) {
  std::vector<std::pair<int, int>> out;
  const int n = static_cast<int>(cut.points.size());
  for (int x = 0; x < n; ++x)
    for (int y = x + 1; y < n; ++y)
      if (cut.points[x].automaton >= 0 && cut.points[x].automaton == cut.points[y].automaton)
        out.emplace_back(x, y);
  return out;
}

}  // namespace ctb
