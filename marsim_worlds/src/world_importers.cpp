// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/world_importers.h"

#include <tinyxml2.h>

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "efs_common/config_check.h"

namespace efs::sim {
namespace {

namespace fs = std::filesystem;
using Box3 = Eigen::AlignedBox3d;

struct OrientedBox {
  Eigen::Isometry3d T;  // box frame -> world, box centred at its origin
  Eigen::Vector3d half;
};
struct Cylinder {
  Eigen::Isometry3d T;  // axis along the frame's z
  double radius, half_length;
};
struct Sphere {
  Eigen::Vector3d centre;
  double radius;
};

/// Everything an importer found, in the world frame, before voxelisation.
struct Scene {
  std::string source;
  std::vector<OrientedBox> boxes;
  std::vector<Cylinder> cylinders;
  std::vector<Sphere> spheres;
  std::vector<Triangle> triangles;
  std::vector<Eigen::Vector3f> points;

  Box3 extent() const {
    Box3 b;
    for (const auto& o : boxes) {
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d corner((k & 1 ? 1 : -1) * o.half.x(), (k & 2 ? 1 : -1) * o.half.y(),
                                     (k & 4 ? 1 : -1) * o.half.z());
        b.extend(o.T * corner);
      }
    }
    for (const auto& c : cylinders) {
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d corner((k & 1 ? 1 : -1) * c.radius, (k & 2 ? 1 : -1) * c.radius,
                                     (k & 4 ? 1 : -1) * c.half_length);
        b.extend(c.T * corner);
      }
    }
    for (const auto& s : spheres) {
      b.extend(s.centre - Eigen::Vector3d::Constant(s.radius));
      b.extend(s.centre + Eigen::Vector3d::Constant(s.radius));
    }
    for (const auto& t : triangles) {
      b.extend(t.a);
      b.extend(t.b);
      b.extend(t.c);
    }
    for (const auto& p : points) b.extend(p.cast<double>());
    return b;
  }
};

