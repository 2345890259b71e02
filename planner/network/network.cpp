#include "planner/network/network.h"

#include <cmath>
#include <string>

namespace ctb::network {

const char* PointKindName(PointKind k) {
  switch (k) {
    case PointKind::kOrigin:
      return "origin";
    case PointKind::kControllable:
      return "controllable";
    case PointKind::kContingent:
      return "contingent";
  }
  return "controllable";
}

std::optional<Ticks> TicksFromSeconds(double seconds) {
  if (!std::isfinite(seconds) || std::fabs(seconds) > kMaxAbsSeconds) return std::nullopt;
  const double scaled = seconds * static_cast<double>(kTicksPerSecond);
  const double rounded = std::nearbyint(scaled);
  if (std::fabs(scaled - rounded) > 1e-6) return std::nullopt;
  return static_cast<Ticks>(rounded);
}

double SecondsFromTicks(Ticks t) {
  return static_cast<double>(t) / static_cast<double>(kTicksPerSecond);
}

namespace {

std::string LinkPointer(std::size_t i) { return "/links/" + std::to_string(i); }

}  // namespace

void CheckLinkBounds(const Link& l, const std::string& p, Diagnostics& diags) {
  if (l.contingent) {
    if (l.lb < 0) diags.Error(p + "/lb", "a contingent link needs lb >= 0");
    if (!l.ub) {
      diags.Error(p + "/ub", "a contingent link needs a finite ub");
    } else if (*l.ub < l.lb) {
      diags.Error(p + "/ub", "ub is below lb");
    }
  } else if (l.ub && *l.ub < l.lb) {
    diags.Error(p + "/ub", "ub is below lb");
  }
}

namespace {

// Marks each point's contingent link (the only one that ends there) and reports a second one.
std::vector<int> ContingentParents(const Network& net, Diagnostics& diags) {
  std::vector<int> parent_link(net.points.size(), -1);
  for (std::size_t i = 0; i < net.links.size(); ++i) {
    const Link& l = net.links[i];
    if (!l.contingent) continue;
    int& slot = parent_link[static_cast<std::size_t>(l.to)];
    if (slot >= 0) {
      diags.Error(LinkPointer(i) + "/to", "the point is already the end of contingent link " +
                                              LinkPointer(static_cast<std::size_t>(slot)));
    } else {
      slot = static_cast<int>(i);
    }
  }
  return parent_link;
}

// A cycle of contingent links has no first activation: every such cycle is reported once.
void CheckContingentForest(const Network& net, const std::vector<int>& parent_link,
                           Diagnostics& diags) {
  const std::size_t n = net.points.size();
  std::vector<int> state(n, 0);  // 0 unseen, 1 on the current walk, 2 done
  for (std::size_t start = 0; start < n; ++start) {
    std::vector<std::size_t> walk;
    std::size_t v = start;
    while (state[v] == 0) {
      state[v] = 1;
      walk.push_back(v);
      const int pl = parent_link[v];
      if (pl < 0) break;
      v = static_cast<std::size_t>(net.links[static_cast<std::size_t>(pl)].from);
    }
    if (state[v] == 1 && parent_link[v] >= 0 && !walk.empty()) {
      diags.Error(LinkPointer(static_cast<std::size_t>(parent_link[v])),
                  "contingent links form a cycle (a contingent point activates "
                  "itself)");
    }
    for (std::size_t w : walk) state[w] = 2;
  }
}

void CheckKinds(const Network& net, const std::vector<int>& parent_link, Diagnostics& diags) {
  int origins = 0;
  for (std::size_t i = 0; i < net.points.size(); ++i) {
    const Point& p = net.points[i];
    const std::string ptr = "/points/" + std::to_string(i);
    if (p.id != static_cast<int>(i)) diags.Error(ptr + "/id", "id must equal the point's index");
    const bool is_end = parent_link[i] >= 0;
    if (p.kind == PointKind::kOrigin && ++origins > 1) diags.Error(ptr, "a second origin");
    if (is_end && p.kind != PointKind::kContingent) {
      diags.Error(ptr + "/kind", "the end of a contingent link must be a contingent point");
    } else if (!is_end && p.kind == PointKind::kContingent) {
      diags.Error(ptr + "/kind", "a contingent point must be the end of a contingent link");
    }
  }
}

}  // namespace

bool Validate(const Network& net, Diagnostics& diags) {
  Diagnostics local;
  const int n = static_cast<int>(net.points.size());
  bool ends_ok = true;
  for (std::size_t i = 0; i < net.links.size(); ++i) {
    const Link& l = net.links[i];
    const std::string p = LinkPointer(i);
    if (l.from < 0 || l.from >= n) local.Error(p + "/from", "no such point"), ends_ok = false;
    if (l.to < 0 || l.to >= n) local.Error(p + "/to", "no such point"), ends_ok = false;
    if (ends_ok && l.from == l.to) local.Error(p, "a link from a point to itself");
    CheckLinkBounds(l, p, local);
  }
  if (ends_ok) {
    const std::vector<int> parent_link = ContingentParents(net, local);
    CheckContingentForest(net, parent_link, local);
    CheckKinds(net, parent_link, local);
  }
  diags.Append(local);
  return local.ok();
}

}  // namespace ctb::network
