#include "planner/analyze/dbm.h"

#include <algorithm>

namespace ctb::analysis {

namespace {
constexpr Dbm::Raw kLeZero = 1;  // "<= 0"
}

Dbm::Dbm(int clocks) : n_(clocks + 1), m_(static_cast<std::size_t>(n_) * n_, kLeZero) {}

Dbm::Raw Dbm::Add(Raw a, Raw b) {
  if (a >= kInfinity || b >= kInfinity) return kInfinity;
  return a + b - ((a | b) & 1);
}

void Dbm::Up() {
  for (int i = 1; i < n_; ++i) M(i, 0) = kInfinity;
}

void Dbm::Reset(int x) {
  for (int j = 0; j < n_; ++j) {
    M(x, j) = M(0, j);
    M(j, x) = M(j, 0);
  }
  M(x, x) = kLeZero;
}

void Dbm::Free(int x) {
  for (int j = 0; j < n_; ++j) {
    if (j == x) continue;
    M(x, j) = kInfinity;
    M(j, x) = M(j, 0);
  }
}

bool Dbm::Constrain(int i, int j, Raw bound) {
  if (empty_ || bound >= M(i, j)) return !empty_;
  if (Add(M(j, i), bound) < kLeZero) {
    empty_ = true;
    return false;
  }
  M(i, j) = bound;
  // Incremental closure through the new edge i -> j.
  for (int k = 0; k < n_; ++k) {
    const Raw ki = M(k, i);
    if (ki >= kInfinity) continue;
    const Raw kij = Add(ki, bound);
    for (int l = 0; l < n_; ++l) {
      const Raw v = Add(kij, M(j, l));
      if (v < M(k, l)) M(k, l) = v;
    }
  }
  return true;
}

void Dbm::Close() {
  for (int k = 0; k < n_; ++k)
    for (int i = 0; i < n_; ++i) {
      if (M(i, k) >= kInfinity) continue;
      for (int j = 0; j < n_; ++j) {
        const Raw v = Add(M(i, k), M(k, j));
        if (v < M(i, j)) M(i, j) = v;
      }
    }
  for (int i = 0; i < n_; ++i)
    if (M(i, i) < kLeZero) empty_ = true;
}

void Dbm::Extrapolate(const std::vector<std::int64_t>& max) {
  if (empty_) return;
  for (int x = 1; x < n_; ++x)
    if (max[x] < 0) Free(x);
  bool changed = false;
  for (int i = 0; i < n_; ++i)
    for (int j = 0; j < n_; ++j) {
      if (i == j || M(i, j) >= kInfinity) continue;
      const std::int64_t mi = i ? max[i] : 0, mj = j ? max[j] : 0;
      if (mi < 0 || mj < 0) continue;
      if (M(i, j) > Le(mi))
        M(i, j) = kInfinity, changed = true;
      else if (M(i, j) < Lt(-mj))
        M(i, j) = Lt(-mj), changed = true;
    }
  if (changed) Close();
}

bool Dbm::Includes(const Dbm& o) const {
  if (o.empty_) return true;
  if (empty_) return false;
  for (std::size_t k = 0; k < m_.size(); ++k)
    if (o.m_[k] > m_[k]) return false;
  return true;
}

}  // namespace ctb::analysis