Eigen::Isometry3d poseFromXyzRpy(const double v[6]) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  T.linear() = (Eigen::AngleAxisd(v[5], Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(v[4], Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return T;
}

class SdfReader {
 public:
  SdfReader(const std::string& path, const ImportConfig& cfg) : path_(path), cfg_(cfg) {}

  Scene read() {
    if (!fs::exists(path_)) throw std::runtime_error("SDF file '" + path_ + "' does not exist");
    tinyxml2::XMLDocument doc;
    if (doc.LoadFile(path_.c_str()) != tinyxml2::XML_SUCCESS) {
      throw std::runtime_error("cannot parse SDF '" + path_ + "': " + doc.ErrorStr());
    }
    const tinyxml2::XMLElement* root = doc.RootElement();
    if (!root || std::string(root->Name()) != "sdf") {
      throw std::runtime_error("SDF '" + path_ + "': root element is <" +
                               (root ? root->Name() : "none") + ">, expected <sdf>");
    }
    scene_.source = path_;
    for (const auto* world = root->FirstChildElement("world"); world;
         world = world->NextSiblingElement("world")) {
      if (cfg_.use_state_poses) readState(world);
      for (const auto* m = world->FirstChildElement("model"); m;
           m = m->NextSiblingElement("model")) {
        readModel(m, Eigen::Isometry3d::Identity(), "");
      }
    }
    for (const auto* m = root->FirstChildElement("model"); m; m = m->NextSiblingElement("model")) {
      readModel(m, Eigen::Isometry3d::Identity(), "");
    }
    return std::move(scene_);
  }

 private:
  std::string where(const tinyxml2::XMLElement* e) const {
    return "SDF '" + path_ + "' line " + std::to_string(e->GetLineNum());
  }

  Eigen::Isometry3d pose(const tinyxml2::XMLElement* parent) const {
    const tinyxml2::XMLElement* p = parent->FirstChildElement("pose");
    if (!p) return Eigen::Isometry3d::Identity();
    return parsePose(p);
  }

  Eigen::Isometry3d parsePose(const tinyxml2::XMLElement* p) const {
    double v[6] = {0, 0, 0, 0, 0, 0};
    parseNumbers(p, v, 6, "pose");
    return poseFromXyzRpy(v);
  }

  void parseNumbers(const tinyxml2::XMLElement* e, double* out, int n,
                    const std::string& what) const {
    std::istringstream in(e->GetText() ? e->GetText() : "");
    for (int i = 0; i < n; ++i) {
      if (!(in >> out[i]) || !std::isfinite(out[i])) {
        throw std::runtime_error(where(e) + ": <" + what + "> needs " + std::to_string(n) +
                                 " finite numbers, got '" + (e->GetText() ? e->GetText() : "") +
                                 "'");
      }
    }
    std::string rest;
    if (in >> rest) {
      throw std::runtime_error(where(e) + ": <" + what + "> has more than " + std::to_string(n) +
                               " numbers: '" + e->GetText() + "'");
    }
  }

  double number(const tinyxml2::XMLElement* parent, const char* key) const {
    const tinyxml2::XMLElement* e = parent->FirstChildElement(key);
    if (!e)
      throw std::runtime_error(where(parent) + ": <" + parent->Name() + "> lacks <" + key + ">");
    double v = 0.0;
    parseNumbers(e, &v, 1, key);
    return v;
  }

  void readState(const tinyxml2::XMLElement* world) {
    for (const auto* st = world->FirstChildElement("state"); st;
         st = st->NextSiblingElement("state")) {
      for (const auto* m = st->FirstChildElement("model"); m; m = m->NextSiblingElement("model")) {
        const char* name = m->Attribute("name");
        if (!name) continue;
        if (m->FirstChildElement("pose")) state_models_[name] = pose(m);
        for (const auto* l = m->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
          const char* lname = l->Attribute("name");
          if (lname && l->FirstChildElement("pose")) {
            state_links_[std::string(name) + "::" + lname] = pose(l);
          }
        }
      }
    }
  }

  void readModel(const tinyxml2::XMLElement* m, const Eigen::Isometry3d& T_parent,
                 const std::string& prefix) {
    const std::string name = prefix + (m->Attribute("name") ? m->Attribute("name") : "");
    Eigen::Isometry3d T_model = T_parent * pose(m);
    if (const auto it = state_models_.find(name); it != state_models_.end()) T_model = it->second;
    for (const auto* l = m->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
      const std::string lname = l->Attribute("name") ? l->Attribute("name") : "";
      Eigen::Isometry3d T_link = T_model * pose(l);
      if (const auto it = state_links_.find(name + "::" + lname); it != state_links_.end()) {
        T_link = it->second;
      }
      const char* kind = l->FirstChildElement("collision") ? "collision" : "visual";
      for (const auto* c = l->FirstChildElement(kind); c; c = c->NextSiblingElement(kind)) {
        const auto* g = c->FirstChildElement("geometry");
        if (g) readGeometry(g, T_link * pose(c));
      }
    }
    for (const auto* sub = m->FirstChildElement("model"); sub;
         sub = sub->NextSiblingElement("model")) {
      readModel(sub, T_model, name + "::");
    }
  }

  void readGeometry(const tinyxml2::XMLElement* g, const Eigen::Isometry3d& T) {
    if (const auto* box = g->FirstChildElement("box")) {
      const auto* size = box->FirstChildElement("size");
      if (!size) throw std::runtime_error(where(box) + ": <box> lacks <size>");
      double s[3];
      parseNumbers(size, s, 3, "size");
      if (!(s[0] >= 0 && s[1] >= 0 && s[2] >= 0)) {
        throw std::runtime_error(where(size) + ": <size> must not be negative");
      }
      scene_.boxes.push_back({T, 0.5 * Eigen::Vector3d(s[0], s[1], s[2])});
    } else if (const auto* cyl = g->FirstChildElement("cylinder")) {
      scene_.cylinders.push_back({T, number(cyl, "radius"), 0.5 * number(cyl, "length")});
    } else if (const auto* sph = g->FirstChildElement("sphere")) {
      scene_.spheres.push_back({T.translation(), number(sph, "radius")});
    } else if (const auto* mesh = g->FirstChildElement("mesh")) {
      const auto* uri = mesh->FirstChildElement("uri");
      if (!uri || !uri->GetText()) throw std::runtime_error(where(mesh) + ": <mesh> lacks <uri>");
      Eigen::Vector3d scale = Eigen::Vector3d::Ones();
      if (const auto* sc = mesh->FirstChildElement("scale"))
        parseNumbers(sc, scale.data(), 3, "scale");
      const std::string file = resolveUri(uri->GetText(), uri);
      const std::vector<Triangle> tris = loadMeshTriangles(file, T, scale);
      scene_.triangles.insert(scene_.triangles.end(), tris.begin(), tris.end());
    }
    // <plane> (ground planes) is represented by ImportConfig::add_floor.
  }

  std::string resolveUri(const std::string& uri, const tinyxml2::XMLElement* e) const {
    const fs::path dir = fs::path(path_).parent_path();
    std::vector<fs::path> candidates;
    const std::string model_prefix = "model://", file_prefix = "file://";
    if (uri.rfind(model_prefix, 0) == 0) {
      const std::string rest = uri.substr(model_prefix.size());
      const auto slash = rest.find('/');
      const std::string model = rest.substr(0, slash);
      const std::string inner = slash == std::string::npos ? "" : rest.substr(slash + 1);
      candidates = {dir / inner, dir / model / inner, dir / ".." / model / inner};
    } else if (uri.rfind(file_prefix, 0) == 0) {
      candidates = {fs::path(uri.substr(file_prefix.size()))};
    } else {
      candidates = {dir / uri, fs::path(uri)};
    }
    for (const auto& c : candidates) {
      if (fs::is_regular_file(c)) return c.string();
    }
    throw std::runtime_error(where(e) + ": mesh '" + uri + "' not found (looked in " +
                             candidates.front().string() + " and next to it)");
  }

  std::string path_;
  ImportConfig cfg_;
  Scene scene_;
  std::map<std::string, Eigen::Isometry3d> state_models_, state_links_;
};

void paintScene(const Scene& scene, int point_dilation_voxels, VoxelWorld& world) {
  const double h = 0.5 * world.resolution();
  auto forVoxels = [&](const Box3& box, auto&& occupied_if) {
    const Box3 clipped = box.intersection(world.gridBox());
    if (clipped.isEmpty()) return;
    const Eigen::Vector3i lo = world.voxelOf(clipped.min()).cwiseMax(0);
    const Eigen::Vector3i hi =
        world.voxelOf(clipped.max()).cwiseMin(world.dimsVoxels() - Eigen::Vector3i::Ones());
    for (int z = lo.z(); z <= hi.z(); ++z)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int x = lo.x(); x <= hi.x(); ++x) {
          const Eigen::Vector3i v(x, y, z);
          if (occupied_if(world.voxelCenter(v))) world.setVoxel(v, true);
        }
  };
  for (const OrientedBox& o : scene.boxes) {
    const Eigen::Matrix3d R = o.T.linear();
    // The box grown by the voxel's half-extent projected on each box axis: a separating-axis test
    // on the box's face normals, so every voxel the box touches is set (slightly more at corners).
    const Eigen::Vector3d grown = o.half + h * R.cwiseAbs().colwise().sum().transpose();
    const Eigen::Vector3d reach = R.cwiseAbs() * o.half + Eigen::Vector3d::Constant(h);
    const Eigen::Isometry3d inv = o.T.inverse();
    forVoxels(Box3(o.T.translation() - reach, o.T.translation() + reach),
              [&](const Eigen::Vector3d& c) {
                const Eigen::Vector3d q = inv * c;
                return (q.cwiseAbs().array() <= grown.array()).all();
              });
  }
  const double voxel_radius = h * std::sqrt(3.0);
  for (const Cylinder& cy : scene.cylinders) {
    const Eigen::Vector3d reach =
        cy.T.linear().cwiseAbs() * Eigen::Vector3d(cy.radius, cy.radius, cy.half_length) +
        Eigen::Vector3d::Constant(h);
    const Eigen::Isometry3d inv = cy.T.inverse();
    forVoxels(Box3(cy.T.translation() - reach, cy.T.translation() + reach),
              [&](const Eigen::Vector3d& c) {
                const Eigen::Vector3d q = inv * c;
                return q.head<2>().norm() <= cy.radius + voxel_radius &&
                       std::abs(q.z()) <= cy.half_length + voxel_radius;
              });
  }
  for (const Sphere& s : scene.spheres) {
    const Eigen::Vector3d reach = Eigen::Vector3d::Constant(s.radius + h);
    forVoxels(Box3(s.centre - reach, s.centre + reach), [&](const Eigen::Vector3d& c) {
      return (c - s.centre).norm() <= s.radius + voxel_radius;
    });
  }
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(h * (1.0 + 1e-6));
  // Triangles: walk the voxel columns along the axis the triangle faces most and test only the
  // few voxels of each column that the triangle's plane crosses (O(area), not O(bounding box)).
  const double res = world.resolution();
  const Eigen::Vector3d org = world.origin();
  const Eigen::Vector3i last = world.dimsVoxels() - Eigen::Vector3i::Ones();
  for (const Triangle& t : scene.triangles) {
    Box3 b;
    b.extend(t.a);
    b.extend(t.b);
    b.extend(t.c);
    b = Box3(b.min() - half, b.max() + half).intersection(world.gridBox());
    if (b.isEmpty()) continue;
    const Eigen::Vector3i lo = world.voxelOf(b.min()).cwiseMax(0);
    const Eigen::Vector3i hi = world.voxelOf(b.max()).cwiseMin(last);
    const Eigen::Vector3d n = (t.b - t.a).cross(t.c - t.a);
    int k = 0;
    n.cwiseAbs().maxCoeff(&k);
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const double nk = n[k], d = n.dot(t.a);
    // The triangle projected along k, with inward edge normals: a column whose (grown) footprint
    // lies outside one edge cannot touch the triangle. Skips most columns of long diagonal ones.
    const Eigen::Vector2d q[3] = {{t.a[i], t.a[j]}, {t.b[i], t.b[j]}, {t.c[i], t.c[j]}};
    const double orient =
        (q[1] - q[0]).x() * (q[2] - q[0]).y() - (q[1] - q[0]).y() * (q[2] - q[0]).x();
    Eigen::Vector2d edge_n[3];
    for (int e = 0; e < 3; ++e) {
      const Eigen::Vector2d ed = q[(e + 1) % 3] - q[e];
      edge_n[e] =
          orient >= 0.0 ? Eigen::Vector2d(-ed.y(), ed.x()) : Eigen::Vector2d(ed.y(), -ed.x());
    }
    const double reach = 0.5 * res + 1e-9;
    Eigen::Vector3i v;
    for (v[i] = lo[i]; v[i] <= hi[i]; ++v[i]) {
      for (v[j] = lo[j]; v[j] <= hi[j]; ++v[j]) {
        const Eigen::Vector2d centre(org[i] + (v[i] + 0.5) * res, org[j] + (v[j] + 0.5) * res);
        bool outside = false;
        for (int e = 0; e < 3 && !outside && std::abs(orient) > 1e-18; ++e) {
          outside = edge_n[e].dot(centre - q[e]) + reach * edge_n[e].cwiseAbs().sum() < 0.0;
        }
        if (outside) continue;
        int k0 = lo[k], k1 = hi[k];
        if (std::abs(nk) > 1e-12) {
          // The plane's k-range over this column's footprint (corners of the cell rectangle).
          const double pi0 = org[i] + v[i] * res, pj0 = org[j] + v[j] * res;
          double kmin = std::numeric_limits<double>::infinity(), kmax = -kmin;
          for (int c = 0; c < 4; ++c) {
            const double pi = pi0 + (c & 1 ? res : 0.0), pj = pj0 + (c & 2 ? res : 0.0);
            const double pk = (d - n[i] * pi - n[j] * pj) / nk;
            kmin = std::min(kmin, pk);
            kmax = std::max(kmax, pk);
          }
          k0 = std::max(k0, static_cast<int>(std::floor((kmin - org[k]) / res)) - 1);
          k1 = std::min(k1, static_cast<int>(std::floor((kmax - org[k]) / res)) + 1);
        }
        for (v[k] = k0; v[k] <= k1; ++v[k]) {
          if (triangleOverlapsBox(world.voxelCenter(v), half, t)) world.setVoxel(v, true);
        }
      }
    }
  }
  // Points mark their voxel; dilation closes the gaps between a cloud's samples.
  const int d = point_dilation_voxels;
  for (const Eigen::Vector3f& p : scene.points) {
    const Eigen::Vector3i v = world.voxelOf(p.cast<double>());
    for (int dz = -d; dz <= d; ++dz)
      for (int dy = -d; dy <= d; ++dy)
        for (int dx = -d; dx <= d; ++dx) world.setVoxel(v + Eigen::Vector3i(dx, dy, dz), true);
  }
}

/// Deterministic start: in the largest connected free region at the start height that does not
/// reach the grid's border (the inside of the building or mine, not the open space around it,
/// nor the hollow inside of a meshed rock pillar), clear of obstacles, with the most room (to
/// 2 m), closest to the centre of the exploration box.
StartPose pickStart(const VoxelWorld& world, const ImportConfig& cfg) {
  const Box3 box = world.bounds();
  const double z = box.min().z() + std::min(cfg.start_height_m, 0.5 * box.sizes().z());
  const int vz = world.voxelOf({box.min().x(), box.min().y(), z}).z();
  const int nx = world.dimsVoxels().x(), ny = world.dimsVoxels().y();
  std::vector<int> label(static_cast<size_t>(nx) * ny, -1);
  std::vector<size_t> sizes;
  std::vector<uint8_t> touches_border;
  std::vector<int> stack;
  for (int y0 = 0; y0 < ny; ++y0) {
    for (int x0 = 0; x0 < nx; ++x0) {
      const size_t i0 = static_cast<size_t>(y0) * nx + x0;
      if (label[i0] >= 0 || world.occupied({x0, y0, vz})) continue;
      const int id = static_cast<int>(sizes.size());
      sizes.push_back(0);
      touches_border.push_back(0);
      label[i0] = id;
      stack.assign(1, static_cast<int>(i0));
      while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        const int x = i % nx, y = i / nx;
        ++sizes[static_cast<size_t>(id)];
        if (x == 0 || y == 0 || x == nx - 1 || y == ny - 1)
          touches_border[static_cast<size_t>(id)] = 1;
        const int nb[4][2] = {{x + 1, y}, {x - 1, y}, {x, y + 1}, {x, y - 1}};
        for (const auto& n : nb) {
          if (n[0] < 0 || n[1] < 0 || n[0] >= nx || n[1] >= ny) continue;
          const size_t j = static_cast<size_t>(n[1]) * nx + n[0];
          if (label[j] >= 0 || world.occupied({n[0], n[1], vz})) continue;
          label[j] = id;
          stack.push_back(static_cast<int>(j));
        }
      }
    }
  }
  int inside = -1;
  for (size_t id = 0; id < sizes.size(); ++id) {
    if (!touches_border[id] && (inside < 0 || sizes[id] > sizes[static_cast<size_t>(inside)])) {
      inside = static_cast<int>(id);
    }
  }
  const double step = std::max(0.5, std::max(box.sizes().x(), box.sizes().y()) / 150.0);
  const Eigen::Vector2d centre = box.center().head<2>();
  double best_room = -1.0, best_dist = 0.0;
  StartPose best;
  for (double y = box.min().y() + 0.5 * step; inside >= 0 && y < box.max().y(); y += step) {
    for (double x = box.min().x() + 0.5 * step; x < box.max().x(); x += step) {
      const Eigen::Vector3d p(x, y, z);
      const Eigen::Vector3i v = world.voxelOf(p);
      if (!world.inGrid(v) || label[static_cast<size_t>(v.y()) * nx + v.x()] != inside) continue;
      if (world.collides(p, cfg.start_clearance_m)) continue;
      const double room = std::floor(world.clearance(p, 2.0) / world.resolution());
      const double dist = (p.head<2>() - centre).norm();
      if (room > best_room || (room == best_room && dist < best_dist)) {
        best_room = room;
        best_dist = dist;
        best.position_m = p;
      }
    }
  }
  if (best_room < 0.0) {
    throw std::runtime_error("world '" + world.name + "': no enclosed start position with " +
                             std::to_string(cfg.start_clearance_m) +
                             " m clearance found; give one in ImportConfig::start");
  }
  return best;
}

