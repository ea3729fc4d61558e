// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/world_importers.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <utility>
#include <vector>

#include "efs_common/config_check.h"
#include "efs_common/testing/paths.h"
#include "marsim_worlds/world_sketch.h"

namespace efs::sim {
namespace {

std::string writeFile(const std::string& name, const std::string& content) {
  const std::string path = efs::testing::testOutputDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(WorldImporters, Ed21MatchesItsGroundTruthGrid) {
  ImportConfig cfg;
  cfg.resolution_m = 0.1;
  const VoxelWorld w = importSdfWorld(efs::testing::sharedDataPath("ed21/ed21.world"), cfg);
  EXPECT_EQ(w.name, "ed21");
  // Walls are 2.5 m high; the building spans about 45 x 38.5 m once Gazebo's <state> poses apply.
  const Eigen::AlignedBox3d b = w.bounds();
  EXPECT_NEAR(b.min().z(), 0.0, 1e-6);
  EXPECT_NEAR(b.max().z(), 2.5, 1e-6);
  EXPECT_NEAR(b.min().y(), -13.43, 0.05);
  EXPECT_NEAR(b.max().y(), 25.12, 0.05);
  EXPECT_NEAR(b.min().x(), -19.91, 0.05);
  EXPECT_NEAR(b.max().x(), 25.36, 0.05);
  // Independent check against the map_server grid drawn from the same world (0.1 m, origin
  // -100, -100): nearly every wall cell of the import lies within 0.3 m of an occupied grid cell
  // (the grid's walls are offset by one or two cells here and there). The
  // grid lacks the small annex east of x = 20 m, so that part is left out.
  const cv::Mat grid =
      cv::imread(efs::testing::sharedDataPath("ed21/ground_truth_grid.pgm"), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(grid.empty());
  int total = 0, matched = 0;
  for (const Eigen::Vector2d& p : wallPoints(w, w.sketch_band)) {
    if (p.x() > 19.5) continue;
    const int u = static_cast<int>(std::floor((p.x() + 100.0) / 0.1));
    const int v = grid.rows - 1 - static_cast<int>(std::floor((p.y() + 100.0) / 0.1));
    bool hit = false;
    for (int dv = -3; dv <= 3 && !hit; ++dv)
      for (int du = -3; du <= 3 && !hit; ++du) hit = grid.at<uint8_t>(v + dv, u + du) < 100;
    ++total;
    matched += hit;
  }
  ASSERT_GT(total, 1000);
  EXPECT_GT(static_cast<double>(matched) / total, 0.95) << matched << " of " << total;
  // The picked start is inside the building with room around it.
  EXPECT_NO_THROW(w.validateStartPoses(cfg.start_clearance_m));
}

TEST(WorldImporters, StatePosesCanBeIgnored) {
  ImportConfig cfg;
  cfg.resolution_m = 0.2;
  cfg.use_state_poses = false;
  const VoxelWorld w = importSdfWorld(efs::testing::sharedDataPath("ed21/ed21.world"), cfg);
  // The model's own pose (0.955, -0.126) instead of the state's (2.723, 5.844), and the links'
  // poses relative to it: the building sits about 1.8 m further west and 5.7 m further south.
  EXPECT_NEAR(w.bounds().min().x(), -19.91 - 1.77, 0.05);
  EXPECT_NEAR(w.bounds().max().y(), 25.12 - 5.97, 0.05);
}

TEST(WorldImporters, PittsburghMineHasTheExpectedExtent) {
  ImportConfig cfg;
  cfg.resolution_m = 0.25;  // coarse: this test reads an 800 kB mesh
  const VoxelWorld w =
      importSdfWorld(efs::testing::sharedDataPath("pittsburgh_mine/pittsburgh_mine.world"), cfg);
  const Eigen::Vector3d size = w.bounds().sizes();
  EXPECT_NEAR(size.x(), 252.3, 0.5);
  EXPECT_NEAR(size.y(), 327.2, 0.5);
  EXPECT_NEAR(size.z(), 2.75, 0.01);
  // Model pose from the world's <state>: (-22.4884, 286.186).
  EXPECT_NEAR(w.bounds().min().x(), -22.49, 0.01);
  EXPECT_NEAR(w.bounds().max().y(), 286.19, 0.01);
  // The start is in a passage: horizontal rays meet walls within the mine, up and down the roof
  // and floor within its height.
  const Eigen::Vector3d s = w.start_poses.at(0).position_m;
  EXPECT_LT(w.castRay(s, Eigen::Vector3d::UnitZ(), 10.0), 2.0);
  EXPECT_LT(w.castRay(s, -Eigen::Vector3d::UnitZ(), 10.0), 1.5);
  // The mesh model file alone (its own pose, no world state) gives the same size.
  const VoxelWorld m =
      importSdfWorld(efs::testing::sharedDataPath("pittsburgh_mine/model.sdf"), cfg);
  EXPECT_NEAR(m.bounds().sizes().x(), size.x(), 1e-6);
  EXPECT_NEAR(m.bounds().min().x(), -22.0, 0.01);
}

// A closed 6 x 4 x 3 m room with a slanted roof (3 m at x = 0, 3.5 m at x = 6), as 12 triangles.
const std::vector<Eigen::Vector3d> kRoomVertices = {{0, 0, 0}, {6, 0, 0},   {6, 4, 0},   {0, 4, 0},
                                                    {0, 0, 3}, {6, 0, 3.5}, {6, 4, 3.5}, {0, 4, 3}};
const std::vector<std::array<int, 3>> kRoomFaces = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7},
                                                    {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5},
                                                    {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};

std::string roomAsObj() {
  std::ostringstream s;
  for (const auto& v : kRoomVertices) s << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  for (const auto& f : kRoomFaces)
    s << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
  return s.str();
}

std::string roomAsAsciiStl() {
  std::ostringstream s;
  s << "solid room\n";
  for (const auto& f : kRoomFaces) {
    const Eigen::Vector3d n = (kRoomVertices[f[1]] - kRoomVertices[f[0]])
                                  .cross(kRoomVertices[f[2]] - kRoomVertices[f[0]])
                                  .normalized();
    s << " facet normal " << n.x() << ' ' << n.y() << ' ' << n.z() << "\n  outer loop\n";
    for (int i : f) {
      const auto& v = kRoomVertices[i];
      s << "   vertex " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    }
    s << "  endloop\n endfacet\n";
  }
  s << "endsolid room\n";
  return s.str();
}

std::string roomAsAsciiPly() {
  std::ostringstream s;
  s << "ply\nformat ascii 1.0\nelement vertex " << kRoomVertices.size()
    << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << kRoomFaces.size()
    << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& v : kRoomVertices) s << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  for (const auto& f : kRoomFaces) s << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  return s.str();
}

/// Rays from inside the room all hit within a voxel diagonal of one of its faces.
void expectClosedSlantedRoom(const VoxelWorld& w, const std::string& format) {
  SCOPED_TRACE(format);
  EXPECT_NEAR(w.bounds().sizes().x(), 6.0, 1e-6);
  EXPECT_NEAR(w.bounds().sizes().y(), 4.0, 1e-6);
  EXPECT_NEAR(w.bounds().sizes().z(), 3.5, 1e-6);
  const Eigen::Vector3d o(3.0, 2.0, 1.5);
  int escaped = 0;
  for (int i = 0; i < 2000; ++i) {
    const double az = i * 2.399963, el = std::asin(-1.0 + 2.0 * (i + 0.5) / 2000.0);
    const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    const float r = w.castRay(o, d, 20.0);
    escaped += !std::isfinite(r);
    if (std::isfinite(r)) {
      const Eigen::Vector3d hit = o + d * r;
      const double roof = 3.0 + 0.5 * hit.x() / 6.0;
      const double dist = std::min(
          {hit.x(), 6.0 - hit.x(), hit.y(), 4.0 - hit.y(), hit.z(), std::abs(roof - hit.z())});
      EXPECT_LT(dist, 0.18) << "ray " << i;
    }
  }
  EXPECT_EQ(escaped, 0);
}

ImportConfig roomImportConfig() {
  ImportConfig cfg;
  cfg.resolution_m = 0.1;
  cfg.add_floor = cfg.add_ceiling = false;
  cfg.start_clearance_m = 0.5;
  return cfg;
}

TEST(WorldImporters, ObjMeshIsVoxelisedWithoutGaps) {
  const std::string obj = writeFile("room.obj", roomAsObj());
  const ImportConfig cfg = roomImportConfig();
  expectClosedSlantedRoom(importMeshWorld(obj, Eigen::Isometry3d::Identity(), cfg), "obj");
  // A world pose moves the mesh.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(10, -5, 0);
  T.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const VoxelWorld moved = importMeshWorld(obj, T, cfg);
  EXPECT_NEAR(moved.bounds().min().x(), 6.0, 1e-9);
  EXPECT_NEAR(moved.bounds().max().y(), 1.0, 1e-9);
}

TEST(WorldImporters, StlAndPlyMeshesGiveTheSameRoomAsObj) {
  const ImportConfig cfg = roomImportConfig();
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  const VoxelWorld obj = importMeshWorld(writeFile("room_ref.obj", roomAsObj()), I, cfg);
  for (const auto& [name, text] :
       {std::pair<std::string, std::string>{"room.stl", roomAsAsciiStl()},
        {"room.ply", roomAsAsciiPly()}}) {
    const VoxelWorld w = importMeshWorld(writeFile(name, text), I, cfg);
    expectClosedSlantedRoom(w, name);
    // Same triangles, same voxels: identical ray casts from a point inside.
    for (int i = 0; i < 200; ++i) {
      const double az = i * 0.7, el = -1.2 + 2.4 * i / 200.0;
      const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                              std::sin(el));
      const Eigen::Vector3d o(1.5, 1.0, 1.0);
      EXPECT_FLOAT_EQ(w.castRay(o, d, 20.0), obj.castRay(o, d, 20.0)) << name << " ray " << i;
    }
  }
}

TEST(WorldImporters, TriangleBoxOverlapIsConservativeAndExact) {
  const Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const Eigen::Vector3d h(0.05, 0.05, 0.05);
  EXPECT_TRUE(triangleOverlapsBox({0.2, 0.2, 0.0}, h, t));
  EXPECT_TRUE(triangleOverlapsBox({0.2, 0.2, 0.049}, h, t));
  EXPECT_FALSE(triangleOverlapsBox({0.2, 0.2, 0.06}, h, t));
  EXPECT_FALSE(triangleOverlapsBox({0.6, 0.6, 0.0}, h, t));   // beyond the hypotenuse
  EXPECT_TRUE(triangleOverlapsBox({0.52, 0.52, 0.0}, h, t));  // straddles the hypotenuse
}

std::string pcdHeader(const std::string& data, int n, const std::string& fields = "x y z",
                      const std::string& size = "4 4 4", const std::string& type = "F F F",
                      const std::string& count = "1 1 1") {
  return "# .PCD v0.7\nVERSION 0.7\nFIELDS " + fields + "\nSIZE " + size + "\nTYPE " + type +
         "\nCOUNT " + count + "\nWIDTH " + std::to_string(n) +
         "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(n) + "\nDATA " + data +
         "\n";
}

// Points on the walls, floor and ceiling of a 10 x 8 x 3 m room, 0.1 m apart.
std::vector<Eigen::Vector3f> roomCloud() {
  std::vector<Eigen::Vector3f> pts;
  for (float a = 0; a <= 10.0f; a += 0.1f)
    for (float b = 0; b <= 8.0f; b += 0.1f) {
      pts.emplace_back(a, b, 0.0f);
      pts.emplace_back(a, b, 3.0f);
    }
  for (float a = 0; a <= 10.0f; a += 0.1f)
    for (float z = 0; z <= 3.0f; z += 0.1f) {
      pts.emplace_back(a, 0.0f, z);
      pts.emplace_back(a, 8.0f, z);
    }
  for (float b = 0; b <= 8.0f; b += 0.1f)
    for (float z = 0; z <= 3.0f; z += 0.1f) {
      pts.emplace_back(0.0f, b, z);
      pts.emplace_back(10.0f, b, z);
    }
  return pts;
}

TEST(WorldImporters, PcdAsciiBinaryAndCompressedGiveTheSameWorld) {
  const std::vector<Eigen::Vector3f> pts = roomCloud();
  const int n = static_cast<int>(pts.size());
  std::string ascii = pcdHeader("ascii", n, "x y z intensity", "4 4 4 4", "F F F F", "1 1 1 1");
  for (const auto& p : pts) {
    ascii +=
        std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + " 7\n";
  }
  // binary with a double-precision z and a padding field between y and z
  std::string binary = pcdHeader("binary", n, "x y pad z", "4 4 2 8", "F F U F", "1 1 1 1");
  for (const auto& p : pts) {
    const float x = p.x(), y = p.y();
    const uint16_t pad = 0;
    const double z = p.z();
    binary.append(reinterpret_cast<const char*>(&x), 4)
        .append(reinterpret_cast<const char*>(&y), 4);
    binary.append(reinterpret_cast<const char*>(&pad), 2)
        .append(reinterpret_cast<const char*>(&z), 8);
  }
  // binary_compressed: field-major payload, LZF-encoded as literal runs of up to 32 bytes
  std::string raw;
  for (int f = 0; f < 3; ++f)
    for (const auto& p : pts) {
      const float v = p[f];
      raw.append(reinterpret_cast<const char*>(&v), 4);
    }
  std::string lzf;
  for (size_t i = 0; i < raw.size(); i += 32) {
    const size_t len = std::min<size_t>(32, raw.size() - i);
    lzf.push_back(static_cast<char>(len - 1));
    lzf.append(raw, i, len);
  }
  std::string compressed = pcdHeader("binary_compressed", n);
  const uint32_t sizes[2] = {static_cast<uint32_t>(lzf.size()), static_cast<uint32_t>(raw.size())};
  compressed.append(reinterpret_cast<const char*>(sizes), 8).append(lzf);

  ImportConfig cfg;
  cfg.resolution_m = 0.2;
  cfg.start_clearance_m = 0.5;
  uint64_t fingerprint = 0;
  for (const auto& [name, content] : {std::pair<std::string, std::string>{"room_ascii.pcd", ascii},
                                      {"room_binary.pcd", binary},
                                      {"room_compressed.pcd", compressed}}) {
    SCOPED_TRACE(name);
    const std::string path = writeFile(name, content);
    EXPECT_EQ(loadPcdPoints(path).size(), pts.size());
    const VoxelWorld w = importPcdWorld(path, cfg);
    EXPECT_NEAR(w.bounds().sizes().x(), 10.0, 1e-4);
    EXPECT_NEAR(w.bounds().sizes().y(), 8.0, 1e-4);
    EXPECT_NEAR(w.castRay({5, 4, 1.5}, {1, 0, 0}, 20.0), 5.0 - 0.2, 0.21);
    if (fingerprint == 0) fingerprint = w.fingerprint();
    EXPECT_EQ(w.fingerprint(), fingerprint);
  }
}

TEST(WorldImporters, BadInputIsReportedWithFileAndPlace) {
  ImportConfig cfg;
  cfg.resolution_m = 0.2;
  // missing files
  EXPECT_NE(messageOf([&] {
              importSdfWorld("/nonexistent/world.sdf", cfg);
            }).find("/nonexistent/world.sdf"),
            std::string::npos);
  EXPECT_NE(messageOf([&] { importPcdWorld("/nonexistent/cloud.pcd", cfg); }).find("cloud.pcd"),
            std::string::npos);
  EXPECT_NE(messageOf([&] {
              importMeshWorld("/nonexistent/m.dae", Eigen::Isometry3d::Identity(), cfg);
            }).find("m.dae"),
            std::string::npos);
  // malformed XML
  const std::string broken =
      writeFile("broken.world", "<sdf version='1.6'><world><model name='a'>\n<link>");
  EXPECT_NE(messageOf([&] { importSdfWorld(broken, cfg); }).find("broken.world"),
            std::string::npos);
  // wrong root
  const std::string not_sdf = writeFile("not_sdf.world", "<urdf/>");
  EXPECT_NE(messageOf([&] { importSdfWorld(not_sdf, cfg); }).find("expected <sdf>"),
            std::string::npos);
  // a bad pose names the file and line
  const std::string bad_pose = writeFile(
      "bad_pose.world",
      "<sdf version='1.6'><world name='w'>\n<model name='m'>\n<pose>1 2 three 0 0 0</pose>\n"
      "<link name='l'><collision name='c'><geometry><box><size>1 1 1</size></box></geometry>"
      "</collision></link></model></world></sdf>");
  const std::string pose_msg = messageOf([&] { importSdfWorld(bad_pose, cfg); });
  EXPECT_NE(pose_msg.find("bad_pose.world' line 3"), std::string::npos) << pose_msg;
  // an SDF without geometry
  const std::string empty = writeFile("empty.world", "<sdf version='1.6'><world name='w'/></sdf>");
  EXPECT_NE(messageOf([&] { importSdfWorld(empty, cfg); }).find("no geometry"), std::string::npos);
  // a mesh without triangles (only a point and a line)
  const std::string no_tris = writeFile("no_tris.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2\np 3\n");
  const std::string tri_msg =
      messageOf([&] { importMeshWorld(no_tris, Eigen::Isometry3d::Identity(), cfg); });
  EXPECT_NE(tri_msg.find("no_tris.obj"), std::string::npos) << tri_msg;
  // mesh URIs that do not resolve
  const std::string lost_mesh = writeFile(
      "lost_mesh.world",
      "<sdf version='1.6'><world name='w'><model name='m'><link name='l'><collision name='c'>\n"
      "<geometry><mesh><uri>model://nowhere/gone.dae</uri></mesh></geometry></collision></link>"
      "</model></world></sdf>");
  EXPECT_NE(messageOf([&] { importSdfWorld(lost_mesh, cfg); }).find("model://nowhere/gone.dae"),
            std::string::npos);
  // malformed PCDs
  const std::string no_z =
      writeFile("no_z.pcd", pcdHeader("ascii", 1, "x y", "4 4", "F F", "1 1") + "1 2\n");
  EXPECT_NE(messageOf([&] { loadPcdPoints(no_z); }).find("x, y or z"), std::string::npos);
  const std::string short_pcd = writeFile("short.pcd", pcdHeader("ascii", 3) + "1 2 3\n");
  EXPECT_NE(messageOf([&] { loadPcdPoints(short_pcd); }).find("expected 3 points"),
            std::string::npos);
  const std::string words = writeFile("words.pcd", pcdHeader("ascii", 1) + "1 two 3\n");
  EXPECT_NE(messageOf([&] { loadPcdPoints(words); }).find("'two' is not a number"),
            std::string::npos);
  const std::string truncated = writeFile("truncated.pcd", pcdHeader("binary", 10) + "abc");
  EXPECT_NE(messageOf([&] { loadPcdPoints(truncated); }).find("truncated"), std::string::npos);
  const std::string not_pcd = writeFile("not_pcd.pcd", "hello world\n");
  EXPECT_NE(messageOf([&] { loadPcdPoints(not_pcd); }).find("not_pcd.pcd"), std::string::npos);
}

TEST(WorldImporters, StartPoseInsideAnObstacleOrOutsideIsRejected) {
  ImportConfig cfg;
  cfg.resolution_m = 0.2;
  cfg.has_start = true;
  const std::string room =
      writeFile("start_room.world",
                "<sdf version='1.6'><world name='w'><model name='m'><link name='l'>"
                "<collision name='wall'><pose>0 0 1 0 0 0</pose><geometry><box><size>2 2 "
                "2</size></box></geometry></collision>"
                "<collision name='far'><pose>10 10 1 0 0 0</pose><geometry><box><size>1 1 "
                "2</size></box></geometry></collision>"
                "</link></model></world></sdf>");
  cfg.start.position_m = {0.0, 0.0, 1.0};  // inside the box
  EXPECT_NE(messageOf([&] { importSdfWorld(room, cfg); }).find("inside an obstacle"),
            std::string::npos);
  cfg.start.position_m = {50.0, 0.0, 1.0};
  EXPECT_NE(messageOf([&] { importSdfWorld(room, cfg); }).find("outside the exploration box"),
            std::string::npos);
  cfg.start.position_m = {5.0, 5.0, 1.0};
  EXPECT_NO_THROW(importSdfWorld(room, cfg));
  cfg.resolution_m = -1.0;
  EXPECT_NE(messageOf([&] { importSdfWorld(room, cfg); }).find("resolution_m"), std::string::npos);
}

}  // namespace
}  // namespace efs::sim
