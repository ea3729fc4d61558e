// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools/sketch_loader.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "efs_common/config_check.h"
#include "prior_map_tools/prior_map_error.h"

namespace efs::prior_map {
namespace fs = std::filesystem;

const char* toString(SketchKind kind) {
  switch (kind) {
    case SketchKind::kAuto:
      return "auto";
    case SketchKind::kLineDrawing:
      return "line_drawing";
    case SketchKind::kOccupancyGrid:
      return "occupancy_grid";
  }
  return "unknown";
}

void SketchLoadConfig::validate() const {
  requirePositive("scale_guess_m_per_px", scale_guess_m_per_px);
  requireInRange("scale_guess_m_per_px", scale_guess_m_per_px, 1e-4, 100.0);
  requireInRange("wall_threshold", wall_threshold, 1, 255);
  requireInRange("max_image_pixels", max_image_pixels, 1L, 1000L * 1000 * 1000);
  requireInRange("occupied_thresh", occupied_thresh, 0.0, 1.0);
  requireInRange("free_thresh", free_thresh, 0.0, 1.0);
  requireThat(free_thresh < occupied_thresh, "free_thresh", "must be below occupied_thresh");
  requireInRange("auto_grid_unknown_fraction", auto_grid_unknown_fraction, 0.0, 1.0);
}

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw PriorMapError(path + ": " + what);
}

std::string readHead(const std::string& path, size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string head(n, '\0');
  in.read(head.data(), static_cast<std::streamsize>(n));
  head.resize(static_cast<size_t>(in.gcount()));
  return head;
}

// Reads width and height from the header of PNG and PNM files so that an oversized image is
// refused before it is decoded into memory. Returns false for other formats.
bool probeImageSize(const std::string& path, long* width, long* height) {
  const std::string head = readHead(path, 64);
  const auto be32 = [&](size_t at) {
    return (static_cast<uint32_t>(static_cast<uint8_t>(head[at])) << 24) |
           (static_cast<uint32_t>(static_cast<uint8_t>(head[at + 1])) << 16) |
           (static_cast<uint32_t>(static_cast<uint8_t>(head[at + 2])) << 8) |
           static_cast<uint32_t>(static_cast<uint8_t>(head[at + 3]));
  };
  if (head.size() >= 24 && head.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0) {
    *width = be32(16);
    *height = be32(20);
    return true;
  }
  if (head.size() >= 2 && head[0] == 'P' && head[1] >= '1' && head[1] <= '6') {
    std::istringstream is(head.substr(2));
    std::string tok;
    std::vector<long> dims;
    while (dims.size() < 2 && is >> tok) {
      if (tok[0] == '#') {
        std::string rest;
        std::getline(is, rest);
        continue;
      }
      try {
        dims.push_back(std::stol(tok));
      } catch (const std::exception&) {
        return false;
      }
    }
    if (dims.size() == 2) {
      *width = dims[0];
      *height = dims[1];
      return true;
    }
  }
  return false;
}

