// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "exploration_mission/mission_prior.h"

#include "prior_map_tools/sketch_loader.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>

namespace efs::mission {

MissionPrior prepareMissionPrior(const cv::Mat& sketch_image, double scale_guess_m_per_px,
                                 prior_map::PriorMapConfig config,
                                 const std::optional<Sim2>& truth_for_drawing_frame,
                                 double drawing_m_per_px, const std::string& description) {
  config.load.scale_guess_m_per_px = scale_guess_m_per_px;
  config.validate();
  const prior_map::LoadedSketch loaded =
      prior_map::sketchFromImage(sketch_image, config.load, description);
  MissionPrior prior;
  prior.bundle = prior_map::buildPriorBundle(loaded, config);
  prior.sketch_image = sketch_image.clone();
  prior.scale_guess_m_per_px = scale_guess_m_per_px;
  prior.description = description;
  if (truth_for_drawing_frame) {
    // Both frames share the image's bottom-left corner as origin; they differ by their unit only.
    const Sim2 T_drawing_bundle(0.0, drawing_m_per_px / scale_guess_m_per_px,
                                Eigen::Vector2d::Zero());
    prior.T_world_sketch_truth = (*truth_for_drawing_frame) * T_drawing_bundle;
  }
  return prior;
}

void saveTruth(const Sim2& T, const std::string& path) {
  std::ofstream f(path);
  f << std::setprecision(12)
    << "# True placement of the prior bundle's sketch frame in the simulated world (= the LIO\n"
       "# frame without drift): p_world_xy = scale * R(yaw) * p_sketch + t. Evaluation only.\n"
    << "T_world_sketch:\n"
    << "  yaw_rad: " << T.yaw_rad << "\n"
    << "  scale: " << T.scale << "\n"
    << "  tx_m: " << T.t_m.x() << "\n"
    << "  ty_m: " << T.t_m.y() << "\n"
    << "  reflected: " << (T.reflected ? "true" : "false") << "\n";
  if (!f) throw std::runtime_error("cannot write " + path);
}

Sim2 loadTruth(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot read");
  std::map<std::string, std::string> values;
  bool in_map = false;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (line.rfind("T_world_sketch:", 0) == 0) {
      in_map = true;
      continue;
    }
    const auto colon = line.find(':');
    if (!in_map || line[0] != ' ' || colon == std::string::npos) continue;
    std::istringstream key(line.substr(0, colon)), value(line.substr(colon + 1));
    std::string k, v;
    key >> k;
    value >> v;
    values[k] = v;
  }
  auto number = [&](const std::string& k) {
    const auto it = values.find(k);
    if (it == values.end()) throw std::runtime_error(path + ": no T_world_sketch/" + k);
    try {
      size_t used = 0;
      const double x = std::stod(it->second, &used);
      if (used == it->second.size() && std::isfinite(x)) return x;
    } catch (const std::exception&) {
    }
    throw std::runtime_error(path + ": T_world_sketch/" + k + " is not a finite number");
  };
  // One key at a time: the first missing one is the one named.
  const double yaw_rad = number("yaw_rad");
  const double scale = number("scale");
  const double tx_m = number("tx_m");
  const double ty_m = number("ty_m");
  Sim2 T(yaw_rad, scale, {tx_m, ty_m});
  const auto r = values.find("reflected");
  if (r == values.end() || (r->second != "true" && r->second != "false")) {
    throw std::runtime_error(path + ": T_world_sketch/reflected must be true or false");
  }
  T.reflected = r->second == "true";
  if (!(T.scale > 0.0)) throw std::runtime_error(path + ": T_world_sketch/scale must be > 0");
  return T;
}

}  // namespace efs::mission
