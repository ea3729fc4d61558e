// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/atsp_solver.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <random>
#include <string>

#include "efs_common/config_check.h"

namespace efs::planner {

void AtspConfig::validate() const {
  requireInRange("atsp.exact_max_nodes", exact_max_nodes, 0, 16);
  requireInRange("atsp.neighbours", neighbours, 1, 64);
  requireInRange("atsp.kicks_per_node", kicks_per_node, 0.0, 1e6);
  requireInRange("atsp.min_kicks", min_kicks, 0, 100000000);
  requireInRange("atsp.max_kicks", max_kicks, min_kicks, 100000000);
  requireInRange("atsp.kick_segment_max", kick_segment_max, 1, 1000000);
}

namespace {

void checkMatrix(const CostMatrix& c) {
  const int n = c.size();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j && (std::isnan(c(i, j)) || c(i, j) == -kUnreachable))
        throw std::invalid_argument("AtspSolver: cost(" + std::to_string(i) + ", " +
                                    std::to_string(j) + ") is NaN or -inf");
}

// Finite working copy: unreachable edges cost `big`, larger than any tour of finite edges, so
// the search minimises the number of unreachable edges first.
struct Work {
  int n = 0;
  std::vector<double> w;
  double big = 0.0;
  double at(int i, int j) const { return w[static_cast<size_t>(i) * n + j]; }
  double& at(int i, int j) { return w[static_cast<size_t>(i) * n + j]; }
};

Work makeWork(const CostMatrix& c, int extra_nodes) {
  const int n = c.size();
  double max_abs = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j && c.reachable(i, j)) max_abs = std::max(max_abs, std::abs(c(i, j)));
  Work wk;
  wk.n = n + extra_nodes;
  wk.big = (wk.n + 1.0) * (2.0 * max_abs + 1.0);
  wk.w.assign(static_cast<size_t>(wk.n) * wk.n, 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      wk.at(i, j) = (i == j) ? 0.0 : (c.reachable(i, j) ? c(i, j) : wk.big);
  return wk;
}

// Held-Karp over the working matrix; the tour starts at node 0.
std::vector<int> heldKarp(const Work& wk) {
  const int n = wk.n;
  if (n <= 3) {
    std::vector<int> t(n);
    std::iota(t.begin(), t.end(), 0);
    if (n == 3 && wk.at(0, 2) + wk.at(2, 1) + wk.at(1, 0) < wk.at(0, 1) + wk.at(1, 2) + wk.at(2, 0))
      std::swap(t[1], t[2]);
    return t;
  }
  const int m = n - 1;  // nodes 1..n-1 -> bits 0..m-1
  const size_t full = size_t(1) << m;
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dp(full * m, inf);
  std::vector<int8_t> par(full * m, -1);
  for (int j = 0; j < m; ++j) dp[(size_t(1) << j) * m + j] = wk.at(0, j + 1);
  for (size_t mask = 1; mask < full; ++mask) {
    for (int j = 0; j < m; ++j) {
      if (!(mask & (size_t(1) << j))) continue;
      const double cur = dp[mask * m + j];
      if (cur == inf) continue;
      const double* row = &wk.w[static_cast<size_t>(j + 1) * n + 1];
      for (int k = 0; k < m; ++k) {
        if (mask & (size_t(1) << k)) continue;
        const size_t nm = mask | (size_t(1) << k);
        const double v = cur + row[k];
        if (v < dp[nm * m + k]) {
          dp[nm * m + k] = v;
          par[nm * m + k] = static_cast<int8_t>(j);
        }
      }
    }
  }
  const size_t all = full - 1;
  int last = 0;
  double best = inf;
  for (int j = 0; j < m; ++j) {
    const double v = dp[all * m + j] + wk.at(j + 1, 0);
    if (v < best) best = v, last = j;
  }
  std::vector<int> rev;
  size_t mask = all;
  int j = last;
  while (j >= 0) {
    rev.push_back(j + 1);
    const int p = par[mask * m + j];
    mask &= ~(size_t(1) << j);
    j = p;
  }
  std::vector<int> t{0};
  t.insert(t.end(), rev.rbegin(), rev.rend());
  return t;
}

// Minimum-cost assignment (each node one successor, no self loops) by the Hungarian method with
// potentials, O(n^3). Returns the successor of every node and the dual potentials u, v
// (c(i,j) - u_i - v_j >= 0, zero on the assignment), used for reduced-cost candidate lists.
struct Assignment {
  std::vector<int> succ;
  std::vector<double> u, v;
};

Assignment solveAssignment(const Work& wk) {
  const int n = wk.n;
  const double inf = std::numeric_limits<double>::infinity();
  const double self = 4.0 * wk.big + 1.0;
  auto cost = [&](int i, int j) { return i == j ? self : wk.at(i, j); };
  // 1-based rows/columns; column 0 is the virtual start of each augmenting path.
  std::vector<double> u(n + 1, 0.0), v(n + 1, 0.0), minv(n + 1);
  std::vector<int> p(n + 1, 0), way(n + 1, 0);
  std::vector<char> used(n + 1);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::fill(minv.begin(), minv.end(), inf);
    std::fill(used.begin(), used.end(), 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= n; ++j) {
        if (used[j]) continue;
        const double cur = cost(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) minv[j] = cur, way[j] = j0;
        if (minv[j] < delta) delta = minv[j], j1 = j;
      }
      for (int j = 0; j <= n; ++j) {
        if (used[j])
          u[p[j]] += delta, v[j] -= delta;
        else
          minv[j] -= delta;
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0);
  }
  Assignment a;
  a.succ.assign(n, 0);
  for (int j = 1; j <= n; ++j) a.succ[p[j] - 1] = j - 1;
  a.u.assign(u.begin() + 1, u.end());
  a.v.assign(v.begin() + 1, v.end());
  return a;
}

