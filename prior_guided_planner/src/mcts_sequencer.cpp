// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/mcts_sequencer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <numeric>
#include <string>
#include <thread>

#include "efs_common/config_check.h"

namespace efs::planner {

void MctsConfig::validate() const {
  requireInRange("mcts.exploration_constant", exploration_constant, 0.0, 100.0);
  requireInRange("mcts.iterations", iterations, 0, 1000000);
  requireInRange("mcts.rollouts_per_iteration", rollouts_per_iteration, 1, 1024);
  requireInRange("mcts.threads", threads, 1, 256);
  requireInRange("mcts.root_chains", root_chains, 1, 64);
  rollout.validate();
}

// Workers kept between batches instead of threads spawned and joined in every iteration. Jobs
// are handed out one at a time (an atomic counter) rather than split up front, since rollouts
// differ in size with the depth of their node. A batch is over when its last job has finished,
// not when every worker has woken up: on a busy machine a worker may get no CPU for a while, and
// the others (the caller included) then take its share.
class RolloutPool {
 public:
  explicit RolloutPool(int workers) {
    for (int i = 0; i < workers; ++i) threads_.emplace_back([this] { workerLoop(); });
  }
  ~RolloutPool() {
    {
      std::lock_guard<std::mutex> lk(m_);
      stop_ = true;
    }
    wake_.notify_all();
    for (auto& t : threads_) t.join();
  }
  RolloutPool(const RolloutPool&) = delete;
  RolloutPool& operator=(const RolloutPool&) = delete;

  /// fn(0) .. fn(jobs - 1) on the workers and the calling thread; returns when all are done and
  /// rethrows the first exception of a job.
  void run(int jobs, const std::function<void(int)>& fn) {
    std::lock_guard<std::mutex> one_batch(run_m_);
    const auto b = std::make_shared<Batch>(fn, jobs);
    {
      std::lock_guard<std::mutex> lk(m_);
      batch_ = b;
      ++generation_;
    }
    wake_.notify_all();
    b->work();
    std::unique_lock<std::mutex> lk(b->m);
    b->finished.wait(lk, [&] { return b->done.load() == jobs; });
    if (b->error) std::rethrow_exception(b->error);
  }

 private:
  // Owned jointly by the caller and the workers that saw it: a worker that wakes late finds no
  // job left in it and never touches the next batch's.
  struct Batch {
    Batch(const std::function<void(int)>& f, int n) : fn(f), jobs(n) {}
    void work() {
      for (int j = next.fetch_add(1); j < jobs; j = next.fetch_add(1)) {
        try {
          fn(j);
        } catch (...) {
          std::lock_guard<std::mutex> lk(m);
          if (!error) error = std::current_exception();
        }
        if (done.fetch_add(1) + 1 == jobs) {
          std::lock_guard<std::mutex> lk(m);  // the caller is waiting or has not checked yet
          finished.notify_all();
        }
      }
    }
    const std::function<void(int)>& fn;
    const int jobs;
    std::atomic<int> next{0}, done{0};
    std::mutex m;
    std::condition_variable finished;
    std::exception_ptr error;
  };

