// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// se3_controller benchmark: time of one Se3Controller::update (target < 20 us) in tracking, hold
// and descent modes, over a figure-eight reference. Thread CPU time; prints a table.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <vector>

#include "se3_controller/reference_shapes.h"
#include "se3_controller/se3_controller.h"
#ifdef EFS_WITH_SIM_DYNAMICS
#include "sim_flight.h"
#endif

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

#ifdef EFS_WITH_SIM_DYNAMICS
// The closed-loop targets with the simulator's quadrotor (marsim_worlds), both outputs.
void closedLoopTable() {
  using testing::flySim;
  using testing::Output;
  const auto no_hook = [](double, efs::sim::QuadrotorDynamics&) {};
  std::printf("\nClosed loop with the simulator's quadrotor (controller 100 Hz, physics 500 Hz)\n");
  std::printf(
      "| output | figure-eight 3 m/s RMS [m] | max [m] | hover max [m] | kick 1 m/s max [m] "
      "| error 2 s after kick [m] |\n|---|---|---|---|---|---|\n");
  for (Output output : {Output::kSo3, Output::kAttitudeTarget}) {
    const FigureEight eight;
    Se3Controller c1;
    efs::sim::QuadrotorDynamics q1(efs::sim::QuadrotorConfig(),
                                   testing::stateOnReference(eight.at(0.0), 9.81));
    const auto f8 = flySim(
        c1, q1, [&](double t) { return eight.at(t); }, 0.0, eight.period() + 1.0, 1.0, output,
        no_hook);
    const Eigen::Vector3d target(0, 0, 1.5);
    const auto hover = [&](double t) { return hoverReference(target, 0.0, t); };
    efs::sim::QuadrotorState start;
    start.p_world_m = target + Eigen::Vector3d(0.02, -0.02, 0.02);
    Se3Controller c2;
    efs::sim::QuadrotorDynamics q2(efs::sim::QuadrotorConfig(), start);
    const auto h = flySim(c2, q2, hover, 0.0, 8.0, 0.0, output, no_hook);
    bool kicked = false;
    const auto kick = [&](double, efs::sim::QuadrotorDynamics& q) {
      if (kicked) return;
      efs::sim::QuadrotorState s = q.state();
      s.v_world_m_s += Eigen::Vector3d(1.0, 1.0, 0.0).normalized();
      q.setState(s);
      kicked = true;
    };
    const auto k = flySim(c2, q2, hover, 8.0, 2.0, 0.0, output, kick);
    std::printf("| %s | %.4f | %.4f | %.4f | %.4f | %.4f |\n",
                output == Output::kSo3 ? "SO3Command" : "AttitudeTarget", f8.rms_error_m,
                f8.max_error_m, h.max_error_m, k.max_error_m,
                (q2.state().p_world_m - target).norm());
  }
  std::printf("\n(targets: figure-eight RMS < 0.10 m, hover within 0.05 m, kick recovered)\n");
}
#endif

}  // namespace

int main() {
  std::printf("Se3Controller::update (thread CPU time per call)\n");
  std::printf("| mode | calls | median [us] | p99 [us] | max [us] |\n|---|---|---|---|---|\n");
  struct Case {
    const char* name;
    double ref_delay_s, odom_delay_s;
  };
  double sink = 0;
  const FigureEight eight;
  for (const Case& c : {Case{"tracking", 0.0, 0.0}, Case{"hold (stale reference)", 1.0, 0.0},
                        Case{"level descend (stale odometry)", 0.0, 1.0}}) {
    Se3Controller ctrl;
    std::vector<double> us;
    const int calls = 20000;
    us.reserve(calls);
    for (int k = 0; k < calls; ++k) {
      const double t = 0.01 * k;
      FlatReference r = eight.at(t - c.ref_delay_s);
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
#ifdef EFS_WITH_SIM_DYNAMICS
  closedLoopTable();
#endif
  return 0;
}
