// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/world_sketch.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <deque>
#include <fstream>
#include <iomanip>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

#include "efs_common/config_check.h"
#include "marsim_worlds/seeded_random.h"

namespace efs::sim {
namespace {

constexpr uint8_t kInk = 0;
constexpr uint8_t kPaper = 255;

Eigen::Matrix2d rotation(double yaw) { return Eigen::Rotation2Dd(yaw).toRotationMatrix(); }

/// Coarse (about 1 m) free-space cells with their BFS distance from the start, for picking
/// "topological regions" to leave out of a partial sketch.
struct CoarseFreeMap {
  int factor = 1, nx = 0, ny = 0;
  std::vector<uint8_t> free;
  std::vector<int> dist;  // -1: unreachable
  int index(int x, int y) const { return y * nx + x; }
};

CoarseFreeMap coarseFreeMap(const VoxelWorld& world, const std::vector<uint8_t>& free_cols) {
  CoarseFreeMap m;
  m.factor = std::max(1, static_cast<int>(std::lround(1.0 / world.resolution())));
  const int fx = world.dimsVoxels().x(), fy = world.dimsVoxels().y();
  m.nx = (fx + m.factor - 1) / m.factor;
  m.ny = (fy + m.factor - 1) / m.factor;
  m.free.assign(static_cast<size_t>(m.nx) * m.ny, 0);
  m.dist.assign(m.free.size(), -1);
  const Eigen::AlignedBox3d box = world.bounds();
  for (int y = 0; y < fy; ++y) {
    for (int x = 0; x < fx; ++x) {
      if (!free_cols[static_cast<size_t>(y) * fx + x]) continue;
      const Eigen::Vector3d c = world.voxelCenter({x, y, 0});
      if (c.x() < box.min().x() || c.x() > box.max().x() || c.y() < box.min().y() ||
          c.y() > box.max().y()) {
        continue;
      }
      m.free[static_cast<size_t>(m.index(x / m.factor, y / m.factor))] = 1;
    }
  }
  if (world.start_poses.empty()) return m;
  const Eigen::Vector3i s = world.voxelOf(world.start_poses.front().position_m);
  const int sx = std::clamp(s.x() / m.factor, 0, m.nx - 1),
            sy = std::clamp(s.y() / m.factor, 0, m.ny - 1);
  std::deque<int> queue;
  if (m.free[static_cast<size_t>(m.index(sx, sy))]) {
    m.dist[static_cast<size_t>(m.index(sx, sy))] = 0;
    queue.push_back(m.index(sx, sy));
  }
  while (!queue.empty()) {
    const int i = queue.front();
    queue.pop_front();
    const int x = i % m.nx, y = i / m.nx;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= m.nx || yy >= m.ny) continue;
        const int j = m.index(xx, yy);
        if (!m.free[static_cast<size_t>(j)] || m.dist[static_cast<size_t>(j)] >= 0) continue;
        m.dist[static_cast<size_t>(j)] = m.dist[static_cast<size_t>(i)] + 1;
        queue.push_back(j);
      }
    }
  }
  return m;
}

/// Coarse cells (incl. a 2-cell rim for the walls) of `regions` geodesic balls away from the start.
std::vector<uint8_t> partialRemoval(const CoarseFreeMap& m, int regions, double fraction,
                                    SeededRandom& rng) {
  std::vector<uint8_t> removed(m.free.size(), 0);
  const int max_d = *std::max_element(m.dist.begin(), m.dist.end());
  if (max_d <= 0) return removed;
  const int radius = std::max(2, static_cast<int>(std::lround(fraction * max_d)));
  std::vector<int> candidates;
  for (size_t i = 0; i < m.dist.size(); ++i) {
    if (m.dist[i] > std::max(radius + 3, static_cast<int>(0.3 * max_d))) {
      candidates.push_back(static_cast<int>(i));
    }
  }
  for (int r = 0; r < regions && !candidates.empty(); ++r) {
    const int seed = candidates[rng.index(candidates.size())];
    std::vector<int> local(m.free.size(), -1);
    std::deque<int> queue{seed};
    local[static_cast<size_t>(seed)] = 0;
    while (!queue.empty()) {
      const int i = queue.front();
      queue.pop_front();
      removed[static_cast<size_t>(i)] = 1;
      if (local[static_cast<size_t>(i)] >= radius) continue;
      const int x = i % m.nx, y = i / m.nx;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= m.nx || yy >= m.ny) continue;
          const int j = m.index(xx, yy);
          if (!m.free[static_cast<size_t>(j)] || local[static_cast<size_t>(j)] >= 0) continue;
          local[static_cast<size_t>(j)] = local[static_cast<size_t>(i)] + 1;
          queue.push_back(j);
        }
      }
    }
  }
  // Grow by two cells so that the walls bounding the removed free space go too.
  std::vector<uint8_t> grown = removed;
  for (int y = 0; y < m.ny; ++y) {
    for (int x = 0; x < m.nx; ++x) {
      if (!removed[static_cast<size_t>(m.index(x, y))]) continue;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx >= 0 && yy >= 0 && xx < m.nx && yy < m.ny)
            grown[static_cast<size_t>(m.index(xx, yy))] = 1;
        }
    }
  }
  return grown;
}

