#include "planner/diagram/diagram.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <vector>

#include "planner/expr/expr_print.h"

namespace ctb {

namespace {

constexpr double kCharWidth = 7.2;  // 12px sans-serif, roughly
constexpr double kBoxHeight = 30;
constexpr double kRowGap = 34;
constexpr double kColumnGap = 190;  // room for edge labels between columns
constexpr double kMargin = 20;
constexpr double kHeader = 72;  // title, commands, and room for the labels of upward bends

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        // Control characters are not allowed in XML 1.0 text.
        if (static_cast<unsigned char>(c) >= 0x20 || c == '\t' || c == '\n') out += c;
    }
  }
  return out;
}

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

std::string Seconds(double s) {
  if (s == std::floor(s) && std::fabs(s) < 1e12) return std::to_string(static_cast<long long>(s));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", s);
  return buf;
}

std::string Unwrap(std::string s) {
  if (s.size() >= 2 && s.front() == '(' && s.back() == ')') {
    int level = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (s[i] == '(') ++level;
      if (s[i] == ')' && --level == 0 && i + 1 < s.size()) return s;  // "(a) /\ (b)"
    }
    return s.substr(1, s.size() - 2);
  }
  return s;
}

void Conjuncts(const Expr& e, std::vector<const Expr*>& out) {
  if (e.op == Expr::Op::kAnd) {
    Conjuncts(e.kids[0], out);
    Conjuncts(e.kids[1], out);
  } else {
    out.push_back(&e);
  }
}

std::string Cut(const std::string& s, std::size_t n) {
  if (s.size() <= n) return s;
  std::size_t k = n > 3 ? n - 3 : n;
  while (k > 0 && (static_cast<unsigned char>(s[k]) & 0xC0) == 0x80) --k;  // UTF-8 boundary
  return s.substr(0, k) + "...";
}

struct Box {
  double x = 0, y = 0, w = 0;
};

// Where the segment from a box's centre towards (tx, ty) leaves the box.
void Exit(const Box& b, double tx, double ty, double& ox, double& oy) {
  double cx = b.x + b.w / 2, cy = b.y + kBoxHeight / 2;
  double dx = tx - cx, dy = ty - cy;
  if (dx == 0 && dy == 0) {
    ox = cx;
    oy = cy;
    return;
  }
  double sx = dx != 0 ? (b.w / 2) / std::fabs(dx) : 1e18;
  double sy = dy != 0 ? (kBoxHeight / 2) / std::fabs(dy) : 1e18;
  double s = std::min(sx, sy);
  ox = cx + dx * s;
  oy = cy + dy * s;
}

