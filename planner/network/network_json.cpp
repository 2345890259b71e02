#include "planner/network/network_json.h"

#include <unordered_map>

#include "planner/model/expr_check.h"

namespace ctb::network {
namespace {

using NameIndex = std::unordered_map<std::string, int>;

std::optional<std::vector<std::string>> ParsePoints(const Json& points, NameIndex& index,
                                                    Diagnostics& diags) {
  if (!points.is_array()) {
    diags.Error("/points",
                std::string("expected an array of point names, got ") + JsonTypeName(points));
    return std::nullopt;
  }
  std::vector<std::string> names;
  names.reserve(points.size());
  bool ok = true;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string ptr = "/points/" + std::to_string(i);
    const Json& p = points[i];
    if (!p.is_string() || p.get_ref<const std::string&>().empty()) {
      diags.Error(ptr, "expected a non-empty point name, got " +
                           std::string(p.is_string() ? "\"\"" : JsonTypeName(p)));
      ok = false;
      names.emplace_back();
      continue;
    }
    const std::string& name = p.get_ref<const std::string&>();
    auto [it, fresh] = index.emplace(name, static_cast<int>(i));
    if (!fresh) {
      diags.Error(ptr, "duplicate point name '" + name + "' (first at /points/" +
                           std::to_string(it->second) + ")");
      ok = false;
    }
    names.push_back(name);
  }
  if (!ok) return std::nullopt;
  return names;
}

std::optional<int> PointRef(const ObjectReader& r, const std::string& key, const NameIndex& index,
                            const std::vector<std::string>& names, Diagnostics& diags) {
  std::optional<std::string> name = r.String(key, true);
  if (!name) return std::nullopt;
  auto it = index.find(*name);
  if (it != index.end()) return it->second;
  const std::string best = NearestName(*name, names);
  diags.Error(r.Child(key), "unknown point '" + *name + "'" +
                                (best.empty() ? "" : " (did you mean '" + best + "'?)"));
  return std::nullopt;
}

// A bound in seconds: a finite number, a whole number of milliseconds, |x| <= kMaxAbsSeconds.
std::optional<Ticks> Bound(const Json& j, const std::string& ptr, Diagnostics& diags) {
  if (!j.is_number()) {
    diags.Error(ptr, std::string("expected a number of seconds, got ") + JsonTypeName(j));
    return std::nullopt;
  }
  std::optional<Ticks> t = TicksFromSeconds(j.get<double>());
  if (!t) {
    diags.Error(ptr,
                "expected a finite number of seconds within +-1e9 and a "
                "whole number of "
                "milliseconds, got " +
                    j.dump());
  }
  return t;
}

std::optional<Link> ParseLink(const Json& j, std::size_t i, const NameIndex& index,
                              const std::vector<std::string>& names, Diagnostics& diags) {
  const std::size_t before = diags.errors().size();
  ObjectReader r(j, "/links/" + std::to_string(i), diags);
  if (!r.valid()) return std::nullopt;
  r.CheckKeys({"from", "to", "lb", "ub", "contingent", "why"});
  Link l;
  const std::optional<int> from = PointRef(r, "from", index, names, diags);
  const std::optional<int> to = PointRef(r, "to", index, names, diags);
  std::optional<Ticks> lb;
  if (const Json* v = r.Get("lb")) {
    lb = Bound(*v, r.Child("lb"), diags);
  } else {
    diags.Error(r.Child("lb"), "missing required field");
  }
  if (const Json* v = r.Get("ub"); v && !v->is_null()) l.ub = Bound(*v, r.Child("ub"), diags);
  l.contingent = r.Bool("contingent", false).value_or(false);
  l.why = r.String("why", false).value_or("");
  if (diags.errors().size() != before || !from || !to || !lb) return std::nullopt;
  l.from = *from;
  l.to = *to;
  l.lb = *lb;
  CheckLinkBounds(l, r.pointer(), diags);
  if (diags.errors().size() != before) return std::nullopt;
  return l;
}

}  // namespace

std::optional<Network> ParseCheckBody(const Json& body, Diagnostics& diags) {
  ObjectReader r(body, "", diags);
  if (!r.valid()) return std::nullopt;
  r.CheckKeys({"points", "links"});
  const Json* points = r.Get("points");
  const Json* links = r.Get("links");
  if (!points) diags.Error("/points", "missing required field");
  if (!links) diags.Error("/links", "missing required field");
  if (links && !links->is_array()) {
    diags.Error("/links", std::string("expected an array of links, got ") + JsonTypeName(*links));
  }
  NameIndex index;
  std::optional<std::vector<std::string>> names;
  if (points) names = ParsePoints(*points, index, diags);
  if (!names || !links || !links->is_array()) return std::nullopt;
  Network net;
  net.points.resize(names->size());
  for (std::size_t i = 0; i < names->size(); ++i) {
    net.points[i] = {static_cast<int>(i), (*names)[i], PointKind::kControllable, {}};
  }
  net.links.reserve(links->size());
  for (std::size_t i = 0; i < links->size(); ++i) {
    std::optional<Link> l = ParseLink((*links)[i], i, index, *names, diags);
    if (l) net.links.push_back(std::move(*l));
  }
  if (!diags.ok()) return std::nullopt;
  for (const Link& l : net.links) {
    if (l.contingent) net.points[static_cast<std::size_t>(l.to)].kind = PointKind::kContingent;
  }
  if (!Validate(net, diags)) return std::nullopt;
  return net;
}

Json CheckResultToJson(const CheckResult& r) {
  Json j = {{"consistent", r.consistent}, {"strong", r.strong}, {"dynamic", r.dynamic}};
  if (!r.dynamic) j["conflict"] = r.conflict;
  j["ms"] = r.ms;
  return j;
}

Json NetworkToJson(const Network& net) {
  Json points = Json::array();
  for (const Point& p : net.points) {
    Json jp = {{"id", p.id}, {"kind", PointKindName(p.kind)}};
    if (!p.name.empty()) jp["name"] = p.name;
    for (const auto& [k, v] : p.labels) jp[k] = v;
    points.push_back(std::move(jp));
  }
  Json links = Json::array();
  for (const Link& l : net.links) {
    Json jl = {{"from", l.from}, {"to", l.to}, {"lb", SecondsFromTicks(l.lb)}};
    jl["ub"] = l.ub ? Json(SecondsFromTicks(*l.ub)) : Json(nullptr);
    jl["kind"] = l.contingent ? "contingent" : "requirement";
    jl["why"] = l.why;
    links.push_back(std::move(jl));
  }
  return {{"points", std::move(points)}, {"links", std::move(links)}};
}

}  // namespace ctb::network
