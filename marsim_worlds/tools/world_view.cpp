// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// world_view: writes a top-down PNG of a world with its four sketch variants beside it, for a
// person to check, and saves each sketch with its sidecar.
//
//   world_view --world garage|simple_cave|subt_cave|indoor [--size small|paper] [--seed N]
//   world_view --sdf path/to/world.sdf | --mesh path/to/mesh.dae | --pcd path/to/cloud.pcd
//   common: [--resolution 0.15] [--out DIR] [--view-mpp 0.2] [--sketch-seed N]
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "efs_common/cli_args.h"
#include "efs_common/resource_usage.h"
#include "marsim_worlds/world_sketch.h"
#include "marsim_worlds/world_source.h"

namespace {

cv::Mat toColor(const cv::Mat& gray) {
  cv::Mat out;
  cv::cvtColor(gray, out, cv::COLOR_GRAY2BGR);
  return out;
}

cv::Mat fitHeight(const cv::Mat& img, int height) {
  cv::Mat out;
  const double f = static_cast<double>(height) / img.rows;
  // INTER_AREA keeps thin lines visible when shrinking.
  cv::resize(img, out, cv::Size(std::max(1, static_cast<int>(img.cols * f)), height), 0, 0,
             f < 1.0 ? cv::INTER_AREA : cv::INTER_NEAREST);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace efs::sim;
  try {
    std::set<std::string> options = worldSourceOptions();
    options.insert({"out", "view-mpp", "sketch-seed"});
    const efs::CliArgs args(argc, argv, options);
    const WorldSource source = worldSourceFromArgs(args, "garage");
    const double res = source.resolution_m;
    const std::string out_dir = args.str("out", ".");
    std::filesystem::create_directories(out_dir);
    efs::Stopwatch watch;
    VoxelWorld world = loadWorld(source);
    const double build_s = watch.elapsedSeconds();
    const Eigen::Vector3d size = world.bounds().sizes();
    std::printf("world %s: %.0f x %.0f x %.0f m at %.2f m, built in %.2f s, %.1f MB\n",
                world.name.c_str(), size.x(), size.y(), size.z(), res, build_s,
                world.memoryBytes() / 1e6);

    const double view_mpp =
        args.number("view-mpp", std::max(0.1, size.head<2>().maxCoeff() / 1500.0));
    const cv::Mat top = renderTopDown(world, view_mpp);
    SketchConfig sc;
    sc.seed = static_cast<uint64_t>(args.integer("sketch-seed", 1));
    std::vector<cv::Mat> panels{top};
    for (SketchVariant v : {SketchVariant::kPrecise, SketchVariant::kPartial,
                            SketchVariant::kDeformed, SketchVariant::kScaled}) {
      const Sketch sk = drawSketch(world, v, sc);
      const std::string png = out_dir + "/" + world.name + "_" + sketchVariantName(v) + ".png";
      saveSketch(sk, png);
      std::printf("  %-8s %5d x %5d px, true %.3f m/px, yaw %.2f rad -> %s\n",
                  sketchVariantName(v).c_str(), sk.image.cols, sk.image.rows,
                  sk.trueMetresPerPixel(), sk.T_world_sketch.yaw_rad, png.c_str());
      panels.push_back(toColor(sk.image));
    }
    const int height = std::min(900, std::max(top.rows, 300));
    std::vector<cv::Mat> row;
    for (const cv::Mat& p : panels) {
      row.push_back(fitHeight(p, height));
      row.push_back(cv::Mat(height, 12, CV_8UC3, cv::Scalar(0, 160, 255)));
    }
    row.pop_back();
    cv::Mat sheet;
    cv::hconcat(row, sheet);
    const std::string sheet_path = out_dir + "/" + world.name + "_view.png";
    if (!cv::imwrite(sheet_path, sheet)) throw std::runtime_error("cannot write " + sheet_path);
    std::printf("view: %s\n", sheet_path.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "world_view: " << e.what() << "\n";
    return 1;
  }
}