// Luminance in [0, 255]; transparent pixels are blank paper (white).
cv::Mat1b toLuminance(const cv::Mat& image) {
  cv::Mat img8;
  if (image.depth() == CV_8U) {
    img8 = image;
  } else if (image.depth() == CV_16U) {
    image.convertTo(img8, CV_8U, 1.0 / 257.0);
  } else {
    cv::Mat tmp;
    double lo = 0, hi = 0;
    cv::minMaxLoc(image.reshape(1), &lo, &hi);
    image.convertTo(img8, CV_8U, hi > lo ? 255.0 / (hi - lo) : 1.0,
                    hi > lo ? -lo * 255.0 / (hi - lo) : 0.0);
  }
  cv::Mat1b grey;
  switch (img8.channels()) {
    case 1:
      grey = img8;
      break;
    case 3:
      cv::cvtColor(img8, grey, cv::COLOR_BGR2GRAY);
      break;
    case 4: {
      cv::Mat bgr;
      cv::cvtColor(img8, bgr, cv::COLOR_BGRA2BGR);
      cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
      std::vector<cv::Mat1b> ch;
      cv::split(img8, ch);
      for (int r = 0; r < grey.rows; ++r) {
        for (int c = 0; c < grey.cols; ++c) {
          const double a = ch[3](r, c) / 255.0;
          grey(r, c) = cv::saturate_cast<uint8_t>(a * grey(r, c) + (1.0 - a) * 255.0);
        }
      }
      break;
    }
    case 2: {
      std::vector<cv::Mat1b> ch;
      cv::split(img8, ch);
      grey = ch[0].clone();
      for (int r = 0; r < grey.rows; ++r) {
        for (int c = 0; c < grey.cols; ++c) {
          const double a = ch[1](r, c) / 255.0;
          grey(r, c) = cv::saturate_cast<uint8_t>(a * grey(r, c) + (1.0 - a) * 255.0);
        }
      }
      break;
    }
    default:
      throw PriorMapError("unsupported number of image channels: " +
                          std::to_string(img8.channels()));
  }
  return grey.clone();
}

struct MapYaml {
  std::string image;
  double resolution = 0.0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\"'");
  const auto e = s.find_last_not_of(" \t\r\"'");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

double parseNumber(const std::string& path, const std::string& key, const std::string& text) {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used != text.size() || !std::isfinite(v)) throw std::invalid_argument(text);
    return v;
  } catch (const std::exception&) {
    fail(path, "key '" + key + "' is not a number: '" + text + "'");
  }
}

// map_server's YAML is flat "key: value" lines; a full YAML library is not needed to read it.
MapYaml parseMapYaml(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path, "cannot open file");
  std::map<std::string, std::string> kv;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line = line.substr(0, hash);
    if (trim(line).empty()) continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos) {
      fail(path, "line " + std::to_string(line_no) + " is not 'key: value'");
    }
    kv[trim(line.substr(0, colon))] = trim(line.substr(colon + 1));
  }
  MapYaml y;
  if (!kv.count("image")) fail(path, "missing key 'image'");
  if (!kv.count("resolution")) fail(path, "missing key 'resolution'");
  y.image = kv["image"];
  y.resolution = parseNumber(path, "resolution", kv["resolution"]);
  if (!(y.resolution > 0.0)) fail(path, "key 'resolution' must be > 0");
  if (kv.count("origin")) {
    std::string o = kv["origin"];
    for (char& ch : o) {
      if (ch == '[' || ch == ']' || ch == ',') ch = ' ';
    }
    std::istringstream is(o);
    std::vector<std::string> parts;
    std::string tok;
    while (is >> tok) parts.push_back(tok);
    if (parts.size() < 2) fail(path, "key 'origin' must be [x, y, yaw]");
    y.origin = {parseNumber(path, "origin", parts[0]), parseNumber(path, "origin", parts[1])};
    if (parts.size() >= 3 && std::abs(parseNumber(path, "origin", parts[2])) > 1e-9) {
      fail(path, "key 'origin' has a non-zero yaw, which map_server does not support either");
    }
  }
  if (kv.count("negate")) y.negate = parseNumber(path, "negate", kv["negate"]) != 0.0;
  if (kv.count("occupied_thresh")) {
    y.occupied_thresh = parseNumber(path, "occupied_thresh", kv["occupied_thresh"]);
  }
  if (kv.count("free_thresh")) y.free_thresh = parseNumber(path, "free_thresh", kv["free_thresh"]);
  return y;
}