// Joins the assignment's cycles into one tour: repeatedly the smallest cycle is patched into
// the rest by the cheapest exchange of two successors (Karp's patching idea).
std::vector<int> patchCycles(const Work& wk, std::vector<int> succ) {
  const int n = wk.n;
  std::vector<int> cyc(n, -1);
  for (;;) {
    std::fill(cyc.begin(), cyc.end(), -1);
    std::vector<int> sizes;
    for (int s = 0; s < n; ++s) {
      if (cyc[s] >= 0) continue;
      int x = s, len = 0;
      while (cyc[x] < 0) cyc[x] = static_cast<int>(sizes.size()), x = succ[x], ++len;
      sizes.push_back(len);
    }
    if (sizes.size() <= 1) break;
    const int small =
        static_cast<int>(std::min_element(sizes.begin(), sizes.end()) - sizes.begin());
    double best = std::numeric_limits<double>::infinity();
    int bi = -1, bj = -1;
    for (int i = 0; i < n; ++i) {
      if (cyc[i] != small) continue;
      for (int j = 0; j < n; ++j) {
        if (cyc[j] == small) continue;
        const double dlt =
            wk.at(i, succ[j]) + wk.at(j, succ[i]) - wk.at(i, succ[i]) - wk.at(j, succ[j]);
        if (dlt < best) best = dlt, bi = i, bj = j;
      }
    }
    std::swap(succ[bi], succ[bj]);
  }
  std::vector<int> t{0};
  for (int x = succ[0]; x != 0; x = succ[x]) t.push_back(x);
  return t;
}

// Iterated local search with reversal-free moves. All moves are one primitive: swapping two
// adjacent tour segments, a -> [a1..b] [bp..c] -> c1 becomes a -> [bp..c] [a1..b] -> c1.
class LocalSearch {
 public:
  // Candidate lists rank edges by reduced cost c(i,j) - u_i - v_j of the assignment relaxation
  // when potentials are given (much better candidates on random asymmetric matrices), else by
  // raw cost.
  LocalSearch(const Work& wk, int k, const Assignment* ap) : n_(wk.n), w_(wk.w.data()) {
    auto r = [&](int i, int j) { return ap ? d(i, j) - ap->u[i] - ap->v[j] : d(i, j); };
    k_ = std::min(k, n_ - 1);
    nout_.resize(static_cast<size_t>(n_) * k_);
    nin_.resize(static_cast<size_t>(n_) * k_);
    std::vector<int> idx(n_ - 1);
    for (int i = 0; i < n_; ++i) {
      int q = 0;
      for (int j = 0; j < n_; ++j)
        if (j != i) idx[q++] = j;
      std::partial_sort(idx.begin(), idx.begin() + k_, idx.end(), [&](int a, int b) {
        return r(i, a) < r(i, b) || (r(i, a) == r(i, b) && a < b);
      });
      std::copy(idx.begin(), idx.begin() + k_, nout_.begin() + static_cast<size_t>(i) * k_);
      std::partial_sort(idx.begin(), idx.begin() + k_, idx.end(), [&](int a, int b) {
        return r(a, i) < r(b, i) || (r(a, i) == r(b, i) && a < b);
      });
      std::copy(idx.begin(), idx.begin() + k_, nin_.begin() + static_cast<size_t>(i) * k_);
    }
    inq_.assign(n_, 0);
    pos_.resize(n_);
    tmp_.resize(n_);
  }