/// Least-squares 2D similarity mapping src onto dst (closed form for 2D).
Sim2 fitSimilarity(const std::vector<Eigen::Vector2d>& src,
                   const std::vector<Eigen::Vector2d>& dst) {
  Eigen::Vector2d ms = Eigen::Vector2d::Zero(), md = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < src.size(); ++i) {
    ms += src[i];
    md += dst[i];
  }
  ms /= static_cast<double>(src.size());
  md /= static_cast<double>(src.size());
  double sxx = 0.0, sxy = 0.0, norm = 0.0;
  for (size_t i = 0; i < src.size(); ++i) {
    const Eigen::Vector2d a = src[i] - ms, b = dst[i] - md;
    sxx += a.dot(b);
    sxy += a.x() * b.y() - a.y() * b.x();
    norm += a.squaredNorm();
  }
  const double yaw = std::atan2(sxy, sxx);
  const double scale = norm > 0.0 ? std::hypot(sxx, sxy) / norm : 1.0;
  const Eigen::Vector2d t = md - scale * (rotation(yaw) * ms);
  return Sim2(yaw, scale, t);
}

uint64_t variantSalt(SketchVariant v) {
  return 0xA5A5ULL + 0x1000193ULL * static_cast<uint64_t>(v);
}

}  // namespace

std::string sketchVariantName(SketchVariant v) {
  switch (v) {
    case SketchVariant::kPrecise:
      return "precise";
    case SketchVariant::kPartial:
      return "partial";
    case SketchVariant::kDeformed:
      return "deformed";
    case SketchVariant::kScaled:
      return "scaled";
  }
  return "unknown";
}

SketchVariant parseSketchVariant(const std::string& name) {
  for (SketchVariant v : {SketchVariant::kPrecise, SketchVariant::kPartial,
                          SketchVariant::kDeformed, SketchVariant::kScaled}) {
    if (sketchVariantName(v) == name) return v;
  }
  throw std::invalid_argument("unknown sketch variant '" + name +
                              "' (expected precise, partial, deformed or scaled)");
}

void SketchConfig::validate() const {
  requireInRange("metres_per_pixel", metres_per_pixel, 1e-3, 100.0);
  requireInRange("min_true_mpp", min_true_mpp, 1e-3, 100.0);
  requireInRange("max_true_mpp", max_true_mpp, min_true_mpp, 100.0);
  requireInRange("max_image_px", max_image_px, 64, 65000);
  requireInRange("line_width_px", line_width_px, 0.5, 50.0);
  requireInRange("min_margin_px", min_margin_px, 0, 10000);
  requireInRange("max_margin_px", max_margin_px, min_margin_px, 10000);
  requireInRange("partial_regions", partial_regions, 0, 100);
  requireInRange("partial_region_fraction", partial_region_fraction, 0.0, 1.0);
  requireInRange("deform_amplitude_fraction", deform_amplitude_fraction, 0.0, 0.5);
  requireInRange("deform_max_m", deform_max_m, 0.0, 1000.0);
  requireInRange("anisotropy", anisotropy, 0.0, 0.5);
  requireInRange("jitter_px", jitter_px, 0.0, 20.0);
  requireInRange("thickness_variation", thickness_variation, 0.0, 0.9);
  requireInRange("scaled_factor", scaled_factor, 0.1, 10.0);
}