VoxelWorld buildWorld(const Scene& scene, const ImportConfig& cfg, const std::string& name) {
  const Box3 extent = scene.extent();
  if (extent.isEmpty()) {
    throw std::runtime_error("'" + scene.source + "' contains no geometry to import");
  }
  const double t = cfg.slab_thickness_m;
  const Eigen::Vector3d pad(cfg.margin_m, cfg.margin_m,
                            std::max(t, cfg.resolution_m) + cfg.resolution_m);
  Box3 grid_extent(extent.min() - pad, extent.max() + pad);
  if (cfg.add_ceiling)
    grid_extent = alignBrickBoundary(grid_extent, extent.max().z(), cfg.resolution_m);
  VoxelWorld world(grid_extent, cfg.resolution_m);
  world.name = name;
  world.setExplorationBox(extent);
  paintScene(scene, cfg.pcd_dilate_voxels, world);
  if (cfg.add_floor) {
    world.fillBox(Box3(Eigen::Vector3d(world.gridBox().min().x(), world.gridBox().min().y(),
                                       extent.min().z() - t),
                       Eigen::Vector3d(world.gridBox().max().x(), world.gridBox().max().y(),
                                       extent.min().z())),
                  true);
  }
  if (cfg.add_ceiling) {
    world.fillBox(Box3(Eigen::Vector3d(world.gridBox().min().x(), world.gridBox().min().y(),
                                       extent.max().z()),
                       Eigen::Vector3d(world.gridBox().max().x(), world.gridBox().max().y(),
                                       std::max(extent.max().z() + t, world.gridBox().max().z()))),
                  true);
  }
  world.compact();
  const double band_lo = extent.min().z() + std::min(1.0, 0.3 * extent.sizes().z());
  const double band_hi = extent.min().z() + std::min(1.8, 0.7 * extent.sizes().z());
  world.sketch_band = {band_lo, band_hi};
  world.start_poses = {cfg.has_start ? cfg.start : pickStart(world, cfg)};
  world.validateStartPoses(cfg.start_clearance_m);
  return world;
}