// The panel of one automaton, drawn at vertical offset top; returns its height and width.
void Panel(const Domain& d, const Automaton& a, double top, const DiagramOptions& o,
           std::string& svg, double& height, double& width) {
  const int n = static_cast<int>(a.locations.size());
  // Columns by BFS depth from the first location; unreached locations in a last column.
  std::vector<int> depth(n, -1);
  std::deque<int> queue;
  if (n > 0) {
    depth[0] = 0;
    queue.push_back(0);
  }
  while (!queue.empty()) {
    int u = queue.front();
    queue.pop_front();
    for (const auto& t : a.transitions)
      if (t.from == u && depth[t.to] < 0) {
        depth[t.to] = depth[u] + 1;
        queue.push_back(t.to);
      }
  }
  int columns = 0;
  for (int v : depth) columns = std::max(columns, v + 1);
  for (int& v : depth)
    if (v < 0) v = columns;
  if (std::count(depth.begin(), depth.end(), columns) > 0) ++columns;
  std::vector<std::vector<int>> col(columns);
  for (int i = 0; i < n; ++i) col[depth[i]].push_back(i);
  std::vector<Box> box(n);
  double x = kMargin;
  std::size_t rows = 1;
  for (const auto& c : col) {
    double w = 0;
    for (int i : c) w = std::max(w, a.locations[i].size() * kCharWidth + 20);
    for (std::size_t r = 0; r < c.size(); ++r)
      box[c[r]] = {x, top + kHeader + r * (kBoxHeight + kRowGap), w};
    rows = std::max(rows, c.size());
    x += w + kColumnGap;
  }
  width = std::max(x - kColumnGap + kMargin, 320.0);
  const double bottom = top + kHeader + rows * (kBoxHeight + kRowGap) - kRowGap;
  bool any_back = false, any_side = false;
  for (const auto& t : a.transitions) {
    any_back |= depth[t.to] < depth[t.from];
    any_side |= depth[t.to] == depth[t.from];
  }
  height = kHeader + rows * (kBoxHeight + kRowGap) + kMargin + (any_back ? 50 : 0);
  if (any_side) width += 120;
  int back = 0, side = 0;

  std::string title = "automaton " + a.name;
  std::string sub = a.commands.empty() ? "no commands" : "commands:";
  for (std::size_t i = 0; i < a.commands.size(); ++i) sub += (i ? ", " : " ") + a.commands[i];
  svg += "<g class=\"automaton\" id=\"automaton-" + Escape(a.name) + "\">\n";
  svg += "<rect x=\"4\" y=\"" + Num(top + 4) + "\" width=\"" + Num(width - 8) + "\" height=\"" +
         Num(height - 8) + "\" rx=\"8\" fill=\"#fafafa\" stroke=\"#bbb\"/>\n";
  svg += "<text x=\"" + Num(kMargin) + "\" y=\"" + Num(top + 24) +
         "\" font-weight=\"bold\" font-size=\"14\">" + Escape(title) + "</text>\n";
  svg += "<text x=\"" + Num(kMargin) + "\" y=\"" + Num(top + 40) + "\" fill=\"#555\">" +
         Escape(Cut(sub, 160)) + "</text>\n";
  // Edges first, so that boxes cover their ends.
  for (std::size_t k = 0; k < a.transitions.size(); ++k) {
    const Transition& t = a.transitions[k];
    const Box& f = box[t.from];
    const Box& g = box[t.to];
    double fx = f.x + f.w / 2, fy = f.y + kBoxHeight / 2, gx = g.x + g.w / 2, gy = g.y + kBoxHeight / 2;
    double dx = gx - fx, dy = gy - fy, len = std::max(1.0, std::hypot(dx, dy));
    // Forward edges bend a little to their right (upwards), edges
    // back to an earlier column (or within one) loop below the boxes, where nothing else is.
    double cx, cy;
    if (depth[t.to] > depth[t.from]) {
      double bend = std::min(36.0, 0.15 * len);
      cx = (fx + gx) / 2 + dy / len * bend;
      cy = (fy + gy) / 2 - dx / len * bend;
    } else if (depth[t.to] == depth[t.from]) {  // within a column: a loop to its right
      cx = std::max(f.x + f.w, g.x + g.w) + 50 + 30 * (side++ % 2);
      cy = (fy + gy) / 2;
    } else {  // the curve's lowest point (halfway to the control point) lies below the boxes
      cx = (fx + gx) / 2;
      cy = 2 * (bottom + 16 + 16 * (back++ % 3)) - (fy + gy) / 2;
    }
    double sx, sy, ex, ey;
    Exit(f, cx, cy, sx, sy);
    Exit(g, cx, cy, ex, ey);
    bool automatic = !t.commanded;
    svg += "<path d=\"M" + Num(sx) + "," + Num(sy) + " Q" + Num(cx) + "," + Num(cy) + " " +
           Num(ex) + "," + Num(ey) + "\" fill=\"none\" stroke=\"" +
           (automatic ? "#777\" stroke-dasharray=\"5,3" : "#1f4e99") +
           "\" marker-end=\"url(#arrow)\"/>\n";
    std::string label = TransitionLabel(d, a, t);
    if (label.empty()) continue;
    double lx = 0.25 * sx + 0.5 * cx + 0.25 * ex, ly = 0.25 * sy + 0.5 * cy + 0.25 * ey - 4;
    std::string shown = Cut(label, o.max_label_chars);
    svg += "<text class=\"edge\" x=\"" + Num(lx) + "\" y=\"" + Num(ly) +
           "\" text-anchor=\"middle\" font-size=\"11\" fill=\"" +
           (automatic ? "#444" : "#1f4e99") + "\">";
    if (shown != label) svg += "<title>" + Escape(label) + "</title>";
    svg += Escape(shown) + "</text>\n";
  }
  for (int i = 0; i < n; ++i) {
    const Box& b = box[i];
    svg += "<g class=\"location\"><rect x=\"" + Num(b.x) + "\" y=\"" + Num(b.y) + "\" width=\"" +
           Num(b.w) + "\" height=\"" + Num(kBoxHeight) + "\" rx=\"12\" fill=\"" +
           (i == 0 ? "#e3f0ff" : "#ffffff") + "\" stroke=\"#333\"/>";
    svg += "<text x=\"" + Num(b.x + b.w / 2) + "\" y=\"" + Num(b.y + 19) +
           "\" text-anchor=\"middle\">" + Escape(a.locations[i]) + "</text></g>\n";
  }
  svg += "</g>\n";
}

}  // namespace

