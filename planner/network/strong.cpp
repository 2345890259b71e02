// Strong controllability (Vidal & Fargier 1999, "Handling contingency in temporal constraint
// networks"): every point is its controllable root (the first point up its chain of contingent
// links) plus the sum of the durations along the chain. A requirement t(Y) - t(X) in [lb, ub] holds
// for every outcome iff it holds for the extreme sums; the durations on the common part of the two
// chains cancel. What is left is an STN over the roots, consistent iff the network is strongly
// controllable.
#include <algorithm>

#include "planner/network/check.h"
#include "planner/network/stn.h"

namespace ctb::network {
namespace {

struct Chain {
  int parent = -1;  // activation point, or -1 for a root
  int depth = 0;
  Ticks lo = 0;  // sum of lower bounds from the root
  Ticks hi = 0;  // sum of upper bounds from the root
  int root = 0;
};

// Chains in an order where parents come first (the contingent links form a forest).
std::vector<Chain> BuildChains(const Network& net) {
  const std::size_t n = net.points.size();
  std::vector<Chain> chain(n);
  std::vector<int> parent_link(n, -1);
  for (std::size_t i = 0; i < net.links.size(); ++i) {
    const Link& l = net.links[i];
    if (l.contingent) parent_link[static_cast<std::size_t>(l.to)] = static_cast<int>(i);
  }
  std::vector<char> done(n, 0);
  for (std::size_t s = 0; s < n; ++s) {
    std::vector<std::size_t> walk;  // s and its not yet computed ancestors
    std::size_t v = s;
    while (!done[v]) {
      walk.push_back(v);
      if (parent_link[v] < 0) break;
      v = static_cast<std::size_t>(net.links[static_cast<std::size_t>(parent_link[v])].from);
    }
    for (auto it = walk.rbegin(); it != walk.rend(); ++it) {
      Chain& c = chain[*it];
      const int pl = parent_link[*it];
      if (pl < 0) {
        c = {-1, 0, 0, 0, static_cast<int>(*it)};
      } else {
        const Link& l = net.links[static_cast<std::size_t>(pl)];
        const Chain& p = chain[static_cast<std::size_t>(l.from)];
        c = {l.from, p.depth + 1, p.lo + l.lb, p.hi + *l.ub, p.root};
      }
      done[*it] = 1;
    }
  }
  return chain;
}

// The lowest common point of two chains with the same root.
int CommonAncestor(const std::vector<Chain>& chain, int a, int b) {
  while (chain[static_cast<std::size_t>(a)].depth > chain[static_cast<std::size_t>(b)].depth) {
    a = chain[static_cast<std::size_t>(a)].parent;
  }
  while (chain[static_cast<std::size_t>(b)].depth > chain[static_cast<std::size_t>(a)].depth) {
    b = chain[static_cast<std::size_t>(b)].parent;
  }
  while (a != b) {
    a = chain[static_cast<std::size_t>(a)].parent;
    b = chain[static_cast<std::size_t>(b)].parent;
  }
  return a;
}

}  // namespace

bool IsStronglyControllable(const Network& net) {
  const std::vector<Chain> chain = BuildChains(net);
  std::vector<internal::StnEdge> edges;
  for (std::size_t i = 0; i < net.links.size(); ++i) {
    const Link& l = net.links[i];
    if (l.contingent) continue;  // holds by itself once its end is a root plus the duration
    const Chain& x = chain[static_cast<std::size_t>(l.from)];
    const Chain& y = chain[static_cast<std::size_t>(l.to)];
    Ticks base_lo = 0, base_hi = 0;  // the common part's sums, which cancel
    if (x.root == y.root) {
      const Chain& c = chain[static_cast<std::size_t>(CommonAncestor(chain, l.from, l.to))];
      base_lo = c.lo;
      base_hi = c.hi;
    }
    // t(Y) - t(X) = t(rY) - t(rX) + dY - dX with dY in [y.lo - base_lo, y.hi - base_hi], ...
    const Ticks min_diff = (y.lo - base_lo) - (x.hi - base_hi);
    const Ticks max_diff = (y.hi - base_hi) - (x.lo - base_lo);
    const int li = static_cast<int>(i);
    if (l.ub) {
      const Ticks w = *l.ub - max_diff;  // t(rY) - t(rX) <= ub - max_diff
      if (x.root == y.root) {
        if (w < 0) return false;
      } else {
        edges.push_back({x.root, y.root, w, li});
      }
    }
    const Ticks w = min_diff - l.lb;  // t(rX) - t(rY) <= min_diff - lb
    if (x.root == y.root) {
      if (w < 0) return false;
    } else {
      edges.push_back({y.root, x.root, w, li});
    }
  }
  return internal::BellmanFord(static_cast<int>(net.points.size()), edges, nullptr, nullptr);
}

}  // namespace ctb::network
