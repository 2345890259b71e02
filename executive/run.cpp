// The executive's decisions for one execution (run.h).
#include "executive/run.h"

#include <algorithm>
#include <cmath>

namespace ctb::exec {

namespace {

using network::Link;
using network::Network;
using network::PointKind;
using network::Ticks;

Ticks ToTicks(double seconds) { return std::llround(seconds * network::kTicksPerSecond); }
double ToSeconds(Ticks t) { return static_cast<double>(t) / network::kTicksPerSecond; }

Error Internal(const std::string& what) { return {ErrorCode::kInternal, "execution: " + what, {}}; }

// The answer's `network` (network::NetworkToJson's form) back into a Network.
std::optional<Network> ReadNetwork(const Json& j, std::string& why) {
  if (!j.is_object() || !j.contains("points") || !j["points"].is_array() || !j.contains("links") ||
      !j["links"].is_array())
    return (why = "the plan has no network"), std::nullopt;
  Network net;
  for (const auto& p : j["points"]) {
    network::Point pt;
    pt.id = static_cast<int>(net.points.size());
    const std::string kind = p.value("kind", "");
    pt.kind = kind == "origin" ? PointKind::kOrigin
              : kind == "contingent" ? PointKind::kContingent
                                     : PointKind::kControllable;
    net.points.push_back(pt);
  }
  const int n = static_cast<int>(net.points.size());
  for (const auto& l : j["links"]) {
    Link link;
    link.from = l.value("from", -1);
    link.to = l.value("to", -1);
    if (link.from < 0 || link.to < 0 || link.from >= n || link.to >= n || !l.contains("lb") ||
        !l["lb"].is_number())
      return (why = "a link of the plan's network is malformed"), std::nullopt;
    link.lb = ToTicks(l["lb"].get<double>());
    if (l.contains("ub") && l["ub"].is_number()) link.ub = ToTicks(l["ub"].get<double>());
    link.contingent = l.value("kind", "") == "contingent";
    net.links.push_back(link);
  }
  return net;
}

const Transition* FindTransition(const Automaton& a, int from, int to) {
  for (const auto& t : a.transitions)
    if (t.from == from && t.to == to) return &t;
  return nullptr;
}

std::string CommandName(const Automaton& a, const Transition& t) {
  return t.commanded && t.command > 0 ? a.commands[t.command - 1] : "";
}

}  // namespace

const char* StateName(State s) {
  switch (s) {
    case State::kRunning: return "running";
    case State::kSucceeded: return "succeeded";
    case State::kFailed: return "failed";
    case State::kStopped: return "stopped";
  }
  return "?";
}

std::optional<State> ParseState(const std::string& s) {
  for (State x : {State::kRunning, State::kSucceeded, State::kFailed, State::kStopped})
    if (s == StateName(x)) return x;
  return std::nullopt;
}

Json Command::ToJson() const {
  return {{"automaton", automaton}, {"command", command}, {"from", from}, {"to", to}, {"at", at}};
}

Json Report::ToJson() const {
  Json j = {{"automaton", automaton}, {"time", time}};
  if (location) j["location"] = *location;
  if (failed) j["failed"] = *failed;
  return j;
}

std::optional<Report> ParseReport(const Json& j, const std::string& prefix, Diagnostics& diags) {
  if (!j.is_object()) {
    diags.Error(prefix.empty() ? "/" : prefix, "a report is an object {\"automaton\", \"location\" "
                                               "or \"failed\", \"time\"}");
    return std::nullopt;
  }
  Report r;
  const std::size_t before = diags.errors().size();
  for (const auto& [k, v] : j.items()) {
    const std::string at = prefix + "/" + k;
    if (k == "automaton" || k == "location" || k == "failed") {
      if (!v.is_string() || v.get<std::string>().empty()) {
        diags.Error(at, "must be a non-empty string");
        continue;
      }
      if (k == "automaton") r.automaton = v.get<std::string>();
      if (k == "location") r.location = v.get<std::string>();
      if (k == "failed") r.failed = v.get<std::string>();
    } else if (k == "time") {
      if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0)
        diags.Error(at, "must be a number of seconds >= 0");
      else
        r.time = v.get<double>();
    } else {
      diags.Error(at, "unknown field (a report has automaton, location or failed, and time)");
    }
  }
  if (!j.contains("automaton")) diags.Error(prefix + "/automaton", "missing");
  if (!j.contains("time")) diags.Error(prefix + "/time", "missing");
  if (j.contains("location") == j.contains("failed"))
    diags.Error(prefix + "/location", "give either \"location\" (a transition done) or \"failed\" "
                                      "(a command that cannot be carried out)");
  if (diags.errors().size() > before) return std::nullopt;
  return r;
}