Eigen::Vector2d Sketch::pixelToSketch(const Eigen::Vector2d& uv) const {
  return {(uv.x() + 0.5) * metres_per_pixel, (image.rows - uv.y() - 0.5) * metres_per_pixel};
}

Eigen::Vector2d Sketch::sketchToPixel(const Eigen::Vector2d& p) const {
  return {p.x() / metres_per_pixel, image.rows - p.y() / metres_per_pixel};
}

bool Sketch::inkAt(const Eigen::Vector2d& uv) const {
  const int u = static_cast<int>(std::floor(uv.x())), v = static_cast<int>(std::floor(uv.y()));
  if (u < 0 || v < 0 || u >= image.cols || v >= image.rows) return false;
  return image.at<uint8_t>(v, u) < 128;
}

std::vector<Eigen::Vector2d> wallPoints(const VoxelWorld& world, const SketchBand& band) {
  const std::vector<uint8_t> free_cols = world.freeColumns(band.z_min_m, band.z_max_m);
  const int nx = world.dimsVoxels().x(), ny = world.dimsVoxels().y();
  std::vector<Eigen::Vector2d> out;
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      if (free_cols[static_cast<size_t>(y) * nx + x]) continue;
      bool wall = false;
      for (int dy = -1; dy <= 1 && !wall; ++dy) {
        for (int dx = -1; dx <= 1 && !wall; ++dx) {
          const int xx = x + dx, yy = y + dy;
          wall = xx >= 0 && yy >= 0 && xx < nx && yy < ny &&
                 free_cols[static_cast<size_t>(yy) * nx + xx];
        }
      }
      if (wall) out.push_back(world.voxelCenter({x, y, 0}).head<2>());
    }
  }
  return out;
}

