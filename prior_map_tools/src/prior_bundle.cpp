// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools/prior_bundle.h"

#include <array>
#include <cstring>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "prior_map_tools/prior_map_error.h"

namespace efs::prior_map {

std::vector<Eigen::Vector2d> PriorBundle::wallPoints() const {
  std::vector<Eigen::Vector2d> out;
  std::vector<cv::Point> px;
  if (!wall_mask.empty()) cv::findNonZero(wall_mask, px);
  out.reserve(px.size());
  for (const auto& p : px) out.push_back(frame.pixelCenter(p.x, p.y));
  return out;
}

namespace {

constexpr char kMagic[8] = {'E', 'F', 'S', 'P', 'R', 'I', 'O', 'R'};

uint32_t crc32(const std::string& data) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : data) c = table[(c ^ b) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

// Little-endian writer/reader of plain values into a byte string.
class Writer {
 public:
  template <typename T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    buf_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void putString(const std::string& s) {
    put<uint64_t>(s.size());
    buf_.append(s);
  }
  std::string& str() { return buf_; }

 private:
  std::string buf_;
};

class Reader {
 public:
  Reader(const std::string& data, std::string where) : data_(data), where_(std::move(where)) {}
  template <typename T>
  T get() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string getString() {
    const uint64_t n = get<uint64_t>();
    need(n);
    std::string s = data_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  uint64_t count(uint64_t element_size) {
    const uint64_t n = get<uint64_t>();
    if (element_size > 0 && n > (data_.size() - pos_) / element_size) {
      throw PriorMapError(where_ + ": element count " + std::to_string(n) + " exceeds the section");
    }
    return n;
  }
  bool done() const { return pos_ == data_.size(); }

 private:
  void need(uint64_t n) const {
    if (n > data_.size() - pos_) {
      throw PriorMapError(where_ + ": section ends early (wants " + std::to_string(n) +
                          " more bytes at offset " + std::to_string(pos_) + ")");
    }
  }
  const std::string& data_;
  std::string where_;
  size_t pos_ = 0;
};

std::string encodePng(const cv::Mat1b& m) {
  std::vector<uchar> buf;
  if (!m.empty()) cv::imencode(".png", m, buf);
  return std::string(buf.begin(), buf.end());
}

cv::Mat1b decodePng(const std::string& bytes, const std::string& where, const SketchFrame& frame) {
  if (bytes.empty()) return cv::Mat1b();
  const std::vector<uchar> buf(bytes.begin(), bytes.end());
  cv::Mat m = cv::imdecode(buf, cv::IMREAD_GRAYSCALE);
  if (m.empty()) throw PriorMapError(where + ": image does not decode");
  if (m.cols != frame.width_px || m.rows != frame.height_px) {
    throw PriorMapError(where + ": image size does not match the sketch frame");
  }
  return m;
}

}  // namespace

void savePriorBundle(const PriorBundle& b, const std::string& path) {
  std::map<std::string, std::string> sections;
  {
    Writer w;
    w.putString(b.source_path);
    w.put<uint8_t>(static_cast<uint8_t>(b.kind));
    w.put<double>(b.frame.m_per_px);
    w.put<double>(b.frame.origin_m.x());
    w.put<double>(b.frame.origin_m.y());
    w.put<int32_t>(b.frame.width_px);
    w.put<int32_t>(b.frame.height_px);
    w.put<double>(b.mapping_range_m);
    sections["META"] = std::move(w.str());
  }
  sections["WALL"] = encodePng(b.wall_mask);
  sections["TRAV"] = encodePng(b.traversable);
  sections["SKEL"] = encodePng(b.skeleton);
  {
    Writer w;
    w.put<uint64_t>(b.guidepoints.size());
    for (const auto& g : b.guidepoints) {
      w.put<uint32_t>(g.id);
      w.put<double>(g.position_m.x());
      w.put<double>(g.position_m.y());
      w.put<int32_t>(g.component);
      w.put<int32_t>(g.branch);
    }
    sections["GUID"] = std::move(w.str());
  }
  {
    Writer w;
    w.put<uint64_t>(b.prm.nodes_m.size());
    for (const auto& p : b.prm.nodes_m) {
      w.put<double>(p.x());
      w.put<double>(p.y());
    }
    w.put<uint64_t>(b.prm.edges.size());
    for (const auto& e : b.prm.edges) {
      w.put<int32_t>(e.a);
      w.put<int32_t>(e.b);
      w.put<double>(e.length_m);
    }
    sections["PRM_"] = std::move(w.str());
  }
  {
    Writer w;
    w.put<int32_t>(b.distances.size());
    for (double v : b.distances.data()) w.put<double>(v);
    sections["DIST"] = std::move(w.str());
  }

  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw PriorMapError(path + ": cannot open for writing");
  Writer header;
  header.str().append(kMagic, sizeof(kMagic));
  header.put<uint32_t>(PriorBundle::kFormatVersion);
  header.put<uint32_t>(static_cast<uint32_t>(sections.size()));
  out.write(header.str().data(), static_cast<std::streamsize>(header.str().size()));
  for (const auto& [tag, payload] : sections) {
    Writer s;
    s.str().append(tag.data(), 4);
    s.put<uint64_t>(payload.size());
    out.write(s.str().data(), static_cast<std::streamsize>(s.str().size()));
    out.write(payload.data(), static_cast<std::streamsize>(payload.size()));
    const uint32_t crc = crc32(payload);
    out.write(reinterpret_cast<const char*>(&crc), sizeof(crc));
  }
  if (!out) throw PriorMapError(path + ": write failed (disk full?)");
}

PriorBundle loadPriorBundle(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw PriorMapError(path + ": cannot open prior bundle (no such file?)");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (data.size() < sizeof(kMagic) + 8 || std::memcmp(data.data(), kMagic, sizeof(kMagic)) != 0) {
    throw PriorMapError(path + ": not a prior bundle (bad magic; truncated or another file type)");
  }
  Reader top(data, path);
  for (size_t i = 0; i < sizeof(kMagic); ++i) top.get<char>();
  const uint32_t version = top.get<uint32_t>();
  if (version != PriorBundle::kFormatVersion) {
    throw PriorMapError(path + ": prior bundle format version " + std::to_string(version) +
                        ", this build reads version " +
                        std::to_string(PriorBundle::kFormatVersion) +
                        "; rebuild it with prior_map_build");
  }
  const uint32_t n_sections = top.get<uint32_t>();
  std::map<std::string, std::string> sections;
  size_t offset = sizeof(kMagic) + 8;
  for (uint32_t i = 0; i < n_sections; ++i) {
    if (data.size() - offset < 12) {
      throw PriorMapError(path + ": truncated at byte " + std::to_string(data.size()) +
                          " (section header " + std::to_string(i) + " of " +
                          std::to_string(n_sections) + " missing)");
    }
    const std::string tag = data.substr(offset, 4);
    uint64_t size = 0;
    std::memcpy(&size, data.data() + offset + 4, sizeof(size));
    offset += 12;
    if (size > data.size() - offset || data.size() - offset - size < 4) {
      throw PriorMapError(path + ": truncated in section '" + tag + "' at byte " +
                          std::to_string(data.size()) + " (needs " + std::to_string(size + 4) +
                          " bytes from byte " + std::to_string(offset) + ")");
    }
    std::string payload = data.substr(offset, size);
    uint32_t crc = 0;
    std::memcpy(&crc, data.data() + offset + size, sizeof(crc));
    if (crc != crc32(payload)) {
      throw PriorMapError(path + ": section '" + tag + "' at byte " + std::to_string(offset) +
                          " is corrupt (CRC mismatch)");
    }
    sections[tag] = std::move(payload);
    offset += size + 4;
  }
  for (const char* tag : {"META", "WALL", "TRAV", "SKEL", "GUID", "PRM_", "DIST"}) {
    if (!sections.count(tag)) {
      throw PriorMapError(path + ": section '" + std::string(tag) + "' missing");
    }
  }

  PriorBundle b;
  {
    Reader r(sections["META"], path + " section META");
    b.source_path = r.getString();
    const uint8_t kind = r.get<uint8_t>();
    if (kind > static_cast<uint8_t>(SketchKind::kOccupancyGrid)) {
      throw PriorMapError(path + " section META: unknown sketch kind " + std::to_string(kind));
    }
    b.kind = static_cast<SketchKind>(kind);
    b.frame.m_per_px = r.get<double>();
    const double ox = r.get<double>();
    const double oy = r.get<double>();
    b.frame.origin_m = {ox, oy};
    b.frame.width_px = r.get<int32_t>();
    b.frame.height_px = r.get<int32_t>();
    b.mapping_range_m = r.get<double>();
    if (!(b.frame.m_per_px > 0.0) || b.frame.width_px <= 0 || b.frame.height_px <= 0) {
      throw PriorMapError(path + " section META: invalid sketch frame");
    }
  }
  b.wall_mask = decodePng(sections["WALL"], path + " section WALL", b.frame);
  b.traversable = decodePng(sections["TRAV"], path + " section TRAV", b.frame);
  b.skeleton = decodePng(sections["SKEL"], path + " section SKEL", b.frame);
  {
    Reader r(sections["GUID"], path + " section GUID");
    const uint64_t n = r.count(4 + 8 + 8 + 4 + 4);
    b.guidepoints.resize(n);
    for (auto& g : b.guidepoints) {
      g.id = r.get<uint32_t>();
      const double x = r.get<double>();
      const double y = r.get<double>();
      g.position_m = {x, y};
      g.component = r.get<int32_t>();
      g.branch = r.get<int32_t>();
    }
  }
  {
    Reader r(sections["PRM_"], path + " section PRM_");
    const uint64_t nn = r.count(16);
    b.prm.nodes_m.resize(nn);
    for (auto& p : b.prm.nodes_m) {
      const double x = r.get<double>();
      const double y = r.get<double>();
      p = {x, y};
    }
    const uint64_t ne = r.count(16);
    b.prm.edges.resize(ne);
    for (auto& e : b.prm.edges) {
      e.a = r.get<int32_t>();
      e.b = r.get<int32_t>();
      e.length_m = r.get<double>();
      if (e.a < 0 || e.b < 0 || static_cast<uint64_t>(e.a) >= nn ||
          static_cast<uint64_t>(e.b) >= nn) {
        throw PriorMapError(path + " section PRM_: edge refers to a node that does not exist");
      }
    }
  }
  {
    Reader r(sections["DIST"], path + " section DIST");
    const int32_t n = r.get<int32_t>();
    if (n < 0 || static_cast<size_t>(n) != b.guidepoints.size()) {
      throw PriorMapError(path + " section DIST: matrix size " + std::to_string(n) +
                          " does not match " + std::to_string(b.guidepoints.size()) +
                          " guidepoints");
    }
    b.distances = DistanceMatrix(n);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) b.distances.set(i, j, r.get<double>());
    }
  }
  return b;
}

