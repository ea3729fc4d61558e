// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// se3_controller benchmark: time of one Se3Controller::update (target < 20 us) in tracking, hold
// and descent modes, over a figure-eight reference. Thread CPU time; prints a table.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <vector>

#include "se3_controller/se3_controller.h"

using namespace efs::control;

namespace {
double nowUs() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e6 + ts.tv_nsec * 1e-3;
}
double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}

FlatReference figureEight(double t) {
  const double A = 5.0, w = 3.0 / (A * std::sqrt(2.0));
  FlatReference r;
  r.stamp_s = t;
  r.p_world_m = {A * std::sin(w * t), 0.5 * A * std::sin(2 * w * t), 1.5};
  r.v_world_mps = {A * w * std::cos(w * t), A * w * std::cos(2 * w * t), 0};
  r.a_world_mps2 = {-A * w * w * std::sin(w * t), -2 * A * w * w * std::sin(2 * w * t), 0};
  r.j_world_mps3 = {-A * w * w * w * std::cos(w * t), -4 * A * w * w * w * std::cos(2 * w * t), 0};
  r.yaw_rad = std::atan2(r.v_world_mps.y(), r.v_world_mps.x());
  r.yaw_rate_radps = 0.3;
  return r;
}
}  // namespace

int main() {
  std::printf("Se3Controller::update (thread CPU time per call)\n");
  std::printf("| mode | calls | median [us] | p99 [us] | max [us] |\n|---|---|---|---|---|\n");
  struct Case {
    const char* name;
    double ref_delay_s, odom_delay_s;
  };
  double sink = 0;
  for (const Case& c : {Case{"tracking", 0.0, 0.0}, Case{"hold (stale reference)", 1.0, 0.0},
                        Case{"level descend (stale odometry)", 0.0, 1.0}}) {
    Se3Controller ctrl;
    std::vector<double> us;
    const int calls = 20000;
    us.reserve(calls);
    for (int k = 0; k < calls; ++k) {
      const double t = 0.01 * k;
      FlatReference r = figureEight(t - c.ref_delay_s);
      OdometryState o;
      o.stamp_s = t - c.odom_delay_s;
      o.p_world_m = r.p_world_m + Eigen::Vector3d(0.01, -0.02, 0.005);
      o.v_world_mps = r.v_world_mps;
      o.q_world_body = Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));
      o.omega_body_radps = Eigen::Vector3d(0.1, 0.0, 0.2);
      o.has_acceleration = true;
      const double t0 = nowUs();
      const ControlOutput out = ctrl.update(o, r, t);
      const double t1 = nowUs();
      us.push_back(t1 - t0);
      sink += out.so3.force_world_N.z();
    }
    std::printf("| %s | %d | %.2f | %.2f | %.2f |\n", c.name, calls, percentile(us, 0.5),
                percentile(us, 0.99), *std::max_element(us.begin(), us.end()));
  }
  std::printf("\n(target: median < 20 us; checksum %.1f)\n", sink);
  return 0;
}