std::optional<Error> Run::ReadPlan(const Json& plan) {
  std::string why;
  auto net = ReadNetwork(plan.value("network", Json()), why);
  if (!net) return Internal(why);
  if (!plan.contains("transitions") || !plan["transitions"].is_array())
    return Internal("the plan has no transitions");
  std::vector<Point> points(1);  // the origin
  for (const auto& t : plan["transitions"]) {
    if (t.value("observed", false)) continue;  // a jump no transition explains: not a point
    Point p;
    p.automaton = d_->AutomatonIndex(t.value("automaton", ""));
    if (p.automaton < 0) return Internal("the plan names an automaton the domain lacks");
    const Automaton& a = d_->automata[p.automaton];
    p.from = a.LocationIndex(t.value("from", ""));
    p.to = a.LocationIndex(t.value("to", ""));
    if (p.from < 0 || p.to < 0) return Internal("the plan names a location the domain lacks");
    // A command is sent for a transition the domain commands; the trajectory's `command` is
    // the automaton's command at that event, which an automatic transition may share.
    if (t.contains("command") && t["command"].is_string()) {
      for (const auto& tr : a.transitions)
        if (tr.from == p.from && tr.to == p.to && CommandName(a, tr) == t["command"].get<std::string>())
          p.command = t["command"];
    }
    if (t.value("executed", false) && t.contains("time") && t["time"].is_number())
      p.at = ToTicks(t["time"].get<double>());
    points.push_back(p);
  }
  if (points.size() != net->points.size())
    return Internal("the plan's network has " + std::to_string(net->points.size()) +
                    " points for " + std::to_string(points.size()) + " transitions");
  if (!flexible::Windows(*net)) return Internal("the plan's network is inconsistent");
  net_ = std::move(*net);
  points_ = std::move(points);
  points_[0].at = 0;
  return std::nullopt;
}

std::optional<Error> Run::Adopt(const Json& plan, double now) {
  (void)now;
  if (auto e = ReadPlan(plan)) return e;
  if (location_.empty()) {  // the first plan: where everything starts
    const Json tl = plan.value("timelines", Json::object());
    for (const auto& a : d_->automata) {
      const Json& line = tl.contains(a.name) ? tl[a.name] : Json();
      const int l = line.is_array() && !line.empty() ? a.LocationIndex(line[0].value("location", "")) : -1;
      if (l < 0) return Internal("the plan has no timeline for " + a.name);
      location_.push_back(l);
      entered_.push_back(0);
    }
  }
  plan_ = plan;
  floor_ = plan.contains("now") && plan["now"].is_number() ? ToTicks(plan["now"].get<double>()) : 0;
  return std::nullopt;
}

bool Run::Replay(std::size_t from) {
  for (std::size_t k = from; k < history_.size(); ++k) {
    const Json& h = history_[k];
    const int ai = d_->AutomatonIndex(h.value("automaton", ""));
    if (ai < 0) return false;
    const Automaton& a = d_->automata[ai];
    const int q = NextPointOf(ai);
    if (q < 0 || points_[q].from != a.LocationIndex(h.value("from", "")) ||
        points_[q].to != a.LocationIndex(h.value("to", "")))
      return false;
    points_[q].at = ToTicks(h["time"].get<double>());
  }
  return true;
}

Ticks Run::OnGrid(double now_s) const {
  const Ticks step = std::max<Ticks>(1, ToTicks(d_->time_resolution));
  const Ticks now = ToTicks(now_s);
  return now / step * step;
}

Network Run::Remainder(Ticks now) const {
  Network net = net_;
  for (std::size_t q = 1; q < points_.size(); ++q) {
    const Point& p = points_[q];
    Link pin;
    pin.to = static_cast<int>(q);
    if (p.at || p.sent) {
      pin.lb = p.at ? *p.at : *p.sent;
      pin.ub = pin.lb;
    } else {
      // Not happened yet: not before now (a device's report may lag by the grace), nor before
      // the replan that made the plan (its future starts there).
      pin.lb = std::max(floor_, p.command.empty() ? now - grace_ : now);
    }
    net.links.push_back(pin);
  }
  for (auto& l : net.links) l.contingent = false;  // windows read every link as a requirement
  return net;
}

