#pragma once
// Small closed surfaces as the files users bring, written by the tests
// themselves (the independent samples, written by numpy and meshio, are in
// tests/data/surface/).
#include <Eigen/Core>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace softcut::test {

struct Soup {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3i> tris;  // counter-clockwise seen from outside
};

// The unit cube [0,1]^3 (12 triangles, outward), scaled and moved.
inline Soup cube(double side = 1, const Eigen::Vector3d& at = Eigen::Vector3d::Zero()) {
  Soup s;
  for (int i = 0; i < 8; ++i) s.points.push_back(at + side * Eigen::Vector3d(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) s.tris.emplace_back(f[0], f[1], f[2]), s.tris.emplace_back(f[0], f[2], f[3]);
  return s;
}

// An icosphere (subdivisions 2: 320 triangles), outward.
inline Soup sphere(double r, const Eigen::Vector3d& c = Eigen::Vector3d::Zero(), int subdivisions = 2) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Eigen::Vector3d> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& x : p) x.normalize();
  std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                    {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::vector<Eigen::Vector3i> g;
    std::vector<std::pair<std::pair<int, int>, int>> mid;
    const auto middle = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      for (const auto& [k, v] : mid)
        if (k == key) return v;
      p.push_back((p[size_t(a)] + p[size_t(b)]).normalized());
      mid.push_back({key, int(p.size()) - 1});
      return int(p.size()) - 1;
    };
    for (const auto& x : f) {
      const int ab = middle(x[0], x[1]), bc = middle(x[1], x[2]), ca = middle(x[2], x[0]);
      g.emplace_back(x[0], ab, ca), g.emplace_back(x[1], bc, ab), g.emplace_back(x[2], ca, bc), g.emplace_back(ab, bc, ca);
    }
    f = g;
  }
  Soup out;
  for (const auto& x : p) out.points.push_back(c + r * x);
  out.tris = f;
  return out;
}

// Several soups as one (one file with several pieces).
inline Soup join(const std::vector<Soup>& parts) {
  Soup s;
  for (const Soup& p : parts) {
    const int base = int(s.points.size());
    s.points.insert(s.points.end(), p.points.begin(), p.points.end());
    for (const auto& t : p.tris) s.tris.push_back(t + Eigen::Vector3i::Constant(base));
  }
  return s;
}

inline std::string off_text(const Soup& s) {
  std::ostringstream os;
  os.precision(17);
  os << "OFF\n" << s.points.size() << " " << s.tris.size() << " 0\n";
  for (const auto& p : s.points) os << p.x() << " " << p.y() << " " << p.z() << "\n";
  for (const auto& t : s.tris) os << "3 " << t.x() << " " << t.y() << " " << t.z() << "\n";
  return os.str();
}

inline std::string obj_text(const Soup& s) {
  std::ostringstream os;
  os.precision(17);
  for (const auto& p : s.points) os << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
  for (const auto& t : s.tris) os << "f " << t.x() + 1 << " " << t.y() + 1 << " " << t.z() + 1 << "\n";
  return os.str();
}

inline std::string stl_ascii(const Soup& s) {
  std::ostringstream os;
  os.precision(17);
  os << "solid test\n";
  for (const auto& t : s.tris) {
    os << " facet normal 0 0 0\n  outer loop\n";
    for (int k = 0; k < 3; ++k) {
      const auto& p = s.points[size_t(t[k])];
      os << "   vertex " << p.x() << " " << p.y() << " " << p.z() << "\n";
    }
    os << "  endloop\n endfacet\n";
  }
  os << "endsolid test\n";
  return os.str();
}

inline std::string stl_binary(const Soup& s) {
  std::string out(80, ' ');
  out.replace(0, 12, "binary test ");
  const auto put = [&](const void* p, std::size_t n) { out.append(static_cast<const char*>(p), n); };
  const std::uint32_t n = std::uint32_t(s.tris.size());
  put(&n, 4);
  for (const auto& t : s.tris) {
    const float zero[3] = {0, 0, 0};
    put(zero, 12);
    for (int k = 0; k < 3; ++k) {
      const auto& p = s.points[size_t(t[k])];
      const float f[3] = {float(p.x()), float(p.y()), float(p.z())};
      put(f, 12);
    }
    const std::uint16_t attr = 0;
    put(&attr, 2);
  }
  return out;
}

inline std::string ply_ascii(const Soup& s) {
  std::ostringstream os;
  os.precision(17);
  os << "ply\nformat ascii 1.0\nelement vertex " << s.points.size()
     << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << s.tris.size()
     << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : s.points) os << p.x() << " " << p.y() << " " << p.z() << "\n";
  for (const auto& t : s.tris) os << "3 " << t.x() << " " << t.y() << " " << t.z() << "\n";
  return os.str();
}

inline std::string ply_binary(const Soup& s) {
  std::ostringstream os;
  os << "ply\nformat binary_little_endian 1.0\nelement vertex " << s.points.size()
     << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << s.tris.size()
     << "\nproperty list uchar int vertex_indices\nend_header\n";
  std::string out = os.str();
  for (const auto& p : s.points) {
    const float f[3] = {float(p.x()), float(p.y()), float(p.z())};
    out.append(reinterpret_cast<const char*>(f), 12);
  }
  for (const auto& t : s.tris) {
    out.push_back(char(3));
    const std::int32_t i[3] = {t.x(), t.y(), t.z()};
    out.append(reinterpret_cast<const char*>(i), 12);
  }
  return out;
}

}  // namespace softcut::test
