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
  requireInRange("atsp.chains", chains, 1, 1024);
}

namespace {

bool badEntry(const CostMatrix& c, int i, int j) {
  if (i == j || !(std::isnan(c(i, j)) || c(i, j) == -kUnreachable)) return false;
  throw std::invalid_argument("AtspSolver: cost(" + std::to_string(i) + ", " + std::to_string(j) +
                              ") is NaN or -inf");
}

void checkMatrix(const CostMatrix& c) {
  for (int i = 0; i < c.size(); ++i)
    for (int j = 0; j < c.size(); ++j) badEntry(c, i, j);
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

// Also checks the matrix (in the pass that finds its largest entry).
Work makeWork(const CostMatrix& c, int extra_nodes) {
  const int n = c.size();
  double max_abs = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (!badEntry(c, i, j) && i != j && c.reachable(i, j))
        max_abs = std::max(max_abs, std::abs(c(i, j)));
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
  // Each state pulls from its predecessors over the set bits only: the same candidates in the
  // same order as relaxing forwards, without testing every bit of every mask. The argmin is
  // recomputed on the way back (the same sums, so the same first minimum) instead of stored.
  std::vector<double> into(static_cast<size_t>(m) * m);  // into[k * m + j] = w(j + 1, k + 1)
  for (int j = 0; j < m; ++j)
    for (int k = 0; k < m; ++k) into[static_cast<size_t>(k) * m + j] = wk.at(j + 1, k + 1);
  std::vector<double> dp(full * m);  // dp[mask * m + k], set for k in mask only
  for (int j = 0; j < m; ++j) dp[(size_t(1) << j) * m + j] = wk.at(0, j + 1);
  auto pull = [&](size_t mask, int k, int* arg) {
    const size_t prev = mask ^ (size_t(1) << k);
    const double* from = &dp[prev * m];
    const double* edge = &into[static_cast<size_t>(k) * m];
    double best = std::numeric_limits<double>::infinity();
    for (size_t js = prev; js; js &= js - 1) {
      const int j = __builtin_ctzll(js);
      const double v = from[j] + edge[j];
      if (v < best) best = v, *arg = j;
    }
    return best;
  };
  int unused = 0;
  for (size_t mask = 3; mask < full; ++mask) {
    if (!(mask & (mask - 1))) continue;  // single nodes are set above
    for (size_t ks = mask; ks; ks &= ks - 1) {
      const int k = __builtin_ctzll(ks);
      dp[mask * m + k] = pull(mask, k, &unused);
    }
  }
  const size_t all = full - 1;
  int last = 0;
  double best = std::numeric_limits<double>::infinity();
  for (int j = 0; j < m; ++j) {
    const double v = dp[all * m + j] + wk.at(j + 1, 0);
    if (v < best) best = v, last = j;
  }
  std::vector<int> rev{last + 1};
  for (size_t mask = all; mask & (mask - 1);) {
    int p = 0;
    pull(mask, last, &p);
    mask ^= size_t(1) << last;
    last = p;
    rev.push_back(last + 1);
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
// The tour lives in a circular buffer: a move rewrites only the two shortest of the three
// segments it touches (the cyclic order A B R -> B A R is also A R B and R B A), and `base_`
// keeps the node the move starts from at logical position 0, so the logical order, and with it
// the random kicks, does not depend on which segments were rewritten.
class LocalSearch {
 public:
  static constexpr int kMaxNeighbours = 64;  // AtspConfig::validate() bounds `neighbours`

  // Candidate lists rank edges by reduced cost c(i,j) - u_i - v_j of the assignment relaxation
  // when potentials are given (much better candidates on random asymmetric matrices), else by
  // raw cost.
  LocalSearch(const Work& wk, int k, const Assignment* ap) : n_(wk.n), w_(wk.w.data()) {
    k_ = std::min(k, n_ - 1);
    buildCandidates(ap);
    inq_.assign(n_, 0);
    pos_.resize(n_);
    tmp_.resize(n_);
    // A failed improveAt(a) is a function of the tour and its cost only: it is not repeated
    // while the tour is unchanged (`checked_[a] == version_`).
    checked_.assign(n_, -1);
  }

  void setTour(const std::vector<int>& t) {
    buf_ = t;
    base_ = 0;
    settle();
  }
  /// The tour in logical order (logical position 0 first).
  std::vector<int> tour() const {
    std::vector<int> t(n_);
    for (int i = 0; i < n_; ++i) t[i] = at(base_ + i);
    return t;
  }
  double cost() const { return cost_; }
  void save() {
    saved_ = buf_;
    saved_base_ = base_;
  }
  void restore() {
    buf_.swap(saved_);
    base_ = saved_base_;
    settle();
  }

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
    for (int i = 0; i < n_; ++i) push(at(base_ + i));
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
    const int a = at(base_ + static_cast<int>(rng() % n_));
    const int lim = std::max(1, std::min(seg_max, (n_ - 1) / 2));
    const int l1 = 1 + static_cast<int>(rng() % lim);
    const int l2 = 1 + static_cast<int>(rng() % lim);
    const int bp = at(pos_[a] + 1 + l1);
    const int c = at(pos_[a] + l1 + l2);
    applySwap(a, bp, c);
  }

 private:
  double d(int a, int b) const { return w_[static_cast<size_t>(a) * n_ + b]; }
  // Node at buffer index p, for 0 <= p < 2n.
  int at(int p) const { return buf_[p >= n_ ? p - n_ : p]; }
  int succ(int x) const { return at(pos_[x] + 1); }
  // Buffer index of the predecessor of x (its position found with the node itself).
  int before(int x) const {
    const int p = pos_[x] - 1;
    return p < 0 ? n_ - 1 : p;
  }
  int pred(int x) const { return buf_[before(x)]; }
  int off(int a, int x) const {
    const int o = pos_[x] - pos_[a];
    return o < 0 ? o + n_ : o;
  }
  void push(int x) {
    if (!inq_[x]) inq_[x] = 1, queue_.push_back(x);
  }

  // Positions and cost of a new buffer; the cost is summed in logical order, as a fresh tour's.
  void settle() {
    for (int i = 0; i < n_; ++i) pos_[buf_[i]] = i;
    cost_ = 0.0;
    for (int i = 0; i < n_; ++i) cost_ += d(at(base_ + i), at(base_ + (i + 1) % n_));
    ++version_;
  }

  // The k best of each row (outgoing) and column (incoming) by (rank value, index): one pass
  // over the matrix in memory order with an insertion into short sorted lists, instead of a
  // sort per row and a strided one per column.
  void buildCandidates(const Assignment* ap) {
    nout_.resize(static_cast<size_t>(n_) * k_);
    nin_.resize(static_cast<size_t>(n_) * k_);
    std::vector<double> out_v(k_), in_v(static_cast<size_t>(n_) * k_);
    std::vector<int> in_len(n_, 0);
    // Rows are scanned in increasing index, so an equal value never displaces an earlier entry.
    auto insert = [this](double* v, int* id, int& len, double x, int j) {
      if (len == k_ && !(x < v[k_ - 1])) return;
      int p = len < k_ ? len++ : k_ - 1;
      for (; p > 0 && v[p - 1] > x; --p) v[p] = v[p - 1], id[p] = id[p - 1];
      v[p] = x, id[p] = j;
    };
    for (int i = 0; i < n_; ++i) {
      int out_len = 0;
      int* out = &nout_[static_cast<size_t>(i) * k_];
      for (int j = 0; j < n_; ++j) {
        if (j == i) continue;
        const double r = ap ? d(i, j) - ap->u[i] - ap->v[j] : d(i, j);
        insert(out_v.data(), out, out_len, r, j);
        const size_t jk = static_cast<size_t>(j) * k_;
        insert(&in_v[jk], &nin_[jk], in_len[j], r, i);
      }
    }
    nout_d_.resize(nout_.size());
    nin_d_.resize(nin_.size());
    for (int i = 0; i < n_; ++i)
      for (int t = 0; t < k_; ++t) {
        const size_t it = static_cast<size_t>(i) * k_ + t;
        nout_d_[it] = d(i, nout_[it]);
        nin_d_[it] = d(nin_[it], i);
      }
  }

  double swapGain(int a, int bp, int c) const {
    const int a1 = succ(a), b = pred(bp), c1 = succ(c);
    return d(a, a1) + d(b, bp) + d(c, c1) - d(a, bp) - d(c, a1) - d(b, c1);
  }
  // Buffer range [s, s + l1 + l2) (cyclic) holding blocks X (l1) and Y (l2) becomes Y X.
  void swapBlocks(int s, int l1, int l2) {
    const int len = l1 + l2;
    for (int q = 0; q < len; ++q) tmp_[q] = at(s + q);
    for (int q = 0; q < len; ++q) {
      int p = s + q;
      if (p >= n_) p -= n_;
      const int x = tmp_[q < l2 ? q + l1 : q - l2];
      buf_[p] = x;
      pos_[x] = p;
    }
  }
  void applySwap(int a, int bp, int c) {
    const int a1 = succ(a), b = pred(bp), c1 = succ(c);
    cost_ -= swapGain(a, bp, c);
    const int pa = pos_[a], ob = off(a, bp), oc = off(a, c);
    // Segments after a: A = offsets 1..ob-1, B = ob..oc, R = oc+1..n (R ends with a itself).
    const int la = ob - 1, lb = oc - ob + 1, lr = n_ - oc;
    auto wrap = [this](int p) { return p >= n_ ? p - n_ : p; };
    if (la + lb <= lb + lr && la + lb <= lr + la)
      swapBlocks(wrap(pa + 1), la, lb);
    else if (lb + lr <= lr + la)
      swapBlocks(wrap(pa + ob), lb, lr);
    else
      swapBlocks(wrap(pa + oc + 1), lr, la);
    base_ = pos_[a];
    ++version_;
    for (int x : {a, a1, b, bp, c, c1}) push(x);
  }

  bool improveAt(int a) {
    if (checked_[a] == version_) return false;
    if (searchAt(a)) return true;
    checked_[a] = version_;
    return false;
  }

  // First improving segment swap in which `a` is the tail of a removed edge. Gains are built
  // up edge by edge so that most candidates are rejected after two lookups. The incoming
  // candidates of a1 serve both move types, so their positions, successors and edge costs are
  // read once.
  bool searchAt(int a) {
    const int a1 = succ(a), pa = pos_[a];
    const double daa1 = d(a, a1);
    const double eps = 1e-9 * (1.0 + std::abs(cost_) / n_);
    const size_t ak = static_cast<size_t>(a) * k_, a1k = static_cast<size_t>(a1) * k_;
    auto offsetAt = [&](int p) {
      const int o = p - pa;
      return o < 0 ? o + n_ : o;
    };
    auto offset = [&](int x) { return offsetAt(pos_[x]); };
    // Incoming candidate p of a1 (the new edge p -> a1), its offset from a, its successor q.
    int in_off[kMaxNeighbours], in_q[kMaxNeighbours];
    double in_dpq[kMaxNeighbours];
    const double* in_dpa1 = &nin_d_[a1k];
    for (int u = 0; u < k_; ++u) {
      const int p = nin_[a1k + u];
      in_off[u] = offset(p);
      in_q[u] = succ(p);
      in_dpq[u] = d(p, in_q[u]);
    }
    // 3-opt segment swap: the new edge a->bp is cheaper than a->a1 (positive first gain).
    for (int t = 0; t < k_; ++t) {
      const int bp = nout_[ak + t];
      const double g1 = daa1 - nout_d_[ak + t];
      if (g1 <= 0.0 || bp == a1) continue;
      const int b = pred(bp), ob = offset(bp);
      const double g2 = g1 + d(b, bp);
      for (int u = 0; u < k_; ++u) {
        if (in_off[u] < ob) continue;
        if (g2 + in_dpq[u] - in_dpa1[u] - d(b, in_q[u]) > eps)
          return applySwap(a, bp, nin_[a1k + u]), true;
      }
      const size_t bk = static_cast<size_t>(b) * k_;
      for (int u = 0; u < k_; ++u) {
        const int c1 = nout_[bk + u];
        const int pc = before(c1), c = buf_[pc];
        if (offsetAt(pc) < ob) continue;
        if (g2 + d(c, c1) - d(c, a1) - nout_d_[bk + u] > eps) return applySwap(a, bp, c), true;
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
        if (in_off[u] <= len) continue;
        if (g1 + in_dpq[u] - in_dpa1[u] - d(e, in_q[u]) > eps)
          return applySwap(a, after, nin_[a1k + u]), true;
      }
      const size_t ek = static_cast<size_t>(e) * k_;
      for (int u = 0; u < k_; ++u) {
        const int q = nout_[ek + u];
        const int pp = before(q), p = buf_[pp];
        if (offsetAt(pp) <= len) continue;
        if (g1 + d(p, q) - d(p, a1) - nout_d_[ek + u] > eps) return applySwap(a, after, p), true;
      }
    }
    return false;
  }

  int n_, k_;
  const double* w_;
  std::vector<int> nout_, nin_, buf_, saved_, pos_, tmp_, queue_;
  std::vector<double> nout_d_, nin_d_;  // d() of each candidate edge, beside nout_ / nin_
  std::vector<char> inq_;
  std::vector<int64_t> checked_;
  int64_t version_ = 0;
  int base_ = 0, saved_base_ = 0;
  double cost_ = 0.0;
};

// Kicks from the local optimum in `ls`, accepting equal or better tours; the best tour seen.
struct Chain {
  std::vector<int> best;
  double cost = 0.0;
};
Chain runKicks(LocalSearch& ls, int kicks, int seg_max, uint64_t seed) {
  Chain out{ls.tour(), ls.cost()};
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull);
  double cur = out.cost;
  for (int k = 0; k < kicks; ++k) {
    ls.save();
    ls.kick(rng, seg_max);
    ls.optimise();
    const double c = ls.cost();
    if (c <= cur + 1e-12 * std::abs(cur)) {
      cur = c;
      if (c < out.cost - 1e-12 * std::abs(out.cost)) out.cost = c, out.best = ls.tour();
    } else {
      ls.restore();
      cur = ls.cost();
    }
  }
  return out;
}

std::vector<int> iteratedLocalSearch(const Work& wk, const AtspConfig& cfg, uint64_t seed,
                                     int* kicks_done, const std::vector<int>* initial,
                                     const ParallelFor* parallel) {
  const int n = wk.n;
  std::unique_ptr<Assignment> ap;
  if (cfg.assignment_start && !initial) ap = std::make_unique<Assignment>(solveAssignment(wk));
  LocalSearch ls(wk, cfg.neighbours, ap.get());
  ls.setTour(initial ? *initial : ap ? patchCycles(wk, ap->succ) : ls.nearestNeighbourTour());
  ls.pushAll();
  ls.optimise();
  const int kicks =
      std::clamp(static_cast<int>(cfg.kicks_per_node * n), cfg.min_kicks, cfg.max_kicks);
  const int chains = std::max(1, std::min(cfg.chains, kicks));
  const int per_chain = (kicks + chains - 1) / chains;
  if (kicks_done) *kicks_done = chains == 1 ? kicks : per_chain * chains;
  if (chains == 1) return runKicks(ls, kicks, cfg.kick_segment_max, seed).best;
  // The chains share the set-up and the first descent, then diverge by their seeds; chain 0
  // keeps the seed of an unsplit search.
  std::vector<Chain> out(chains);
  const std::function<void(int)> chain = [&](int q) {
    LocalSearch mine = ls;
    out[q] = runKicks(mine, per_chain, cfg.kick_segment_max,
                      q == 0 ? seed : seed ^ (0xD1B54A32D192ED03ull * static_cast<uint64_t>(q)));
  };
  if (parallel) {
    (*parallel)(chains, chain);
  } else {
    for (int q = 0; q < chains; ++q) chain(q);
  }
  int best = 0;  // ties go to the lower chain, whatever finished first
  for (int q = 1; q < chains; ++q)
    if (out[q].cost < out[best].cost) best = q;
  return std::move(out[best].best);
}

std::vector<int> rotateTo(const std::vector<int>& t, int first) {
  const auto it = std::find(t.begin(), t.end(), first);
  std::vector<int> r(it, t.end());
  r.insert(r.end(), t.begin(), it);
  return r;
}

std::vector<int> solveWork(const Work& wk, const AtspConfig& cfg, uint64_t seed, bool exact,
                           int* kicks, const std::vector<int>* initial,
                           const ParallelFor* parallel) {
  if (exact || wk.n <= 3) return heldKarp(wk);
  return iteratedLocalSearch(wk, cfg, seed, kicks, initial, parallel);
}

}  // namespace

AtspSolver::AtspSolver(AtspConfig config) : config_(config) { config_.validate(); }

AtspResult AtspSolver::solveTour(const CostMatrix& c, uint64_t seed,
                                 const ParallelFor* parallel) const {
  const Work wk = makeWork(c, 0);
  AtspResult r;
  if (c.size() == 0) return r;
  r.exact = c.size() <= config_.exact_max_nodes || c.size() <= 3;
  r.order = rotateTo(solveWork(wk, config_, seed, r.exact, &r.kicks, nullptr, parallel), 0);
  r.cost = pathCost(c, r.order, true);
  r.feasible = r.cost < kUnreachable;
  return r;
}

AtspResult AtspSolver::solveOpenPath(const CostMatrix& c, int start, int end, uint64_t seed,
                                     const std::vector<int>* initial_order,
                                     const ParallelFor* parallel) const {
  // The matrix is checked first, by building the working copy.
  Work wk = makeWork(c, end == kFreeEnd ? 0 : 1);
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
    for (int i = 0; i < n; ++i) wk.at(i, start) = 0.0;
    r.order = rotateTo(solveWork(wk, config_, seed, r.exact, &r.kicks, init, parallel), start);
  } else {
    // Dummy node D: end -> D -> start are free, every other edge at D is forbidden with a
    // weight above any tour of ordinary (even unreachable) edges.
    const int dn = n;
    const double forbid = (wk.n + 2.0) * wk.big;
    for (int i = 0; i < n; ++i) wk.at(i, dn) = wk.at(dn, i) = forbid;
    wk.at(end, dn) = 0.0;
    wk.at(dn, start) = 0.0;
    std::vector<int> t =
        rotateTo(solveWork(wk, config_, seed, r.exact, &r.kicks, init, parallel), start);
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