std::string stem(const std::string& path) { return fs::path(path).stem().string(); }

}  // namespace

void ImportConfig::validate() const {
  requireInRange("resolution_m", resolution_m, 0.02, 2.0);
  requireInRange("slab_thickness_m", slab_thickness_m, 0.0, 10.0);
  requireInRange("margin_m", margin_m, 0.0, 100.0);
  requireInRange("start_clearance_m", start_clearance_m, 0.0, 10.0);
  requireInRange("start_height_m", start_height_m, 0.0, 100.0);
  requireInRange("pcd_dilate_voxels", pcd_dilate_voxels, 0, 5);
  if (has_start) {
    requireThat(start.position_m.allFinite() && std::isfinite(start.yaw_rad), "start",
                "must be finite");
  }
}

bool triangleOverlapsBox(const Eigen::Vector3d& centre, const Eigen::Vector3d& half,
                         const Triangle& tri) {
  const Eigen::Vector3d v[3] = {tri.a - centre, tri.b - centre, tri.c - centre};
  // 1) the box's face normals: the triangle's bounding box against the box
  for (int a = 0; a < 3; ++a) {
    const double lo = std::min({v[0][a], v[1][a], v[2][a]});
    const double hi = std::max({v[0][a], v[1][a], v[2][a]});
    if (lo > half[a] || hi < -half[a]) return false;
  }
  // 2) the triangle's plane against the box
  const Eigen::Vector3d e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  const Eigen::Vector3d n = e[0].cross(e[1]);
  const double r_plane = half.dot(n.cwiseAbs());
  if (std::abs(n.dot(v[0])) > r_plane) return false;
  // 3) the nine cross products of box axes and triangle edges
  for (int i = 0; i < 3; ++i) {
    for (int a = 0; a < 3; ++a) {
      const Eigen::Vector3d axis = Eigen::Vector3d::Unit(a).cross(e[i]);
      if (axis.squaredNorm() < 1e-18) continue;
      const double p0 = axis.dot(v[0]), p1 = axis.dot(v[1]), p2 = axis.dot(v[2]);
      const double r = half.dot(axis.cwiseAbs());
      if (std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r) return false;
    }
  }
  return true;
}