  void workerLoop() {
    uint64_t seen = 0;
    for (;;) {
      std::shared_ptr<Batch> b;
      {
        std::unique_lock<std::mutex> lk(m_);
        wake_.wait(lk, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
        b = batch_;
      }
      b->work();
    }
  }

  std::vector<std::thread> threads_;
  std::mutex run_m_, m_;
  std::condition_variable wake_;
  std::shared_ptr<Batch> batch_;
  uint64_t generation_ = 0;
  bool stop_ = false;
};

namespace {

void checkProblem(const MctsProblem& p) {
  const int m = p.cost.size();
  if (m < 1 || static_cast<int>(p.exploring.size()) != m)
    throw std::invalid_argument("MctsProblem: cost is " + std::to_string(m) + " x " +
                                std::to_string(m) + " but exploring has " +
                                std::to_string(p.exploring.size()) + " entries (need >= 1, equal)");
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      if (std::isnan(p.cost(i, j)))
        throw std::invalid_argument("MctsProblem: cost(" + std::to_string(i) + ", " +
                                    std::to_string(j) + ") is NaN");
}

uint64_t mix(uint64_t a, uint64_t b) {
  uint64_t z = a * 0x9E3779B97F4A7C15ull + b + 0x7F4A7C159E3779B9ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

struct Node {
  int parent = -1;
  int gp = 0;  // problem node; 0 for the root
  double prefix_len = 0.0;
  double w = 0.0;
  int visits = 0;
  std::vector<int> children;
  std::vector<int> untried;  // in expansion order
};

struct Rollout {
  std::vector<int> sequence;  // full guidepoint sequence (without the robot)
  double length = kUnreachable;
};

// The root rollout starts from the assignment relaxation, or from the caller's warm order
// (the last plan's sequence), and gets a larger kick budget (its tour seeds every later
// rollout through the warm starts), shared by its chains.
AtspConfig rootConfig(const MctsConfig& c) {
  AtspConfig a = c.rollout;
  a.assignment_start = true;
  a.kicks_per_node = std::max(c.rollout.kicks_per_node, 15.0);
  a.chains = c.root_chains;
  return a;
}

class Search {
 public:
  Search(const MctsProblem& p, const MctsConfig& c, uint64_t seed, RolloutPool* pool,
         std::vector<int> root_warm)
      : p_(p),
        c_(c),
        seed_(seed),
        pool_(pool),
        root_warm_(std::move(root_warm)),
        m_(p.cost.size()),
        solver_(c.rollout),
        root_solver_(rootConfig(c)),
        parallel_([this](int jobs, const std::function<void(int)>& fn) { runJobs(jobs, fn); }) {}

  MctsResult run() {
    MctsResult res = initialMctsResult(m_);
    if (m_ == 1) return res;
    nodes_.push_back(Node{});
    const Rollout root = rollout(0);
    res.rollouts = 1;
    norm_ = (root.length < kUnreachable && root.length > 0.0) ? root.length : 1.0;
    record(root, res);
    setUntried(0, root);
    best_seq_.push_back(root.sequence);
    nodes_[0].visits = 1;
    nodes_[0].w = reward(root.length);
    if (nodes_[0].untried.empty()) return finish(res);

    for (int it = 0; it < std::max(1, c_.iterations); ++it) {
      int cur = 0;
      while (nodes_[cur].untried.empty() && !nodes_[cur].children.empty()) cur = selectChild(cur);
      if (nodes_[cur].untried.empty()) {  // complete sequence: its value is known
        backprop(cur, reward(nodes_[cur].prefix_len));
        continue;
      }
      const size_t take = (it == 0 && cur == 0) ? nodes_[cur].untried.size()
                                                : std::min<size_t>(c_.rollouts_per_iteration,
                                                                   nodes_[cur].untried.size());
      std::vector<int> fresh;
      for (size_t k = 0; k < take; ++k) {
        Node child;
        child.parent = cur;
        child.gp = nodes_[cur].untried[k];
        child.prefix_len = nodes_[cur].prefix_len + edge(nodes_[cur].gp, child.gp);
        nodes_.push_back(child);
        nodes_[cur].children.push_back(static_cast<int>(nodes_.size()) - 1);
        fresh.push_back(static_cast<int>(nodes_.size()) - 1);
      }
      nodes_[cur].untried.erase(nodes_[cur].untried.begin(), nodes_[cur].untried.begin() + take);
      std::vector<Rollout> outs(fresh.size());
      runParallel(fresh, outs);
      res.rollouts += static_cast<int>(fresh.size());
      for (size_t k = 0; k < fresh.size(); ++k) {
        record(outs[k], res);
        setUntried(fresh[k], outs[k]);
        best_seq_.push_back(outs[k].sequence);
        backprop(fresh[k], reward(outs[k].length));
      }
    }
    return finish(res);
  }

 private:
  double edge(int from, int to) const {
    if (from == 0 && !p_.exploring[to]) return kUnreachable;
    return p_.cost(from, to);
  }
  double reward(double len) const { return len < kUnreachable ? -len / norm_ : -100.0; }

  std::vector<int> prefix(int node) const {
    std::vector<int> r;
    for (int x = node; x > 0; x = nodes_[x].parent) r.push_back(nodes_[x].gp);
    std::reverse(r.begin(), r.end());
    return r;
  }

  // Completes the node's prefix with the ATSP solver. The parent's best completion minus this
  // node is the warm start: it is usually near optimal already, so few kicks suffice.
  Rollout rollout(int node, const std::vector<int>* parent_seq = nullptr) const {
    const std::vector<int> pre = prefix(node);
    std::vector<char> used(m_, 0);
    used[0] = 1;
    for (int g : pre) used[g] = 1;
    std::vector<int> idx{nodes_[node].gp};
    for (int g = 1; g < m_; ++g)
      if (!used[g]) idx.push_back(g);
    Rollout r;
    r.sequence = pre;
    const int k = static_cast<int>(idx.size());
    if (k == 1) {
      r.length = nodes_[node].prefix_len;
      return r;
    }
    CostMatrix sub(k);  // column 0 stays zero: the free return
    for (int i = 0; i < k; ++i)
      for (int j = 1; j < k; ++j)
        if (i != j) sub(i, j) = edge(idx[i], idx[j]);
    std::vector<int> warm;
    if (node == 0 && !root_warm_.empty()) {
      warm = root_warm_;  // the root's sub-problem is the whole problem: same node numbers
    } else if (parent_seq) {
      std::vector<int> local(m_, -1);
      for (int i = 0; i < k; ++i) local[idx[i]] = i;
      warm.push_back(0);
      for (int g : *parent_seq)
        if (!used[g]) warm.push_back(local[g]);
      if (static_cast<int>(warm.size()) != k) warm.clear();
    }
    const uint64_t seed = mix(seed_, node);
    // Only the root rollout runs outside the pool's jobs, so only its chains may use the pool.
    const AtspResult a =
        node == 0      ? root_solver_.solveOpenPath(sub, 0, AtspSolver::kFreeEnd, seed,
                                               warm.empty() ? nullptr : &warm, &parallel_)
        : warm.empty() ? root_solver_.solveOpenPath(sub, 0, AtspSolver::kFreeEnd, seed)
                       : solver_.solveOpenPath(sub, 0, AtspSolver::kFreeEnd, seed, &warm);
    for (size_t q = 1; q < a.order.size(); ++q) r.sequence.push_back(idx[a.order[q]]);
    r.length = nodes_[node].prefix_len + a.cost;
    return r;
  }

  void runJobs(int jobs, const std::function<void(int)>& fn) const {
    if (pool_ && jobs > 1) {
      pool_->run(jobs, fn);
    } else {
      for (int j = 0; j < jobs; ++j) fn(j);
    }
  }

  void runParallel(const std::vector<int>& fresh, std::vector<Rollout>& outs) const {
    runJobs(static_cast<int>(fresh.size()),
            [&](int k) { outs[k] = rollout(fresh[k], &best_seq_[nodes_[fresh[k]].parent]); });
  }

  // Children in expansion order: the rollout's next guidepoint first, then cheapest edges.
  void setUntried(int node, const Rollout& r) {
    std::vector<char> used(m_, 0);
    used[0] = 1;
    for (int x = node; x > 0; x = nodes_[x].parent) used[nodes_[x].gp] = 1;
    const int from = nodes_[node].gp;
    std::vector<int> cand;
    for (int g = 1; g < m_; ++g)
      if (!used[g] && (from != 0 || p_.exploring[g])) cand.push_back(g);
    std::stable_sort(cand.begin(), cand.end(),
                     [&](int a, int b) { return edge(from, a) < edge(from, b); });
    const size_t depth = prefix(node).size();
    if (r.sequence.size() > depth) {
      const auto it = std::find(cand.begin(), cand.end(), r.sequence[depth]);
      if (it != cand.end()) std::rotate(cand.begin(), it, it + 1);
    }
    nodes_[node].untried = cand;
  }

  int selectChild(int node) const {
    const Node& n = nodes_[node];
    const double ln = std::log(std::max(1, n.visits));
    int best = n.children.front();
    double best_v = -std::numeric_limits<double>::infinity();
    for (int ch : n.children) {
      const Node& c = nodes_[ch];
      const double v = c.w / c.visits + c_.exploration_constant * std::sqrt(ln / c.visits);
      if (v > best_v) best_v = v, best = ch;
    }
    return best;
  }

  void backprop(int node, double rew) {
    for (int x = node; x >= 0; x = nodes_[x].parent) {
      nodes_[x].visits += 1;
      nodes_[x].w += rew;
      if (x == 0) break;
    }
  }

  void record(const Rollout& r, MctsResult& res) const {
    if (r.sequence.empty() || !(r.length < kUnreachable)) return;
    const int first = r.sequence.front();
    if (r.length < res.best_length_by_first[first]) {
      res.best_length_by_first[first] = r.length;
      res.best_sequence_by_first[first] = r.sequence;
    }
    if (r.length < res.length) res.length = r.length, res.sequence = r.sequence;
  }

  MctsResult finish(MctsResult& res) const {
    res.feasible = !res.sequence.empty() && res.length < kUnreachable;
    res.tree_nodes = static_cast<int>(nodes_.size());
    return res;
  }

  const MctsProblem& p_;
  const MctsConfig& c_;
  uint64_t seed_;
  RolloutPool* pool_;
  std::vector<int> root_warm_;
  int m_;
  AtspSolver solver_, root_solver_;
  ParallelFor parallel_;
  std::vector<Node> nodes_;
  std::vector<std::vector<int>> best_seq_;  // per tree node: its rollout's full sequence
  double norm_ = 1.0;
};

// warmRootOrder of a problem already checked: solve() checks it once (an O(n^2) pass).
std::vector<int> warmRootOrderOfChecked(const MctsProblem& p, const std::vector<int>& previous) {
  const int m = p.cost.size();
  std::vector<char> in(m, 0);
  in[0] = 1;
  std::vector<int> path{0};
  for (int g : previous)
    if (g > 0 && g < m && !in[g]) in[g] = 1, path.push_back(g);
  if (path.size() == 1) return {};
  // Cheapest insertion of the rest, never before the first (the root's edge is priced only
  // for exploring guidepoints); the return to the robot is free, so the end costs only the
  // edge into g. An unreachable edge makes its slot infinite (or NaN), never the cheapest.
  for (int g = 1; g < m; ++g) {
    if (in[g]) continue;
    size_t best_pos = path.size();
    double best = p.cost(path.back(), g);
    for (size_t q = 2; q < path.size(); ++q) {
      const double d = p.cost(path[q - 1], g) + p.cost(g, path[q]) - p.cost(path[q - 1], path[q]);
      if (d < best) best = d, best_pos = q;
    }
    path.insert(path.begin() + static_cast<std::ptrdiff_t>(best_pos), g);
    in[g] = 1;
  }
  // The first exploring one leads; the rest keep their order.
  const auto lead =
      std::find_if(path.begin() + 1, path.end(), [&](int g) { return p.exploring[g]; });
  if (lead == path.end()) return {};
  std::rotate(path.begin() + 1, lead, lead + 1);
  return path;
}

}  // namespace

MctsSequencer::MctsSequencer(MctsConfig config) : config_(config) {
  config_.validate();
  if (config_.threads > 1) pool_ = std::make_shared<RolloutPool>(config_.threads - 1);
}

MctsResult MctsSequencer::solve(const MctsProblem& problem, uint64_t seed,
                                const std::vector<int>* root_warm) const {
  checkProblem(problem);
  return Search(problem, config_, seed, pool_.get(),
                root_warm ? warmRootOrderOfChecked(problem, *root_warm) : std::vector<int>{})
      .run();
}

std::vector<int> warmRootOrder(const MctsProblem& p, const std::vector<int>& previous) {
  checkProblem(p);
  return warmRootOrderOfChecked(p, previous);
}

MctsResult initialMctsResult(int nodes) {
  MctsResult res;
  res.best_length_by_first.assign(nodes, kUnreachable);
  res.best_sequence_by_first.assign(nodes, {});
  if (nodes == 1) {
    res.length = 0.0;
    res.feasible = true;
  }
  return res;
}

MctsResult solveSequenceExhaustive(const MctsProblem& p) {
  checkProblem(p);
  const int m = p.cost.size();
  if (m > 10) throw std::invalid_argument("solveSequenceExhaustive: more than 9 guidepoints");
  MctsResult res = initialMctsResult(m);
  if (m == 1) return res;
  std::vector<int> s(m - 1);
  std::iota(s.begin(), s.end(), 1);
  do {
    if (!p.exploring[s[0]]) continue;
    double len = p.cost(0, s[0]);
    for (size_t k = 0; k + 1 < s.size(); ++k) len += p.cost(s[k], s[k + 1]);
    if (len < res.best_length_by_first[s[0]])
      res.best_length_by_first[s[0]] = len, res.best_sequence_by_first[s[0]] = s;
    if (len < res.length) res.length = len, res.sequence = s;
  } while (std::next_permutation(s.begin(), s.end()));
  res.feasible = res.length < kUnreachable;
  return res;
}

}  // namespace efs::planner
