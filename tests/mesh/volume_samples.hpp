#pragma once
// Writes small NRRD label volumes for the nrrd.cpp and label_volume.cpp
// suites (raw or gzip, attached or detached headers).
#include <zlib.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace softcut::test {

inline std::string gzip_bytes(const std::string& in) {
  z_stream zs{};
  if (deflateInit2(&zs, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw std::runtime_error("zlib");
  std::string out(deflateBound(&zs, uLong(in.size())) + 32, '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  zs.avail_in = uInt(in.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = uInt(out.size());
  if (deflate(&zs, Z_FINISH) != Z_STREAM_END) throw std::runtime_error("zlib");
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

// Little- or big-endian bytes of `values` as integers of `bytes` bytes.
inline std::string pack(const std::vector<long long>& values, int bytes, bool big = false) {
  std::string s;
  for (long long v : values)
    for (int k = 0; k < bytes; ++k) {
      const int shift = big ? 8 * (bytes - 1 - k) : 8 * k;
      s += char((static_cast<unsigned long long>(v) >> shift) & 0xff);
    }
  return s;
}

inline void write_bytes(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out << bytes;
}

// A 3 x 2 x 2 volume: label 1 in the i = 0 column, label 2 in i = 1, background
// (0) in i = 2 except voxel (2, 1, 1) which is label 5.
inline std::vector<long long> sample_labels() {
  std::vector<long long> v;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) v.push_back(i == 0 ? 1 : i == 1 ? 2 : (j == 1 && k == 1 ? 5 : 0));
  return v;
}

}  // namespace softcut::test