int Run::NextPointOf(int automaton) const {
  for (std::size_t q = 1; q < points_.size(); ++q)
    if (points_[q].automaton == automaton && !points_[q].at) return static_cast<int>(q);
  return -1;
}

bool Run::AllHappened() const {
  return std::all_of(points_.begin(), points_.end(), [](const Point& p) { return p.at.has_value(); });
}

// A command goes out once what its guard reads has been reported: every point ordered before it
// has happened. A point tied to it ([0, 0], one event) that moves on its own (a door that a
// robot's command swings) happens with it, after it, so it does not hold it back.
bool Run::Ready(int q) const {
  for (const auto& l : net_.links) {
    if (l.to != q || l.lb < 0 || points_[l.from].at) continue;
    const bool tie = l.lb == 0 && l.ub && *l.ub == 0;
    if (!(tie && (points_[l.from].command.empty() || points_[l.from].sent))) return false;
  }
  return true;
}

// A device moves on its own once every point ordered before it has happened, and the commands
// it is tied to have been reported done (a door does not swing for a command that failed).
bool Run::DeviceReady(int q) const {
  for (const auto& l : net_.links) {
    const bool tie = l.lb == 0 && l.ub && *l.ub == 0;
    if (l.to == q && l.lb >= 0 && !points_[l.from].at) return false;
    if (tie && l.from == q && !points_[l.to].command.empty() && !points_[l.to].at) return false;
  }
  return true;
}

std::string Run::Describe(int q) const {
  const Point& p = points_[q];
  const Automaton& a = d_->automata[p.automaton];
  return a.name + " " + a.locations[p.from] + "->" + a.locations[p.to];
}

// Each point's window given what has happened (not yet the present).
std::optional<std::vector<flexible::Window>> Run::HappenedWindows() const {
  return flexible::Windows(Remainder(-network::kInfinity / 4));
}

std::string Run::WhyInconsistent(Ticks now) const {
  auto w = HappenedWindows();
  for (std::size_t q = 1; w && q < points_.size(); ++q) {
    const Point& p = points_[q];
    if (p.at || p.sent || !(*w)[q].latest) continue;
    if (*(*w)[q].latest < now - grace_)
      return Describe(static_cast<int>(q)) + " is overdue: due by " +
             Json(ToSeconds(*(*w)[q].latest)).dump() + " s";
  }
  return "what happened leaves no schedule for the rest of the plan";
}

Decision Run::Advance(double now_s) {
  Decision d;
  if (state_ != State::kRunning) return d;
  // Decisions on the domain's grid, where the plan's bounds are: every time set stays on it.
  const Ticks now = OnGrid(now_s);
  for (bool changed = true; changed;) {
    changed = false;
    if (AllHappened()) {
      d.finished = true;
      Finish(State::kSucceeded);
      return d;
    }
    auto w = flexible::Windows(Remainder(now));
    if (!w) {
      d.replan = WhyInconsistent(now);
      return d;
    }
    for (std::size_t q = 1; q < points_.size() && !changed; ++q) {
      Point& p = points_[q];
      if (p.at || p.sent || p.command.empty() || !Ready(static_cast<int>(q))) continue;
      if ((*w)[q].earliest > now) continue;
      p.sent = std::max((*w)[q].earliest, now);
      const Automaton& a = d_->automata[p.automaton];
      d.dispatch.push_back({a.name, p.command, a.locations[p.from], a.locations[p.to], ToSeconds(*p.sent)});
      changed = true;
    }
  }
  return d;
}

std::optional<double> Run::NextWake(double now_s) const {
  if (state_ != State::kRunning) return std::nullopt;
  const Ticks now = OnGrid(now_s);
  auto w = flexible::Windows(Remainder(now));
  if (!w) return now_s;
  Ticks soonest = network::kInfinity;
  for (std::size_t q = 1; q < points_.size(); ++q) {
    const Point& p = points_[q];
    if (p.at) continue;
    if (!p.sent && !p.command.empty() && (*w)[q].earliest > now) soonest = std::min(soonest, (*w)[q].earliest);
    // Overdue once its latest time (and the grace) has passed without a report.
    const Ticks step = std::max<Ticks>(1, ToTicks(d_->time_resolution));
    if ((*w)[q].latest) soonest = std::min(soonest, std::max(now, *(*w)[q].latest) + grace_ + step);
  }
  if (soonest >= network::kInfinity) return std::nullopt;
  return ToSeconds(soonest);
}