std::vector<Triangle> loadMeshTriangles(const std::string& path, const Eigen::Isometry3d& T,
                                        const Eigen::Vector3d& scale) {
  if (!fs::is_regular_file(path))
    throw std::runtime_error("mesh file '" + path + "' does not exist");
  Assimp::Importer importer;
  // Gazebo reads COLLADA coordinates as they are; assimp would otherwise rotate Z_UP files.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                  aiProcess_JoinIdenticalVertices);
  if (!scene) {
    throw std::runtime_error("cannot read mesh '" + path + "': " + importer.GetErrorString());
  }
  std::vector<Triangle> out;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    auto vertex = [&](unsigned i) {
      const aiVector3D& p = mesh->mVertices[i];
      return T * Eigen::Vector3d(p.x * scale.x(), p.y * scale.y(), p.z * scale.z());
    };
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      Triangle t{vertex(face.mIndices[0]), vertex(face.mIndices[1]), vertex(face.mIndices[2])};
      if (t.a.allFinite() && t.b.allFinite() && t.c.allFinite()) out.push_back(t);
    }
  }
  if (out.empty()) throw std::runtime_error("mesh '" + path + "' has no triangles");
  return out;
}

VoxelWorld importSdfWorld(const std::string& sdf_path, const ImportConfig& cfg) {
  cfg.validate();
  const Scene scene = SdfReader(sdf_path, cfg).read();
  return buildWorld(scene, cfg, stem(sdf_path));
}

VoxelWorld importMeshWorld(const std::string& mesh_path, const Eigen::Isometry3d& T_world_mesh,
                           const ImportConfig& cfg) {
  cfg.validate();
  Scene scene;
  scene.source = mesh_path;
  scene.triangles = loadMeshTriangles(mesh_path, T_world_mesh);
  return buildWorld(scene, cfg, stem(mesh_path));
}

VoxelWorld importPcdWorld(const std::string& pcd_path, const ImportConfig& cfg) {
  cfg.validate();
  Scene scene;
  scene.source = pcd_path;
  scene.points = loadPcdPoints(pcd_path);
  if (scene.points.empty()) throw std::runtime_error("PCD '" + pcd_path + "' has no finite points");
  return buildWorld(scene, cfg, stem(pcd_path));
}

}  // namespace efs::sim
