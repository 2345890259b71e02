// The built-in simulated team (sim.h).
#include "executive/sim.h"

#include <algorithm>
#include <cmath>

namespace ctb::exec {

Json SimOptions::ToJson() const {
  return {{"fail", fail}, {"late", late}, {"late_by", late_by}, {"seed", seed}};
}

std::optional<SimOptions> ParseSimOptions(const Json& j, const std::string& prefix, Diagnostics& diags) {
  SimOptions o;
  if (j.is_null()) return o;
  if (!j.is_object()) {
    diags.Error(prefix, "must be an object {\"fail\", \"late\", \"late_by\", \"seed\"}");
    return std::nullopt;
  }
  const std::size_t before = diags.errors().size();
  for (const auto& [k, v] : j.items()) {
    const std::string at = prefix + "/" + k;
    const bool number = v.is_number() && std::isfinite(v.get<double>());
    if (k == "fail" || k == "late") {
      if (!number || v.get<double>() < 0 || v.get<double>() > 1) diags.Error(at, "must be a chance in [0, 1]");
      else (k == "fail" ? o.fail : o.late) = v.get<double>();
    } else if (k == "late_by") {
      if (!number || v.get<double>() < 0 || v.get<double>() > 86400) diags.Error(at, "must be seconds in [0, 86400]");
      else o.late_by = v.get<double>();
    } else if (k == "seed") {
      if (!v.is_number_unsigned() || v.get<unsigned long>() > 0xffffffffUL) diags.Error(at, "must be a whole number in [0, 2^32)");
      else o.seed = v.get<unsigned>();
    } else {
      diags.Error(at, "unknown field (sim has fail, late, late_by, seed)");
    }
  }
  if (diags.errors().size() > before) return std::nullopt;
  return o;
}

double SimTeam::Grid(double t) const { return std::round(t / res_) * res_; }

std::vector<SimTeam::Pending> SimTeam::Pend(const Run& run) {
  std::vector<Pending> out;
  const auto points = run.Points();
  const auto windows = run.WindowsAt(0);  // given what happened, not yet the present
  for (std::size_t q = 1; q < points.size(); ++q) {
    const Run::PointView& p = points[q];
    if (p.at) continue;
    const std::string base = p.automaton + "|" + p.from + "|" + p.to + "|";
    if (!p.command.empty()) {
      if (!p.sent) continue;
      const std::string key = base + std::to_string(*p.sent);
      if (!decided_.count(key)) {
        Report r{p.automaton, p.to, std::nullopt, *p.sent};
        if (std::uniform_real_distribution<double>(0, 1)(rng_) < o_.fail) r = {p.automaton, std::nullopt, p.command, *p.sent};
        decided_[key] = r;
      }
      out.push_back({*p.sent, decided_[key]});
    } else if (p.contingent) {
      const auto& from = points[p.activation];
      if (!from.at) continue;
      const std::string key = base + std::to_string(*from.at);
      if (!decided_.count(key)) {
        double d;
        if (std::uniform_real_distribution<double>(0, 1)(rng_) < o_.late) {
          d = p.ub + (o_.late_by > 0 ? o_.late_by : p.ub - p.lb + res_);
        } else {
          const long steps = std::lround((p.ub - p.lb) / res_);
          d = p.lb + res_ * static_cast<double>(std::uniform_int_distribution<long>(0, steps)(rng_));
        }
        decided_[key] = Report{p.automaton, p.to, std::nullopt, Grid(*from.at + d)};
      }
      out.push_back({decided_[key].time, decided_[key]});
    } else if (p.ready && windows) {
      const double at = Grid((*windows)[q].earliest);
      out.push_back({at, Report{p.automaton, p.to, std::nullopt, at}});
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const Pending& a, const Pending& b) { return a.at < b.at; });
  return out;
}

std::vector<Report> SimTeam::Due(const Run& run, double now) {
  std::vector<Report> out;
  for (const auto& p : Pend(run)) {
    if (p.at > now + 1e-9) continue;
    const std::string key = p.report.ToJson().dump();
    if (given_.insert(key).second) out.push_back(p.report);
  }
  return out;
}

std::optional<double> SimTeam::NextDue(const Run& run, double now) {
  std::optional<double> next;
  for (const auto& p : Pend(run)) {
    if (given_.count(p.report.ToJson().dump())) continue;
    const double at = std::max(p.at, now);  // one that became due by what was just applied: now
    next = next ? std::min(*next, at) : at;
  }
  return next;
}

}  // namespace ctb::exec