std::variant<Applied, Error> Run::Apply(const Report& r, double now_s, const std::string& prefix) {
  Applied out;
  if (std::find(reports_.begin(), reports_.end(), r) != reports_.end()) {
    out.duplicate = true;
    return out;
  }
  Diagnostics diags;
  const int ai = d_->AutomatonIndex(r.automaton);
  const Ticks t = ToTicks(r.time);
  if (ai < 0) {
    diags.Error(prefix + "/automaton", "unknown automaton '" + Echo(r.automaton) + "'");
    return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid report", diags);
  }
  const Automaton& a = d_->automata[ai];
  const std::string here = a.locations[location_[ai]];
  if (state_ != State::kRunning) diags.Error(prefix.empty() ? "/" : prefix, "the execution is " + std::string(StateName(state_)));
  const Transition* tr = nullptr;
  int to = -1;
  if (r.location) {
    to = a.LocationIndex(*r.location);
    if (to < 0)
      diags.Error(prefix + "/location", a.name + " has no location '" + Echo(*r.location) + "'");
    else if (!(tr = FindTransition(a, location_[ai], to)))
      diags.Error(prefix + "/location", a.name + " is at " + here + " and has no transition to " +
                                            *r.location);
  } else {
    for (const auto& x : a.transitions)
      if (x.from == location_[ai] && CommandName(a, x) == *r.failed) tr = &x;
    if (!tr)
      diags.Error(prefix + "/failed", a.name + " is at " + here + " and has no command '" +
                                          Echo(*r.failed) + "' there");
  }
  // What was reported before when: a device that names a place it cannot be has that error first.
  if (t > ToTicks(now_s) + grace_)
    diags.Error(prefix + "/time", "after now (" + Json(now_s).dump() + " s): a report tells what happened");
  else if (t < entered_[ai])
    diags.Error(prefix + "/time", "before " + a.name + "'s last transition, at " +
                                      Json(ToSeconds(entered_[ai])).dump() + " s");
  if (!diags.ok()) return Error::FromDiagnostics(ErrorCode::kInvalidInput, "invalid report", diags);
  reports_.push_back(r);
  if (r.failed) {
    blocked_.push_back({{"automaton", a.name}, {"from", here}, {"to", a.locations[tr->to]}});
    out.replan = a.name + " cannot " + *r.failed + " at " + here;
    return out;
  }
  Json entry = {{"time", r.time}, {"automaton", a.name}, {"from", here}, {"to", *r.location}};
  if (const std::string c = CommandName(a, *tr); !c.empty()) entry["command"] = c;
  history_.push_back(entry);
  const int from = location_[ai];
  location_[ai] = to;
  entered_[ai] = t;
  const int q = NextPointOf(ai);
  if (q < 0 || points_[q].from != from || points_[q].to != to) {
    out.replan = a.name + " moved " + here + "->" + *r.location + ", which the plan did not have next";
    return out;
  }
  // Inside what the network absorbs: its window given what happened before it. A report a little
  // off (within the grace: a device's clock, the transport) counts at the nearest time inside the
  // window, so that jitter on an exact duration does not break the schedule; the history keeps
  // the time reported.
  const auto windows = HappenedWindows();
  points_[q].at = t;
  if (!windows) return out;  // already inconsistent: Advance replans
  const auto& win = (*windows)[q];
  if (t < win.earliest - grace_ || (win.latest && t > *win.latest + grace_)) {
    out.replan = Describe(q) + " happened at " + Json(r.time).dump() + " s, outside its window [" +
                 Json(ToSeconds(win.earliest)).dump() + ", " +
                 (win.latest ? Json(ToSeconds(*win.latest)).dump() : std::string("inf")) + "]";
    return out;
  }
  points_[q].at = std::max(win.earliest, win.latest ? std::min(t, *win.latest) : t);
  return out;
}

Json Run::ReplanRequest(double now_s) const {
  double now = now_s;
  for (const auto& h : history_) now = std::max(now, h["time"].get<double>());
  const double res = d_->time_resolution;
  now = std::ceil(now / res - 1e-9) * res;
  Json req = {{"now", now}, {"executed", history_}, {"trajectory", plan_}};
  if (!blocked_.empty()) req["blocked"] = blocked_;
  return req;
}

