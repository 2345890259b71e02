// Internal to planner/analyze: difference-bound matrices (zones), the symbolic sets of clock
// valuations of timed-automata reachability (Dill 1989; Bengtsson and Yi, "Timed automata:
// semantics, algorithms and tools", 2004). No Debian package ships one (UPPAAL's UDBM is not
// packaged); this is the textbook structure, kept canonical (all-pairs shortest paths).
//
// Clock 0 is the reference (always 0); m(i, j) bounds x_i - x_j by a constant, strict or not.
// Bounds are encoded as in UDBM: 2c + 1 for "<= c", 2c for "< c". Values are plain data;
// thread-safe as values are.
#pragma once

#include <cstdint>
#include <vector>

namespace ctb::analysis {

class Dbm {
 public:
  using Raw = std::int64_t;
  static constexpr Raw kInfinity = INT64_MAX / 4;

  static Raw Le(std::int64_t c) { return 2 * c + 1; }
  static Raw Lt(std::int64_t c) { return 2 * c; }

  // `clocks` clocks besides the reference, all 0.
  explicit Dbm(int clocks);

  int Size() const { return n_; }
  bool Empty() const { return empty_; }
  Raw At(int i, int j) const { return m_[i * n_ + j]; }
  // The least value x takes in the zone (its infimum, when the bound is strict) and the largest
  // (kInfinity when none), read from its bounds against the reference clock.
  std::int64_t Lower(int x) const { return -(At(0, x) >> 1); }
  std::int64_t Upper(int x) const { return At(x, 0) >= kInfinity ? kInfinity : At(x, 0) >> 1; }

  // Let time pass: no upper bounds on clocks.
  void Up();
  // x := 0.
  void Reset(int x);
  // Forgets x (any value >= 0).
  void Free(int x);
  // Adds x_i - x_j (< or <=) c, as encoded; false when the zone becomes empty.
  bool Constrain(int i, int j, Raw bound);
  bool AtMost(int x, std::int64_t c) { return Constrain(x, 0, Le(c)); }
  bool Below(int x, std::int64_t c) { return Constrain(x, 0, Lt(c)); }
  bool AtLeast(int x, std::int64_t c) { return Constrain(0, x, Le(-c)); }
  // Classical extrapolation with each clock's largest constant (max[0] unused; a negative value
  // frees the clock): an over-approximation that keeps reachability exact for diagonal-free
  // automata and makes the zone graph finite.
  void Extrapolate(const std::vector<std::int64_t>& max);
  // Whether every valuation of `o` is in this zone.
  bool Includes(const Dbm& o) const;

 private:
  static Raw Add(Raw a, Raw b);
  Raw& M(int i, int j) { return m_[i * n_ + j]; }
  void Close();

  int n_;
  bool empty_ = false;
  std::vector<Raw> m_;
};

}  // namespace ctb::analysis
