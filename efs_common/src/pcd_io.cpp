// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// PCD (v0.7 and older) for x/y/z. Own code rather than pcl::io so that core libraries do not
// pull PCL's headers in (and PCL's compile time) for a file format this small.
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "efs_common/pcd_io.h"

namespace efs {
namespace {

struct PcdField {
  std::string name;
  int size = 4;
  char type = 'F';
  int count = 1;
  size_t offset = 0;  // bytes into a point (binary) or value index (ascii)
};

/// LZF decompression (the format PCD's binary_compressed uses): literal runs and back references.
std::vector<uint8_t> lzfDecompress(const uint8_t* in, size_t in_len, size_t out_len,
                                   const std::string& where) {
  std::vector<uint8_t> out(out_len);
  size_t ip = 0, op = 0;
  while (ip < in_len) {
    const unsigned ctrl = in[ip++];
    if (ctrl < 32) {  // literal run of ctrl + 1 bytes
      const size_t n = ctrl + 1;
      if (ip + n > in_len || op + n > out_len)
        throw std::runtime_error(where + ": corrupt LZF literal");
      std::memcpy(&out[op], &in[ip], n);
      ip += n;
      op += n;
    } else {  // back reference
      size_t len = ctrl >> 5;
      if (ip >= in_len) throw std::runtime_error(where + ": corrupt LZF reference");
      if (len == 7) {
        len += in[ip++];
        if (ip >= in_len) throw std::runtime_error(where + ": corrupt LZF reference");
      }
      const size_t back = ((ctrl & 0x1f) << 8) + in[ip++] + 1;
      len += 2;
      if (back > op || op + len > out_len)
        throw std::runtime_error(where + ": corrupt LZF reference");
      for (size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];
    }
  }
  if (op != out_len) throw std::runtime_error(where + ": LZF data shorter than announced");
  return out;
}

double readValue(const uint8_t* p, const PcdField& f) {
  if (f.type == 'F' && f.size == 4) {
    float v;
    std::memcpy(&v, p, 4);
    return v;
  }
  if (f.type == 'F' && f.size == 8) {
    double v;
    std::memcpy(&v, p, 8);
    return v;
  }
  int64_t v = 0;
  if (f.type == 'I') {
    if (f.size == 1) v = *reinterpret_cast<const int8_t*>(p);
    if (f.size == 2) {
      int16_t t;
      std::memcpy(&t, p, 2);
      v = t;
    }
    if (f.size == 4) {
      int32_t t;
      std::memcpy(&t, p, 4);
      v = t;
    }
    if (f.size == 8) {
      std::memcpy(&v, p, 8);
    }
  } else {
    uint64_t u = 0;
    std::memcpy(&u, p, static_cast<size_t>(f.size));
    v = static_cast<int64_t>(u);
  }
  return static_cast<double>(v);
}

}  // namespace

std::vector<Eigen::Vector3f> loadPcdPoints(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open PCD '" + path + "'");
  std::vector<PcdField> fields;
  std::vector<int> sizes, counts;
  std::vector<char> types;
  size_t points = 0, width = 0, height = 1;
  bool have_points = false;
  std::string data, line;
  int line_no = 0;
  auto fail = [&](const std::string& what) {
    throw std::runtime_error("PCD '" + path + "' line " + std::to_string(line_no) + ": " + what);
  };
  while (data.empty() && std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "VERSION") continue;
    if (key == "FIELDS" || key == "COLUMNS") {
      std::string name;
      while (ls >> name) fields.push_back({name, 4, 'F', 1, 0});
    } else if (key == "SIZE") {
      int v;
      while (ls >> v) sizes.push_back(v);
    } else if (key == "TYPE") {
      char v;
      while (ls >> v) types.push_back(v);
    } else if (key == "COUNT") {
      int v;
      while (ls >> v) counts.push_back(v);
    } else if (key == "WIDTH") {
      if (!(ls >> width)) fail("WIDTH needs a number");
    } else if (key == "HEIGHT") {
      if (!(ls >> height)) fail("HEIGHT needs a number");
    } else if (key == "POINTS") {
      if (!(ls >> points)) fail("POINTS needs a number");
      have_points = true;
    } else if (key == "VIEWPOINT") {
      continue;
    } else if (key == "DATA") {
      if (!(ls >> data)) fail("DATA needs ascii, binary or binary_compressed");
    } else {
      fail("unknown header key '" + key + "'");
    }
  }
  if (data.empty())
    throw std::runtime_error("PCD '" + path + "' has no DATA line (not a PCD file?)");
  if (fields.empty()) throw std::runtime_error("PCD '" + path + "' has no FIELDS");
  if (!sizes.empty() && sizes.size() != fields.size()) fail("SIZE does not match FIELDS");
  if (!types.empty() && types.size() != fields.size()) fail("TYPE does not match FIELDS");
  if (!counts.empty() && counts.size() != fields.size()) fail("COUNT does not match FIELDS");
  if (!have_points) points = width * height;
  if (points > (size_t{1} << 31)) fail("POINTS is absurdly large");
  size_t stride = 0, values_per_point = 0;
  int ix = -1, iy = -1, iz = -1;
  for (size_t i = 0; i < fields.size(); ++i) {
    PcdField& f = fields[i];
    if (!sizes.empty()) f.size = sizes[i];
    if (!types.empty()) f.type = types[i];
    if (!counts.empty()) f.count = counts[i];
    if (f.size != 1 && f.size != 2 && f.size != 4 && f.size != 8) fail("SIZE must be 1, 2, 4 or 8");
    if (f.type != 'F' && f.type != 'I' && f.type != 'U') fail("TYPE must be F, I or U");
    if (f.type == 'F' && f.size != 4 && f.size != 8) fail("a float field must have SIZE 4 or 8");
    if (f.count < 1) fail("COUNT must be >= 1");
    f.offset = data == "ascii" ? values_per_point : stride;
    stride += static_cast<size_t>(f.size) * f.count;
    values_per_point += static_cast<size_t>(f.count);
    if (f.name == "x") ix = static_cast<int>(i);
    if (f.name == "y") iy = static_cast<int>(i);
    if (f.name == "z") iz = static_cast<int>(i);
  }
  if (ix < 0 || iy < 0 || iz < 0) {
    throw std::runtime_error("PCD '" + path + "' lacks an x, y or z field");
  }