  void setTour(const std::vector<int>& t) {
    tour_ = t;
    for (int i = 0; i < n_; ++i) pos_[tour_[i]] = i;
    cost_ = 0.0;
    for (int i = 0; i < n_; ++i) cost_ += d(tour_[i], tour_[(i + 1) % n_]);
  }
  const std::vector<int>& tour() const { return tour_; }
  double cost() const { return cost_; }

  std::vector<int> nearestNeighbourTour() const {
    std::vector<int> t{0};
    std::vector<char> used(n_, 0);
    used[0] = 1;
    for (int s = 1; s < n_; ++s) {
      const int a = t.back();
      int best = -1;
      for (int j = 0; j < n_; ++j)
        if (!used[j] && (best < 0 || d(a, j) < d(a, best))) best = j;
      used[best] = 1;
      t.push_back(best);
    }
    return t;
  }

  void pushAll() {
    for (int i = 0; i < n_; ++i) push(tour_[i]);
  }

  void optimise() {
    while (!queue_.empty()) {
      const int x = queue_.back();
      queue_.pop_back();
      inq_[x] = 0;
      if (improveAt(x) || improveAt(pred(x))) push(x);
    }
  }

  // Random segment swap ("double bridge" on an asymmetric tour: orientation preserving).
  void kick(std::mt19937_64& rng, int seg_max) {
    const int a = tour_[rng() % n_];
    const int lim = std::max(1, std::min(seg_max, (n_ - 1) / 2));
    const int l1 = 1 + static_cast<int>(rng() % lim);
    const int l2 = 1 + static_cast<int>(rng() % lim);
    const int bp = tour_[(pos_[a] + 1 + l1) % n_];
    const int c = tour_[(pos_[a] + l1 + l2) % n_];
    applySwap(a, bp, c);
  }

 private:
  double d(int a, int b) const { return w_[static_cast<size_t>(a) * n_ + b]; }
  int succ(int x) const {
    const int p = pos_[x] + 1;
    return tour_[p == n_ ? 0 : p];
  }
  int pred(int x) const {
    const int p = pos_[x] - 1;
    return tour_[p < 0 ? n_ - 1 : p];
  }
  int off(int a, int x) const {
    const int o = pos_[x] - pos_[a];
    return o < 0 ? o + n_ : o;
  }
  void push(int x) {
    if (!inq_[x]) inq_[x] = 1, queue_.push_back(x);
  }

  double swapGain(int a, int bp, int c) const {
    const int a1 = succ(a), b = pred(bp), c1 = succ(c);
    return d(a, a1) + d(b, bp) + d(c, c1) - d(a, bp) - d(c, a1) - d(b, c1);
  }
  void applySwap(int a, int bp, int c) {
    const int a1 = succ(a), b = pred(bp), c1 = succ(c);
    cost_ -= swapGain(a, bp, c);
    const int pa = pos_[a], ob = off(a, bp), oc = off(a, c);
    auto at = [&](int o) {
      const int p = pa + o;
      return tour_[p >= n_ ? p - n_ : p];
    };
    int q = 0;
    tmp_[q++] = a;
    for (int o = ob; o <= oc; ++o) tmp_[q++] = at(o);
    for (int o = 1; o < ob; ++o) tmp_[q++] = at(o);
    for (int o = oc + 1; o < n_; ++o) tmp_[q++] = at(o);
    tour_.swap(tmp_);
    for (int i = 0; i < n_; ++i) pos_[tour_[i]] = i;
    for (int x : {a, a1, b, bp, c, c1}) push(x);
  }

