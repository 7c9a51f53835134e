#pragma once
// Checksummed binary streams for softcut's own cache files: every byte
// written or read goes into a CRC-32 (zlib), so a reader can tell a corrupt or
// truncated file from a good one before it uses anything it read. Sizes read
// from a file are checked against the bytes left before anything is allocated.
//
//   BinaryWriter w(out);  w.pod(n);  w.array(v.data(), v.size());  w.finish();
//   BinaryReader r(fd, file_size, "cache file x");
//   r.pod(n);  v.resize(r.count(sizeof(double)));  r.bytes(v.data(), ...);  r.finish();
#include <cstddef>
#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <type_traits>

namespace softcut {

class BinaryWriter {
 public:
  explicit BinaryWriter(std::ostream& out) : out_(out) {}
  void bytes(const void* p, size_t n);
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof v);
  }
  // A count (u64) then the elements.
  template <class T>
  void array(const T* p, size_t n) {
    static_assert(std::is_trivially_copyable_v<T>);
    pod(std::uint64_t(n));
    bytes(p, n * sizeof(T));
  }
  void finish();  // appends the CRC-32 of everything written before it

 private:
  std::ostream& out_;
  std::uint32_t crc_ = 0;
};

class BinaryReader {
 public:
  // Reads the open file `fd` from its start; `size`: its bytes; `what` names
  // it in errors. Large arrays are read and checksummed in two halves on two
  // threads (the cache's point is speed: a 0.5 GB entry in ~0.2 s).
  // `threads`: 0 = thread_policy() (core/threads.hpp); 1 reads on the calling thread only.
  BinaryReader(int fd, std::uint64_t size, std::string what, int threads = 0)
      : fd_(fd), left_(size), what_(std::move(what)), threads_(threads) {}
  void bytes(void* p, size_t n);  // throws softcut::Error when fewer than n bytes are left
  template <class T>
  void pod(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof v);
  }
  // Reads an array's count and checks that count elements of `elem` bytes
  // fit in what is left of the file (the 4-byte trailer included).
  size_t count(size_t elem);
  template <class T>
  void array_into(T* p, size_t n_expected) {
    if (count(sizeof(T)) != n_expected) fail_size();
    bytes(p, n_expected * sizeof(T));
  }
  // Checks the trailer against the CRC-32 of what was read, and that nothing follows it.
  void finish();
  const std::string& what() const { return what_; }

 private:
  [[noreturn]] void fail_size() const;
  int fd_;
  std::uint64_t offset_ = 0;
  std::uint64_t left_;
  std::string what_;
  std::uint32_t crc_ = 0;
  int threads_ = 0;
};

}  // namespace softcut