  std::vector<Eigen::Vector3f> out;
  out.reserve(points);
  auto push = [&](double x, double y, double z) {
    if (std::isfinite(x) && std::isfinite(y) && std::isfinite(z)) {
      out.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
    }
  };
  if (data == "ascii") {
    std::vector<double> v(values_per_point);
    for (size_t n = 0; n < points; ++n) {
      if (!std::getline(in, line)) {
        throw std::runtime_error("PCD '" + path + "': expected " + std::to_string(points) +
                                 " points, found " + std::to_string(n));
      }
      ++line_no;
      std::istringstream ls(line);
      for (size_t k = 0; k < values_per_point; ++k) {
        std::string tok;
        if (!(ls >> tok)) fail("expected " + std::to_string(values_per_point) + " values");
        try {
          v[k] = std::stod(tok);  // "nan" parses; non-finite points are dropped below
        } catch (const std::exception&) {
          fail("'" + tok + "' is not a number");
        }
      }
      push(v[fields[ix].offset], v[fields[iy].offset], v[fields[iz].offset]);
    }
  } else if (data == "binary") {
    std::vector<uint8_t> buf(stride * points);
    in.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(buf.size()));
    if (static_cast<size_t>(in.gcount()) != buf.size()) {
      throw std::runtime_error("PCD '" + path + "': binary data is truncated (" +
                               std::to_string(in.gcount()) + " of " + std::to_string(buf.size()) +
                               " bytes)");
    }
    for (size_t n = 0; n < points; ++n) {
      const uint8_t* p = buf.data() + n * stride;
      push(readValue(p + fields[ix].offset, fields[ix]),
           readValue(p + fields[iy].offset, fields[iy]),
           readValue(p + fields[iz].offset, fields[iz]));
    }
  } else if (data == "binary_compressed") {
    uint32_t sizes_hdr[2];
    in.read(reinterpret_cast<char*>(sizes_hdr), sizeof(sizes_hdr));
    if (in.gcount() != sizeof(sizes_hdr))
      throw std::runtime_error("PCD '" + path + "': truncated compressed header");
    if (sizes_hdr[1] != stride * points) {
      throw std::runtime_error("PCD '" + path +
                               "': compressed payload size does not match the header");
    }
    std::vector<uint8_t> comp(sizes_hdr[0]);
    in.read(reinterpret_cast<char*>(comp.data()), static_cast<std::streamsize>(comp.size()));
    if (static_cast<size_t>(in.gcount()) != comp.size()) {
      throw std::runtime_error("PCD '" + path + "': compressed data is truncated");
    }
    const std::vector<uint8_t> raw =
        lzfDecompress(comp.data(), comp.size(), sizes_hdr[1], "PCD '" + path + "'");
    // Field-major layout: each field's values for all points lie together.
    std::vector<size_t> field_start(fields.size());
    size_t acc = 0;
    for (size_t i = 0; i < fields.size(); ++i) {
      field_start[i] = acc;
      acc += static_cast<size_t>(fields[i].size) * fields[i].count * points;
    }
    auto at = [&](int f, size_t n) {
      const PcdField& fd = fields[static_cast<size_t>(f)];
      return readValue(raw.data() + field_start[static_cast<size_t>(f)] +
                           n * static_cast<size_t>(fd.size) * fd.count,
                       fd);
    };
    for (size_t n = 0; n < points; ++n) push(at(ix, n), at(iy, n), at(iz, n));
  } else {
    fail("DATA must be ascii, binary or binary_compressed, not '" + data + "'");
  }
  return out;
}

void writePcdBinary(const std::string& path, const std::vector<Eigen::Vector3f>& points_m) {
  // Written beside the target and renamed over it, so a reader never sees a half-written map.
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write PCD '" + path + "' (cannot create " + tmp + ")");
    std::vector<float> xyz;
    xyz.reserve(3 * points_m.size());
    for (const auto& p : points_m) {
      if (!p.allFinite()) continue;
      xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    }
    const size_t n = xyz.size() / 3;
    out << "# .PCD v0.7 - Point Cloud Data file format\n"
        << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
        << "WIDTH " << n << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << n
        << "\nDATA binary\n";
    out.write(reinterpret_cast<const char*>(xyz.data()),
              static_cast<std::streamsize>(xyz.size() * sizeof(float)));
    out.flush();
    if (!out) throw std::runtime_error("cannot write PCD '" + path + "': write failed (disk full?)");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write PCD '" + path + "': rename from " + tmp + " failed");
  }
}

}  // namespace efs