std::vector<Run::PointView> Run::Points() const {
  std::vector<PointView> out(points_.size());
  for (std::size_t q = 1; q < points_.size(); ++q) {
    const Point& p = points_[q];
    const Automaton& a = d_->automata[p.automaton];
    PointView& v = out[q];
    v.automaton = a.name;
    v.from = a.locations[p.from];
    v.to = a.locations[p.to];
    v.command = p.command;
    v.ready = p.command.empty() ? DeviceReady(static_cast<int>(q)) : Ready(static_cast<int>(q));
    if (p.at) v.at = ToSeconds(*p.at);
    if (p.sent) v.sent = ToSeconds(*p.sent);
  }
  out[0].at = 0;
  for (const auto& l : net_.links) {
    if (!l.contingent) continue;
    PointView& v = out[l.to];
    v.contingent = true;
    v.activation = l.from;
    v.lb = ToSeconds(l.lb);
    v.ub = ToSeconds(l.ub.value_or(l.lb));
  }
  return out;
}

std::optional<std::vector<Run::WindowView>> Run::WindowsAt(double now) const {
  auto w = flexible::Windows(Remainder(ToTicks(now)));
  if (!w) return std::nullopt;
  std::vector<WindowView> out;
  for (const auto& x : *w) {
    WindowView v;
    v.earliest = ToSeconds(x.earliest);
    if (x.latest) v.latest = ToSeconds(*x.latest);
    out.push_back(v);
  }
  return out;
}

void Run::Finish(State s, std::string why) {
  state_ = s;
  why_ = std::move(why);
}

Json Run::ToJson() const {
  Json points = Json::array();
  for (const auto& p : points_) {
    Json j = Json::object();
    if (p.at) j["at"] = *p.at;
    if (p.sent) j["sent"] = *p.sent;
    points.push_back(j);
  }
  Json reports = Json::array();
  for (const auto& r : reports_) reports.push_back(r.ToJson());
  Json locations = Json::array();
  for (std::size_t a = 0; a < location_.size(); ++a)
    locations.push_back({{"location", d_->automata[a].locations[location_[a]]}, {"since", entered_[a]}});
  return {{"state", StateName(state_)}, {"why", why_}, {"plan", plan_}, {"history", history_},
          {"blocked", blocked_}, {"reports", reports}, {"points", points},
          {"locations", locations}, {"grace", grace_}, {"floor", floor_}};
}

std::optional<Error> Run::FromJson(const Json& j) {
  if (!j.is_object()) return Internal("the stored run is not an object");
  auto s = ParseState(j.value("state", ""));
  if (!s) return Internal("the stored run has no state");
  if (auto e = ReadPlan(j.value("plan", Json()))) return e;
  const Json& pts = j.value("points", Json());
  const Json& locs = j.value("locations", Json());
  if (!pts.is_array() || pts.size() != points_.size() || !locs.is_array() ||
      locs.size() != d_->automata.size())
    return Internal("the stored run does not match its plan or domain");
  for (std::size_t q = 0; q < points_.size(); ++q) {
    if (pts[q].contains("at")) points_[q].at = pts[q]["at"].get<Ticks>();
    if (pts[q].contains("sent")) points_[q].sent = pts[q]["sent"].get<Ticks>();
  }
  location_.clear();
  entered_.clear();
  for (std::size_t a = 0; a < locs.size(); ++a) {
    const int l = d_->automata[a].LocationIndex(locs[a].value("location", ""));
    if (l < 0) return Internal("the stored run names a location the domain lacks");
    location_.push_back(l);
    entered_.push_back(locs[a].value("since", Ticks{0}));
  }
  for (const auto& r : j.value("reports", Json::array())) {
    Diagnostics diags;
    auto rep = ParseReport(r, "", diags);
    if (!rep) return Internal("a stored report is malformed");
    reports_.push_back(*rep);
  }
  state_ = *s;
  why_ = j.value("why", "");
  plan_ = j["plan"];
  history_ = j.value("history", Json::array());
  blocked_ = j.value("blocked", Json::array());
  grace_ = j.value("grace", grace_);
  floor_ = j.value("floor", floor_);
  return std::nullopt;
}

}  // namespace ctb::exec