Sketch drawSketch(const VoxelWorld& world, SketchVariant variant, const SketchConfig& cfg) {
  cfg.validate();
  SeededRandom rng(cfg.seed ^ variantSalt(variant));
  Sketch sk;
  sk.variant = variant;
  sk.world_name = world.name;
  sk.seed = cfg.seed;
  sk.metres_per_pixel = cfg.metres_per_pixel;
  sk.band = world.sketch_band;

  const std::vector<uint8_t> free_cols = world.freeColumns(sk.band.z_min_m, sk.band.z_max_m);
  std::vector<Eigen::Vector2d> walls = wallPoints(world, sk.band);
  if (walls.empty()) {
    throw std::invalid_argument("drawSketch: world '" + world.name +
                                "' has no walls in the band [" + std::to_string(sk.band.z_min_m) +
                                ", " + std::to_string(sk.band.z_max_m) + "] m");
  }
  std::vector<uint8_t> keep(walls.size(), 1);

  if (variant == SketchVariant::kPartial) {
    const CoarseFreeMap coarse = coarseFreeMap(world, free_cols);
    SeededRandom region_rng = rng.fork(1);
    const std::vector<uint8_t> removed =
        partialRemoval(coarse, cfg.partial_regions, cfg.partial_region_fraction, region_rng);
    for (size_t i = 0; i < walls.size(); ++i) {
      const Eigen::Vector3i v = world.voxelOf({walls[i].x(), walls[i].y(), world.origin().z()});
      const int cx = v.x() / coarse.factor, cy = v.y() / coarse.factor;
      if (removed[static_cast<size_t>(coarse.index(cx, cy))]) keep[i] = 0;
    }
  }

  // Line width per wall point (thickening / thinning varies smoothly over the drawing).
  std::vector<float> radius_px(walls.size(), static_cast<float>(0.5 * cfg.line_width_px));
  std::vector<Eigen::Vector2d> drawn = walls;
  Eigen::AlignedBox2d wall_box;
  for (const auto& p : walls) wall_box.extend(p);
  const double diag = wall_box.diagonal().norm();

  if (variant == SketchVariant::kDeformed) {
    const Eigen::Vector2d c = wall_box.center();
    const double ax = 1.0 + rng.uniform(-cfg.anisotropy, cfg.anisotropy);
    const Eigen::Vector2d aniso(ax, 1.0 / ax);
    const double amp = std::min(cfg.deform_amplitude_fraction * diag, cfg.deform_max_m);
    const ValueNoise warp_x(rng.next(), std::max(diag / 3.0, 1.0), 1);
    const ValueNoise warp_y(rng.next(), std::max(diag / 3.0, 1.0), 1);
    const ValueNoise thick(rng.next(), 8.0, 1);
    for (size_t i = 0; i < walls.size(); ++i) {
      const Eigen::Vector2d& p = walls[i];
      drawn[i] = c + aniso.cwiseProduct(p - c) +
                 amp * Eigen::Vector2d(warp_x(p.x(), p.y()), warp_y(p.x(), p.y()));
      radius_px[i] = static_cast<float>(std::max(
          0.5, 0.5 * cfg.line_width_px * (1.0 + cfg.thickness_variation * thick(p.x(), p.y()))));
    }
    // Take out the deformation's best-fit similarity so that T_world_sketch stays the best
    // similarity explanation of the drawing.
    const Sim2 fit = fitSimilarity(walls, drawn);
    const Sim2 undo = fit.inverse();
    for (auto& p : drawn) p = undo.apply(p);
  }

  double true_mpp = rng.uniform(cfg.min_true_mpp, cfg.max_true_mpp);
  if (variant == SketchVariant::kScaled) true_mpp /= cfg.scaled_factor;
  const double yaw = rng.uniform(-M_PI, M_PI);
  const Eigen::Matrix2d rot = rotation(yaw);
  Eigen::AlignedBox2d q_box;  // in metres of the world, rotated into the sketch's axes
  for (const auto& p : drawn) q_box.extend(rot.transpose() * p);
  const double longest_m = q_box.sizes().maxCoeff();
  const double longest_px_allowed = cfg.max_image_px - 2.0 * cfg.max_margin_px - 4.0;
  true_mpp = std::max(true_mpp, longest_m / std::max(longest_px_allowed, 16.0));
  const double s = true_mpp / cfg.metres_per_pixel;
  const int left =
      cfg.min_margin_px + static_cast<int>(rng.index(cfg.max_margin_px - cfg.min_margin_px + 1));
  const int right =
      cfg.min_margin_px + static_cast<int>(rng.index(cfg.max_margin_px - cfg.min_margin_px + 1));
  const int bottom =
      cfg.min_margin_px + static_cast<int>(rng.index(cfg.max_margin_px - cfg.min_margin_px + 1));
  const int top =
      cfg.min_margin_px + static_cast<int>(rng.index(cfg.max_margin_px - cfg.min_margin_px + 1));
  const int width = static_cast<int>(std::ceil(q_box.sizes().x() / true_mpp)) + left + right;
  const int height = static_cast<int>(std::ceil(q_box.sizes().y() / true_mpp)) + bottom + top;
  // p_sketch (frame units) = (R^T p_world) / s - offset  <=>  p_world = s R p_sketch + s R offset.
  const Eigen::Vector2d offset =
      q_box.min() / s - Eigen::Vector2d(left, bottom) * cfg.metres_per_pixel;
  sk.T_world_sketch = Sim2(yaw, s, s * (rot * offset));
  sk.image = cv::Mat(height, width, CV_8UC1, cv::Scalar(kPaper));

  const ValueNoise jitter_x(rng.next(), 1.5, 2), jitter_y(rng.next(), 1.5, 2);
  const Sim2 T_sketch_world = sk.T_world_sketch.inverse();
  for (size_t i = 0; i < drawn.size(); ++i) {
    if (!keep[i]) continue;
    const Eigen::Vector2d p_sketch = T_sketch_world.apply(drawn[i]);
    sk.drawn_walls.push_back({walls[i], p_sketch});
    Eigen::Vector2d uv = sk.sketchToPixel(p_sketch);
    if (variant == SketchVariant::kDeformed) {
      uv += cfg.jitter_px * Eigen::Vector2d(jitter_x(walls[i].x(), walls[i].y()),
                                            jitter_y(walls[i].x(), walls[i].y()));
    }
    const double r = radius_px[i];
    const int u0 = static_cast<int>(std::floor(uv.x() - r)),
              u1 = static_cast<int>(std::floor(uv.x() + r));
    const int v0 = static_cast<int>(std::floor(uv.y() - r)),
              v1 = static_cast<int>(std::floor(uv.y() + r));
    for (int v = std::max(v0, 0); v <= std::min(v1, height - 1); ++v) {
      for (int u = std::max(u0, 0); u <= std::min(u1, width - 1); ++u) {
        const double du = u + 0.5 - uv.x(), dv = v + 0.5 - uv.y();
        if (du * du + dv * dv <= r * r) sk.image.at<uint8_t>(v, u) = kInk;
      }
    }
    // The pixel the wall point falls in is always inked, however thin the line.
    const int u = static_cast<int>(std::floor(uv.x())), v = static_cast<int>(std::floor(uv.y()));
    if (u >= 0 && v >= 0 && u < width && v < height) sk.image.at<uint8_t>(v, u) = kInk;
  }
  return sk;
}