  // First improving segment swap in which `a` is the tail of a removed edge. Gains are built
  // up edge by edge so that most candidates are rejected after two lookups.
  bool improveAt(int a) {
    const int a1 = succ(a), pa = pos_[a];
    const double daa1 = d(a, a1);
    const double eps = 1e-9 * (1.0 + std::abs(cost_) / n_);
    const int* out = &nout_[static_cast<size_t>(a) * k_];
    const int* in_a1 = &nin_[static_cast<size_t>(a1) * k_];
    auto offset = [&](int x) {
      const int o = pos_[x] - pa;
      return o < 0 ? o + n_ : o;
    };
    // 3-opt segment swap: the new edge a->bp is cheaper than a->a1 (positive first gain).
    for (int t = 0; t < k_; ++t) {
      const int bp = out[t];
      const double g1 = daa1 - d(a, bp);
      if (g1 <= 0.0 || bp == a1) continue;
      const int b = pred(bp), ob = offset(bp);
      const double g2 = g1 + d(b, bp);
      for (int u = 0; u < k_; ++u) {
        const int c = in_a1[u];
        const int oc = offset(c);
        if (oc < ob) continue;
        const int c1 = succ(c);
        if (g2 + d(c, c1) - d(c, a1) - d(b, c1) > eps) return apply(a, bp, c), true;
      }
      const int* outb = &nout_[static_cast<size_t>(b) * k_];
      for (int u = 0; u < k_; ++u) {
        const int c1 = outb[u];
        const int c = pred(c1);
        const int oc = offset(c);
        if (oc < ob) continue;
        if (g2 + d(c, c1) - d(c, a1) - d(b, c1) > eps) return apply(a, bp, c), true;
      }
    }
    // Or-opt: move the 1..3 nodes after `a` elsewhere (forwards == backwards on a cycle), with
    // either of its new edges a candidate neighbour.
    int e = a;
    for (int len = 1; len <= 3 && len + 2 <= n_; ++len) {
      e = succ(e);
      const int after = succ(e);
      if (after == a) break;
      const double g1 = daa1 + d(e, after) - d(a, after);
      for (int u = 0; u < k_; ++u) {
        const int p = in_a1[u];
        if (offset(p) <= len) continue;
        const int q = succ(p);
        if (g1 + d(p, q) - d(p, a1) - d(e, q) > eps) return apply(a, after, p), true;
      }
      const int* oute = &nout_[static_cast<size_t>(e) * k_];
      for (int u = 0; u < k_; ++u) {
        const int q = oute[u];
        const int p = pred(q);
        if (offset(p) <= len) continue;
        if (g1 + d(p, q) - d(p, a1) - d(e, q) > eps) return apply(a, after, p), true;
      }
    }
    return false;
  }

  void apply(int a, int bp, int c) { applySwap(a, bp, c); }

  int n_, k_;
  const double* w_;
  std::vector<int> nout_, nin_, tour_, pos_, tmp_, queue_;
  std::vector<char> inq_;
  double cost_ = 0.0;
};

std::vector<int> iteratedLocalSearch(const Work& wk, const AtspConfig& cfg, uint64_t seed,
                                     int* kicks_done, const std::vector<int>* initial) {
  const int n = wk.n;
  std::unique_ptr<Assignment> ap;
  if (cfg.assignment_start && !initial) ap = std::make_unique<Assignment>(solveAssignment(wk));
  LocalSearch ls(wk, cfg.neighbours, ap.get());
  ls.setTour(initial ? *initial : ap ? patchCycles(wk, ap->succ) : ls.nearestNeighbourTour());
  ls.pushAll();
  ls.optimise();
  std::vector<int> best = ls.tour(), saved;
  double best_cost = ls.cost();
  const int kicks =
      std::clamp(static_cast<int>(cfg.kicks_per_node * n), cfg.min_kicks, cfg.max_kicks);
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull);
  double cur = best_cost;
  for (int k = 0; k < kicks; ++k) {
    saved = ls.tour();
    ls.kick(rng, cfg.kick_segment_max);
    ls.optimise();
    const double c = ls.cost();
    if (c <= cur + 1e-12 * std::abs(cur)) {
      cur = c;
      if (c < best_cost - 1e-12 * std::abs(best_cost)) best_cost = c, best = ls.tour();
    } else {
      ls.setTour(saved);
      cur = ls.cost();
    }
  }
  if (kicks_done) *kicks_done = kicks;
  return best;
}

std::vector<int> rotateTo(const std::vector<int>& t, int first) {
  const auto it = std::find(t.begin(), t.end(), first);
  std::vector<int> r(it, t.end());
  r.insert(r.end(), t.begin(), it);
  return r;
}

std::vector<int> solveWork(const Work& wk, const AtspConfig& cfg, uint64_t seed, bool exact,
                           int* kicks, const std::vector<int>* initial = nullptr) {
  if (exact || wk.n <= 3) return heldKarp(wk);
  return iteratedLocalSearch(wk, cfg, seed, kicks, initial);
}

}  // namespace