std::string TransitionLabel(const Domain& d, const Automaton& a, const Transition& t) {
  std::vector<std::string> parts;
  std::vector<const Expr*> conj;
  Conjuncts(t.guard, conj);
  std::string command;
  std::vector<std::string> rest;
  for (const Expr* e : conj) {
    if (t.commanded && t.command > 0 && e->op == Expr::Op::kAtom &&
        e->var_kind == VarKind::kCommand && !e->not_equal && e->value_code == t.command &&
        command.empty() && e->target >= 0 &&
        e->target < static_cast<int>(d.automata.size()) && d.automata[e->target].name == a.name) {
      command = a.commands[t.command - 1];
      continue;
    }
    if (e->op == Expr::Op::kTrue) continue;
    rest.push_back(PrintSource(*e));  // compound parts keep their parentheses
  }
  if (rest.size() == 1) rest[0] = Unwrap(rest[0]);
  if (!command.empty()) parts.push_back(command);
  std::string when;
  for (std::size_t i = 0; i < rest.size(); ++i) when += (i ? " /\\ " : "") + rest[i];
  if (!when.empty()) parts.push_back(when);
  const Duration& du = t.duration;
  if (du.hi && du.lo == *du.hi && du.lo > 0)
    parts.push_back("after " + Seconds(du.lo) + " s");
  else if (du.lo > 0 || du.hi)
    parts.push_back("[" + Seconds(du.lo) + ", " + (du.hi ? Seconds(*du.hi) : "inf") + "] s");
  if (t.controllable) parts.push_back("(controllable)");
  if (t.contingent) parts.push_back("(contingent)");
  if (t.cost != 1) parts.push_back("cost " + std::to_string(t.cost));
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? " · " : "") + parts[i];
  return out;
}

std::string DomainSvg(const Domain& d, const DiagramOptions& o) {
  std::string body;
  double top = 0, width = 320;
  for (const auto& a : d.automata) {
    double h = 0, w = 0;
    Panel(d, a, top, o, body, h, w);
    top += h + 8;
    width = std::max(width, w);
  }
  std::string svg =
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Num(width) + "\" height=\"" +
      Num(top + 4) + "\" viewBox=\"0 0 " + Num(width) + " " + Num(top + 4) +
      "\" font-family=\"sans-serif\" font-size=\"12\">\n<title>" +
      Escape("action model " + d.name) + "</title>\n" +
      "<defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"10\" refY=\"5\" markerWidth=\"7\" "
      "markerHeight=\"7\" orient=\"auto-start-reverse\"><path d=\"M0,0 L10,5 L0,10 z\" "
      "fill=\"#333\"/></marker></defs>\n";
  return svg + body + "</svg>\n";
}

}  // namespace ctb