std::string sidecarPath(const std::string& png_path) {
  const auto dot = png_path.find_last_of('.');
  const auto slash = png_path.find_last_of('/');
  const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  return (has_ext ? png_path.substr(0, dot) : png_path) + ".yaml";
}

std::string saveSketch(const Sketch& sk, const std::string& png_path) {
  if (!cv::imwrite(png_path, sk.image)) {
    throw std::runtime_error("saveSketch: cannot write image '" + png_path + "'");
  }
  const std::string yaml = sidecarPath(png_path);
  std::ofstream out(yaml);
  if (!out) throw std::runtime_error("saveSketch: cannot write sidecar '" + yaml + "'");
  const auto slash = png_path.find_last_of('/');
  out << std::setprecision(17);
  out << "# Sketch sidecar: ground truth for EVALUATION ONLY; the flight stack must not read it.\n"
      << "# Sketch frame: x right, y up, origin at the image's bottom-left corner, unit\n"
      << "# metres_per_pixel; pixel (u, v) (v = row from the top) has its centre at\n"
      << "# ((u + 0.5) * metres_per_pixel, (height_px - v - 0.5) * metres_per_pixel).\n"
      << "# T_world_sketch: p_world_xy = scale * R(yaw_rad) * p_sketch + (tx_m, ty_m).\n"
      << "image: " << (slash == std::string::npos ? png_path : png_path.substr(slash + 1)) << "\n"
      << "variant: " << sketchVariantName(sk.variant) << "\n"
      << "world: " << sk.world_name << "\n"
      << "seed: " << sk.seed << "\n"
      << "width_px: " << sk.image.cols << "\n"
      << "height_px: " << sk.image.rows << "\n"
      << "metres_per_pixel: " << sk.metres_per_pixel << "\n"
      << "true_metres_per_pixel: " << sk.trueMetresPerPixel() << "\n"
      << "band_z_min_m: " << sk.band.z_min_m << "\n"
      << "band_z_max_m: " << sk.band.z_max_m << "\n"
      << "T_world_sketch:\n"
      << "  yaw_rad: " << sk.T_world_sketch.yaw_rad << "\n"
      << "  scale: " << sk.T_world_sketch.scale << "\n"
      << "  tx_m: " << sk.T_world_sketch.t_m.x() << "\n"
      << "  ty_m: " << sk.T_world_sketch.t_m.y() << "\n"
      << "  reflected: " << (sk.T_world_sketch.reflected ? "true" : "false") << "\n";
  if (!out) throw std::runtime_error("saveSketch: error writing sidecar '" + yaml + "'");
  return yaml;
}