AtspSolver::AtspSolver(AtspConfig config) : config_(config) { config_.validate(); }

AtspResult AtspSolver::solveTour(const CostMatrix& c, uint64_t seed) const {
  checkMatrix(c);
  AtspResult r;
  if (c.size() == 0) return r;
  const Work wk = makeWork(c, 0);
  r.exact = c.size() <= config_.exact_max_nodes || c.size() <= 3;
  r.order = rotateTo(solveWork(wk, config_, seed, r.exact, &r.kicks), 0);
  r.cost = pathCost(c, r.order, true);
  r.feasible = r.cost < kUnreachable;
  return r;
}

AtspResult AtspSolver::solveOpenPath(const CostMatrix& c, int start, int end, uint64_t seed,
                                     const std::vector<int>* initial_order) const {
  checkMatrix(c);
  const int n = c.size();
  if (start < 0 || start >= n || end < kFreeEnd || end >= n || end == start)
    throw std::invalid_argument("AtspSolver::solveOpenPath: bad start " + std::to_string(start) +
                                " / end " + std::to_string(end) + " for " + std::to_string(n) +
                                " nodes");
  if (initial_order) {
    std::vector<int> chk = *initial_order;
    std::sort(chk.begin(), chk.end());
    bool ok = static_cast<int>(chk.size()) == n && !chk.empty() &&
              initial_order->front() == start && (end == kFreeEnd || initial_order->back() == end);
    for (int i = 0; ok && i < n; ++i) ok = chk[i] == i;
    if (!ok)
      throw std::invalid_argument(
          "AtspSolver::solveOpenPath: initial order is not a path from start");
  }
  AtspResult r;
  r.exact = n <= config_.exact_max_nodes;
  std::vector<int> warm;
  if (initial_order && !r.exact) {
    warm = *initial_order;
    if (end != kFreeEnd) warm.push_back(n);  // the dummy closes end -> D -> start
  }
  const std::vector<int>* init = warm.empty() ? nullptr : &warm;
  if (end == kFreeEnd) {
    // Every edge back to the start is free: the closing edge of the tour costs nothing.
    Work wk = makeWork(c, 0);
    for (int i = 0; i < n; ++i) wk.at(i, start) = 0.0;
    r.order = rotateTo(solveWork(wk, config_, seed, r.exact, &r.kicks, init), start);
  } else {
    // Dummy node D: end -> D -> start are free, every other edge at D is forbidden with a
    // weight above any tour of ordinary (even unreachable) edges.
    Work wk = makeWork(c, 1);
    const int dn = n;
    const double forbid = (wk.n + 2.0) * wk.big;
    for (int i = 0; i < n; ++i) wk.at(i, dn) = wk.at(dn, i) = forbid;
    wk.at(end, dn) = 0.0;
    wk.at(dn, start) = 0.0;
    std::vector<int> t = rotateTo(solveWork(wk, config_, seed, r.exact, &r.kicks, init), start);
    t.erase(std::remove(t.begin(), t.end(), dn), t.end());
    r.order = t;
  }
  r.cost = pathCost(c, r.order, false);
  r.feasible = r.cost < kUnreachable && (end == kFreeEnd || r.order.back() == end);
  return r;
}

AtspResult solveAtspExact(const CostMatrix& c) {
  checkMatrix(c);
  if (c.size() > 16) throw std::invalid_argument("solveAtspExact: more than 16 nodes");
  AtspResult r;
  if (c.size() == 0) return r;
  r.order = heldKarp(makeWork(c, 0));
  r.cost = pathCost(c, r.order, true);
  r.feasible = r.cost < kUnreachable;
  r.exact = true;
  return r;
}

AtspResult solveAtspBruteForce(const CostMatrix& c) {
  checkMatrix(c);
  if (c.size() > 10) throw std::invalid_argument("solveAtspBruteForce: more than 10 nodes");
  AtspResult r;
  if (c.size() == 0) return r;
  std::vector<int> t(c.size());
  std::iota(t.begin(), t.end(), 0);
  r.cost = kUnreachable;
  r.order = t;
  bool first = true;
  do {
    const double v = pathCost(c, t, true);
    if (first || v < r.cost) r.cost = v, r.order = t, first = false;
  } while (std::next_permutation(t.begin() + 1, t.end()));
  r.feasible = r.cost < kUnreachable;
  r.exact = true;
  return r;
}

}  // namespace efs::planner