cv::Mat readImageChecked(const std::string& path, const SketchLoadConfig& config) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "no such file");
  if (fs::is_directory(path, ec)) fail(path, "is a directory, not an image");
  if (fs::file_size(path, ec) == 0) fail(path, "empty file (zero bytes)");
  long w = 0, h = 0;
  if (probeImageSize(path, &w, &h)) {
    if (w <= 0 || h <= 0)
      fail(path, "zero-size image (" + std::to_string(w) + " x " + std::to_string(h) + ")");
    if (w * h > config.max_image_pixels) {
      fail(path, "image of " + std::to_string(w) + " x " + std::to_string(h) +
                     " pixels exceeds the limit of " + std::to_string(config.max_image_pixels) +
                     " pixels (SketchLoadConfig::max_image_pixels)");
    }
  }
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    fail(path, std::string("cannot decode image: ") + e.what());
  }
  if (image.empty()) fail(path, "not an image, or a corrupt or zero-size one (cannot decode)");
  return image;
}

LoadedSketch classify(const cv::Mat1b& lum, SketchKind kind, const SketchLoadConfig& config,
                      bool negate, const std::string& name) {
  LoadedSketch out;
  out.source_path = name;
  if (kind == SketchKind::kAuto) {
    // map_server writes unknown as 205; light anti-aliasing greys of a drawing are rare.
    const int mid = cv::countNonZero((lum > 150) & (lum < 235));
    const double fraction = static_cast<double>(mid) / static_cast<double>(lum.total());
    kind = fraction > config.auto_grid_unknown_fraction ? SketchKind::kOccupancyGrid
                                                        : SketchKind::kLineDrawing;
  }
  out.kind = kind;
  out.wall_mask = cv::Mat1b::zeros(lum.size());
  out.unknown_mask = cv::Mat1b::zeros(lum.size());
  if (kind == SketchKind::kLineDrawing) {
    out.wall_mask.setTo(255, lum < config.wall_threshold);
  } else {
    for (int r = 0; r < lum.rows; ++r) {
      for (int c = 0; c < lum.cols; ++c) {
        const double v = lum(r, c) / 255.0;
        const double p_occupied = negate ? v : 1.0 - v;
        if (p_occupied > config.occupied_thresh) {
          out.wall_mask(r, c) = 255;
        } else if (p_occupied >= config.free_thresh) {
          out.unknown_mask(r, c) = 255;
        }
      }
    }
  }
  out.frame.width_px = lum.cols;
  out.frame.height_px = lum.rows;
  return out;
}

}  // namespace

LoadedSketch sketchFromImage(const cv::Mat& image, const SketchLoadConfig& config,
                             const std::string& name) {
  config.validate();
  if (image.empty() || image.rows == 0 || image.cols == 0) fail(name, "zero-size image");
  if (static_cast<long>(image.total()) > config.max_image_pixels) {
    fail(name, "image of " + std::to_string(image.cols) + " x " + std::to_string(image.rows) +
                   " pixels exceeds the limit of " + std::to_string(config.max_image_pixels) +
                   " pixels");
  }
  LoadedSketch out = classify(toLuminance(image), config.kind, config, false, name);
  out.frame.m_per_px = config.scale_guess_m_per_px;
  return out;
}

LoadedSketch loadSketch(const std::string& path, const SketchLoadConfig& config) {
  try {
    config.validate();
  } catch (const ConfigError& e) {
    fail(path, e.what());
  }
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".yaml" || ext == ".yml") {
    std::error_code ec;
    if (!fs::exists(path, ec)) fail(path, "no such file");
    const MapYaml y = parseMapYaml(path);
    fs::path image_path = y.image;
    if (image_path.is_relative()) image_path = fs::path(path).parent_path() / image_path;
    SketchLoadConfig grid_config = config;
    grid_config.occupied_thresh = y.occupied_thresh;
    grid_config.free_thresh = y.free_thresh;
    const cv::Mat image = readImageChecked(image_path.string(), grid_config);
    LoadedSketch out =
        classify(toLuminance(image), SketchKind::kOccupancyGrid, grid_config, y.negate, path);
    out.frame.m_per_px = y.resolution;
    out.frame.origin_m = y.origin;
    return out;
  }
  const cv::Mat image = readImageChecked(path, config);
  LoadedSketch out = classify(toLuminance(image), config.kind, config, false, path);
  out.frame.m_per_px = config.scale_guess_m_per_px;
  return out;
}

}  // namespace efs::prior_map