Sketch loadSketch(const std::string& png_path) {
  Sketch sk;
  sk.image = cv::imread(png_path, cv::IMREAD_GRAYSCALE);
  if (sk.image.empty())
    throw std::runtime_error("loadSketch: cannot read image '" + png_path + "'");
  const std::string yaml = sidecarPath(png_path);
  std::ifstream in(yaml);
  if (!in) throw std::runtime_error("loadSketch: cannot open sidecar '" + yaml + "'");
  std::map<std::string, std::string> kv;
  std::string line;
  while (std::getline(in, line)) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line = line.substr(0, hash);
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    auto trim = [](std::string t) {
      const auto b = t.find_first_not_of(" \t\r"), e = t.find_last_not_of(" \t\r");
      return b == std::string::npos ? std::string() : t.substr(b, e - b + 1);
    };
    const std::string key = trim(line.substr(0, colon)), value = trim(line.substr(colon + 1));
    if (!value.empty()) kv[key] = value;
  }
  auto get = [&](const std::string& key) -> const std::string& {
    const auto it = kv.find(key);
    if (it == kv.end())
      throw std::runtime_error("loadSketch: sidecar '" + yaml + "' lacks key '" + key + "'");
    return it->second;
  };
  auto number = [&](const std::string& key) {
    const std::string& text = get(key);
    try {
      size_t used = 0;
      const double v = std::stod(text, &used);
      if (used != text.size() || !std::isfinite(v)) throw std::invalid_argument(text);
      return v;
    } catch (const std::exception&) {
      throw std::runtime_error("loadSketch: sidecar '" + yaml + "' key '" + key +
                               "' is not a finite number: '" + text + "'");
    }
  };
  sk.variant = parseSketchVariant(get("variant"));
  sk.world_name = kv.count("world") ? kv["world"] : "";
  sk.seed = static_cast<uint64_t>(number("seed"));
  sk.metres_per_pixel = number("metres_per_pixel");
  if (!(sk.metres_per_pixel > 0.0)) {
    throw std::runtime_error("loadSketch: sidecar '" + yaml +
                             "' key 'metres_per_pixel' must be > 0");
  }
  sk.band = {number("band_z_min_m"), number("band_z_max_m")};
  sk.T_world_sketch =
      Sim2(number("yaw_rad"), number("scale"), Eigen::Vector2d(number("tx_m"), number("ty_m")),
           get("reflected") == "true");
  if (!(sk.T_world_sketch.scale > 0.0)) {
    throw std::runtime_error("loadSketch: sidecar '" + yaml + "' key 'scale' must be > 0");
  }
  if (number("width_px") != sk.image.cols || number("height_px") != sk.image.rows) {
    throw std::runtime_error("loadSketch: sidecar '" + yaml +
                             "' width_px/height_px do not match '" + png_path + "'");
  }
  return sk;
}

cv::Mat renderTopDown(const VoxelWorld& world, double mpp) {
  requirePositive("metres_per_pixel", mpp);
  const std::vector<uint8_t> free_cols =
      world.freeColumns(world.sketch_band.z_min_m, world.sketch_band.z_max_m);
  const int nx = world.dimsVoxels().x(), ny = world.dimsVoxels().y();
  const Eigen::AlignedBox3d grid = world.gridBox();
  const int w = std::max(1, static_cast<int>(std::ceil(grid.sizes().x() / mpp)));
  const int h = std::max(1, static_cast<int>(std::ceil(grid.sizes().y() / mpp)));
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(150, 150, 150));
  auto freeAt = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < nx && y < ny && free_cols[static_cast<size_t>(y) * nx + x];
  };
  const int reach = std::max(1, static_cast<int>(std::lround(mpp / world.resolution())));
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const Eigen::Vector3d p(grid.min().x() + (u + 0.5) * mpp, grid.max().y() - (v + 0.5) * mpp,
                              0.0);
      const Eigen::Vector3i c = world.voxelOf({p.x(), p.y(), world.origin().z()});
      if (freeAt(c.x(), c.y())) {
        img.at<cv::Vec3b>(v, u) = cv::Vec3b(255, 255, 255);
        continue;
      }
      bool near_free = false;
      for (int dy = -reach; dy <= reach && !near_free; ++dy)
        for (int dx = -reach; dx <= reach && !near_free; ++dx)
          near_free = freeAt(c.x() + dx, c.y() + dy);
      if (near_free) img.at<cv::Vec3b>(v, u) = cv::Vec3b(0, 0, 0);
    }
  }
  for (const StartPose& s : world.start_poses) {
    const cv::Point2d px = topDownPixel(world, mpp, s.position_m.head<2>());
    const double len = std::max(6.0, 2.0 / mpp);
    const cv::Point2d tip(px.x + len * std::cos(s.yaw_rad), px.y - len * std::sin(s.yaw_rad));
    cv::circle(img, px, std::max(3, static_cast<int>(len / 3)), cv::Scalar(0, 0, 255), -1);
    cv::arrowedLine(img, px, tip, cv::Scalar(0, 0, 255), 2);
  }
  return img;
}

cv::Point2d topDownPixel(const VoxelWorld& world, double metres_per_pixel,
                         const Eigen::Vector2d& p_world_xy) {
  const Eigen::AlignedBox3d grid = world.gridBox();
  return {(p_world_xy.x() - grid.min().x()) / metres_per_pixel,
          (grid.max().y() - p_world_xy.y()) / metres_per_pixel};
}

}  // namespace efs::sim
