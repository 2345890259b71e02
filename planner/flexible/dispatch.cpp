// Dynamic and fixed-time dispatch of a flexible plan against sampled outcomes (dispatch.h).
#include "planner/flexible/dispatch.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "planner/network/check.h"

namespace ctb::flexible {

namespace {

using network::Link;
using network::Network;
using network::PointKind;
using network::Ticks;

class Dispatcher {
 public:
  Dispatcher(const FlexiblePlan& f, const Domain& d, const std::vector<Ticks>& planned,
             const DispatchOptions& o, std::mt19937& rng)
      : f_(f), d_(d), planned_(planned), o_(o), rng_(rng), n_(f.net.points.size()),
        step_(network::kTicksPerSecond / f.tps), done_(n_, false), at_(n_, 0), due_(n_) {
    for (std::size_t i = 0; i < f.net.links.size(); ++i)
      if (f.net.links[i].contingent) contingent_of_[f.net.links[i].to] = static_cast<int>(i);
  }

  Execution Run() {
    Execution e;
    Happen(0, 0);
    Ticks t = 0;
    const Ticks limit = Horizon();
    while (Remaining() > 0) {
      if (t > limit) return Stop(e, "no point could be started by the plan's horizon");
      bool changed = true;
      while (changed) {  // nature first (what finishes now is seen now), then starts, until still
        changed = false;
        for (std::size_t p = 1; p < n_; ++p)
          if (!done_[p] && due_[p] && *due_[p] <= t) {
            Happen(static_cast<int>(p), t);
            changed = true;
          }
        for (std::size_t p = 1; p < n_; ++p)
          if (!done_[p] && Kind(p) != PointKind::kContingent && Ready(static_cast<int>(p), t)) {
            Happen(static_cast<int>(p), t);
            changed = true;
          }
      }
      t = Next(t);
    }
    e.times = at_;
    e.met = Holds(e.why);
    return e;
  }

 private:
  PointKind Kind(std::size_t p) const { return f_.net.points[p].kind; }
  int Remaining() const { return static_cast<int>(std::count(done_.begin(), done_.end(), false)); }

  Execution& Stop(Execution& e, const std::string& why) {
    e.times = at_;
    e.met = false;
    e.why = why;
    return e;
  }

  Ticks Horizon() const {
    Ticks last = 0, span = 0;
    for (Ticks x : planned_) last = std::max(last, x);
    for (const auto& l : f_.net.links) span += std::max<Ticks>(0, l.ub.value_or(l.lb));
    return last + span + network::kTicksPerSecond;
  }

  // Point p happens at t; a contingent link it activates gets nature's duration now.
  void Happen(int p, Ticks t) {
    done_[p] = true;
    at_[p] = t;
    for (const auto& [to, li] : contingent_of_)
      if (f_.net.links[li].from == p) due_[to] = t + Draw(f_.net.links[li], to);
  }

  Ticks Draw(const Link& l, int to) {
    const Ticks lo = l.lb / step_, hi = *l.ub / step_;
    const Transition& tr = d_.automata[f_.point_automaton[to]].transitions[f_.point_transition[to]];
    if (o_.sampling == Sampling::kDistribution && tr.distribution &&
        tr.distribution->kind == Distribution::Kind::kNormal) {
      std::normal_distribution<double> nd(tr.distribution->mean * f_.tps, tr.distribution->sd * f_.tps);
      for (int tries = 0; tries < 100; ++tries) {
        const Ticks x = std::llround(nd(rng_));
        if (x >= lo && x <= hi) return x * step_;
      }
    }
    return std::uniform_int_distribution<Ticks>(lo, hi)(rng_) * step_;
  }

  // The turn of controllable point p has come at t.
  bool Ready(int p, Ticks t) const {
    if (!o_.dynamic) return planned_[p] <= t;
    for (const auto& l : f_.net.links)  // every point it must follow has happened
      if (l.to == p && !done_[l.from] && l.lb >= 0) return false;
    return Controllable(p, t);
  }

  // The network that remains at t: what has happened fixed, what runs narrowed to outcomes after
  // t, every other point not before t; with p >= 0, p happens at t.
  Network Remainder(int p, Ticks t) const {
    Network net = f_.net;
    for (auto& l : net.links) {
      if (!l.contingent) continue;
      if (done_[l.to]) {
        l.contingent = false;
        l.lb = *l.ub = at_[l.to] - at_[l.from];
      } else if (done_[l.from]) {
        l.lb = std::min(*l.ub, std::max(l.lb, t + step_ - at_[l.from]));  // not finished by t
      }
    }
    for (std::size_t q = 1; q < n_; ++q) {
      Link pin;
      pin.to = static_cast<int>(q);
      if (done_[q] || static_cast<int>(q) == p) {
        pin.lb = done_[q] ? at_[q] : t;
        pin.ub = pin.lb;
      } else if (Kind(q) == PointKind::kContingent) {
        continue;  // its own link bounds it
      } else {
        pin.lb = t;
      }
      net.links.push_back(pin);
    }
    return net;
  }

  bool Controllable(int p, Ticks t) const {
    return network::IsDynamicallyControllable(Remainder(p, t));
  }

  // The next moment something may happen: a contingent outcome, a planned start (fixed), or the
  // earliest time any waiting point could start in what remains (dynamic).
  Ticks Next(Ticks t) const {
    Ticks soonest = network::kInfinity;
    for (std::size_t p = 1; p < n_; ++p)
      if (!done_[p] && due_[p] && *due_[p] > t) soonest = std::min(soonest, *due_[p]);
    if (!o_.dynamic) {
      for (std::size_t p = 1; p < n_; ++p)
        if (!done_[p] && Kind(p) != PointKind::kContingent) soonest = std::min(soonest, planned_[p]);
    } else if (auto w = Windows(Remainder(-1, t))) {
      for (std::size_t p = 1; p < n_; ++p)
        if (!done_[p] && Kind(p) != PointKind::kContingent)
          soonest = std::min(soonest, (*w)[p].earliest);
    }
    if (soonest >= network::kInfinity) return t + step_;
    return std::max(t + step_, (soonest + step_ - 1) / step_ * step_);
  }

  bool Holds(std::string& why) const {
    for (std::size_t i = 0; i < f_.net.links.size(); ++i) {
      const Link& l = f_.net.links[i];
      const Ticks dt = at_[l.to] - at_[l.from];
      if (dt < l.lb || (l.ub && dt > *l.ub)) {
        why = "link " + std::to_string(i) + " (" + l.why + ") broken: " +
              std::to_string(network::SecondsFromTicks(dt)) + " s apart";
        return false;
      }
    }
    return true;
  }

  const FlexiblePlan& f_;
  const Domain& d_;
  const std::vector<Ticks>& planned_;
  const DispatchOptions& o_;
  std::mt19937& rng_;
  const std::size_t n_;
  const Ticks step_;
  std::vector<bool> done_;
  std::vector<Ticks> at_;
  std::vector<std::optional<Ticks>> due_;
  std::map<int, int> contingent_of_;  // contingent point -> its link
};

}  // namespace

Execution Execute(const FlexiblePlan& f, const Domain& d, const std::vector<Ticks>& planned,
                  const DispatchOptions& o, std::mt19937& rng) {
  return Dispatcher(f, d, planned, o, rng).Run();
}

}  // namespace ctb::flexible