namespace {
bool sameMat(const cv::Mat1b& a, const cv::Mat1b& b) {
  if (a.size() != b.size()) return false;
  return a.empty() || cv::countNonZero(a != b) == 0;
}
}  // namespace

bool operator==(const PriorBundle& a, const PriorBundle& b) {
  if (a.source_path != b.source_path || a.kind != b.kind) return false;
  if (a.frame.m_per_px != b.frame.m_per_px || a.frame.origin_m != b.frame.origin_m ||
      a.frame.width_px != b.frame.width_px || a.frame.height_px != b.frame.height_px) {
    return false;
  }
  if (a.mapping_range_m != b.mapping_range_m) return false;
  if (!sameMat(a.wall_mask, b.wall_mask) || !sameMat(a.traversable, b.traversable) ||
      !sameMat(a.skeleton, b.skeleton)) {
    return false;
  }
  if (a.guidepoints.size() != b.guidepoints.size()) return false;
  for (size_t i = 0; i < a.guidepoints.size(); ++i) {
    const auto &g = a.guidepoints[i], &h = b.guidepoints[i];
    if (g.id != h.id || g.position_m != h.position_m || g.component != h.component ||
        g.branch != h.branch) {
      return false;
    }
  }
  if (a.prm.nodes_m != b.prm.nodes_m || a.prm.edges.size() != b.prm.edges.size()) return false;
  for (size_t i = 0; i < a.prm.edges.size(); ++i) {
    const auto &e = a.prm.edges[i], &f = b.prm.edges[i];
    if (e.a != f.a || e.b != f.b || e.length_m != f.length_m) return false;
  }
  return a.distances.size() == b.distances.size() && a.distances.data() == b.distances.data();
}

}  // namespace efs::prior_map
