#include "core/binary_io.hpp"

#include <zlib.h>

#include <algorithm>

#include "core/error.hpp"

namespace softcut {

namespace {
std::uint32_t crc_update(std::uint32_t crc, const void* p, size_t n) {
  const auto* b = static_cast<const unsigned char*>(p);
  while (n > 0) {  // crc32_z takes size_t, but stay within 1 GiB per call
    const size_t k = std::min<size_t>(n, size_t(1) << 30);
    crc = std::uint32_t(crc32_z(crc, b, k));
    b += k, n -= k;
  }
  return crc;
}
}  // namespace

void BinaryWriter::bytes(const void* p, size_t n) {
  if (n == 0) return;
  crc_ = crc_update(crc_, p, n);
  out_.write(static_cast<const char*>(p), std::streamsize(n));
}

void BinaryWriter::finish() {
  const std::uint32_t c = crc_;
  out_.write(reinterpret_cast<const char*>(&c), sizeof c);
}

void BinaryReader::bytes(void* p, size_t n) {
  if (n == 0) return;
  if (n > left_) fail(what_, ": truncated (", n, " bytes wanted, ", left_, " left)");
  in_.read(static_cast<char*>(p), std::streamsize(n));
  if (size_t(in_.gcount()) != n) fail(what_, ": read failed (", in_.gcount(), " of ", n, " bytes)");
  left_ -= n;
  crc_ = crc_update(crc_, p, n);
}

size_t BinaryReader::count(size_t elem) {
  std::uint64_t n = 0;
  pod(n);
  if (elem > 0 && n > left_ / elem) fail(what_, ": an array of ", n, " elements does not fit in the ", left_, " bytes left");
  return size_t(n);
}

void BinaryReader::fail_size() const { fail(what_, ": an array has the wrong size for what it holds"); }

void BinaryReader::finish() {
  const std::uint32_t mine = crc_;
  std::uint32_t stored = 0;
  bytes(&stored, sizeof stored);
  if (stored != mine) fail(what_, ": checksum mismatch (corrupt)");
  if (left_ != 0) fail(what_, ": ", left_, " unexpected bytes after the checksum");
}

}  // namespace softcut
