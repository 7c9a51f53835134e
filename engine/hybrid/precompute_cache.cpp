#include "hybrid/precompute_cache.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <sstream>

#include "core/atomic_file.hpp"
#include "core/binary_io.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/timer.hpp"

namespace softcut::hybrid {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'S', 'C', 'H', 'Y', 'B', 'R', 'I', 'D'};
constexpr std::uint32_t kFormat = 3;  // bump when the layout or the precompute's meaning or bits change

// Everything the precompute depends on, as bytes: compared exactly on a hit.
std::string input_bytes(const mesh::TetMesh& m, const std::vector<fem::Material>& mat, const Partition& p,
                        const PrecomputeOptions& opt) {
  std::ostringstream os;
  BinaryWriter w(os);
  w.pod(kFormat);
  w.array(m.nodes.data(), size_t(m.nodes.size()));
  w.array(m.tets.data(), size_t(m.tets.size()));
  w.array(mat.data(), mat.size());
  w.array(p.node_set.data(), p.node_set.size());
  w.array(p.operational_tet.data(), p.operational_tet.size());
  w.pod(std::int32_t(opt.storage));
  w.pod(opt.memory_budget_bytes);
  w.pod(opt.max_bytes);
  w.pod(std::int32_t(opt.block_columns));
  w.array(opt.initial_loads.data(), size_t(opt.initial_loads.size()));
  return os.str();
}

std::string key_of(const std::string& in) {
  const auto* b = reinterpret_cast<const unsigned char*>(in.data());
  const std::uint64_t k = (std::uint64_t(crc32_z(0, b, in.size())) << 32) | adler32_z(1, b, in.size());
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(k));
  return hex;
}

void write_matrix(BinaryWriter& w, const Eigen::MatrixXd& A) { w.array(A.data(), size_t(A.size())); }

// Reads a matrix that must have the given shape (known from the model).
void read_matrix(BinaryReader& r, Eigen::MatrixXd& A, Eigen::Index rows, Eigen::Index cols) {
  A.resize(rows, cols);
  r.array_into(A.data(), size_t(A.size()));
}

void write_payload(BinaryWriter& w, const Model& M) {
  w.pod(std::int32_t(M.storage));
  w.pod(M.memory);
  w.pod(M.timings);
  w.pod(std::int32_t(M.K22.factored()));
  if (M.K22.factored()) M.K22.save(w);
  const SparseMatrix& K = M.K2I;  // compressed column storage
  w.pod(std::int64_t(K.nonZeros()));
  w.array(K.outerIndexPtr(), size_t(K.outerSize()) + 1);
  w.array(K.innerIndexPtr(), size_t(K.nonZeros()));
  w.array(K.valuePtr(), size_t(K.nonZeros()));
  write_matrix(w, *M.K_prime);
  write_matrix(w, M.Kstar_inv);
  write_matrix(w, M.KI2_K22inv_s);
  write_matrix(w, M.Kstar_inv_Pstar);
  w.array(M.Kstar_inv_Ps0.data(), size_t(M.Kstar_inv_Ps0.size()));
  w.array(M.P_prime0.data(), size_t(M.P_prime0.size()));
}

void read_payload(BinaryReader& r, Model& M) {
  const Eigen::Index ns3 = 3 * Eigen::Index(M.ns()), ni3 = 3 * Eigen::Index(M.ni());
  const Eigen::Index n23 = 3 * Eigen::Index(M.nonop_nodes.size());
  std::int32_t storage = 0, factored = 0;
  r.pod(storage);
  if (storage != int(Storage::dense) && storage != int(Storage::product) && storage != int(Storage::factor))
    fail(r.what(), ": unknown storage mode ", storage);
  M.storage = Storage(storage);
  r.pod(M.memory);
  r.pod(M.timings);
  r.pod(factored);
  if (factored != (n23 > 0)) fail(r.what(), ": the K22 factor is ", factored ? "present" : "missing");
  if (factored) {
    M.K22.load(r);
    if (M.K22.rows() != n23) fail(r.what(), ": the K22 factor has ", M.K22.rows(), " rows, not ", n23);
  }
  std::int64_t nnz = 0;
  r.pod(nnz);
  if (nnz < 0 || nnz > n23 * ni3) fail(r.what(), ": K2I has an impossible ", nnz, " nonzeros");
  SparseMatrix K(n23, ni3);
  K.resizeNonZeros(Eigen::Index(nnz));
  r.array_into(K.outerIndexPtr(), size_t(ni3) + 1);
  r.array_into(K.innerIndexPtr(), size_t(nnz));
  r.array_into(K.valuePtr(), size_t(nnz));
  // The compressed structure must be valid before anything multiplies with it.
  const int* outer = K.outerIndexPtr();
  bool ok = outer[0] == 0 && outer[ni3] == nnz;
  for (Eigen::Index c = 0; ok && c < ni3; ++c) {
    ok = outer[c] <= outer[c + 1];
    for (int k = outer[c]; ok && k < outer[c + 1]; ++k)
      ok = K.innerIndexPtr()[k] >= 0 && K.innerIndexPtr()[k] < n23 && (k == outer[c] || K.innerIndexPtr()[k - 1] < K.innerIndexPtr()[k]);
  }
  if (!ok) fail(r.what(), ": K2I's sparse structure is invalid");
  M.K2I = std::move(K);
  M.KI2 = M.K2I.transpose();
  Eigen::MatrixXd Kp;
  read_matrix(r, Kp, ni3, ni3);
  M.K_prime = std::make_shared<const Eigen::MatrixXd>(std::move(Kp));
  const bool dense = M.storage == Storage::dense;
  read_matrix(r, M.Kstar_inv, dense ? ns3 : 0, dense ? ns3 : 0);
  read_matrix(r, M.KI2_K22inv_s, dense ? ni3 : 0, dense ? ns3 : 0);
  read_matrix(r, M.Kstar_inv_Pstar, M.has_Kstar_inv_Pstar() ? ns3 : 0, M.has_Kstar_inv_Pstar() ? ni3 : 0);
  M.Kstar_inv_Ps0.resize(ns3);
  r.array_into(M.Kstar_inv_Ps0.data(), size_t(ns3));
  M.P_prime0.resize(ni3);
  r.array_into(M.P_prime0.data(), size_t(ni3));
}

// Loads the entry into M (set up from the same inputs); returns the miss reason, empty on a hit.
std::string try_load(const fs::path& file, const std::string& inputs, Model& M) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return errno == ENOENT ? "no entry" : errno == ELOOP ? "not a regular file" : "unreadable";
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) return "unreadable";
  if (!S_ISREG(st.st_mode)) return "not a regular file";
  try {
    BinaryReader r(fd, std::uint64_t(st.st_size), "precompute cache " + file.string());
    char magic[sizeof kMagic];
    r.bytes(magic, sizeof magic);
    if (!std::equal(magic, magic + sizeof magic, kMagic)) return "not a softcut cache file";
    std::uint32_t format = 0;
    r.pod(format);
    if (format != kFormat) return cat("format version ", format, " (this softcut writes ", kFormat, ")");
    const size_t n = r.count(1);
    if (n != inputs.size()) return "inputs differ";
    std::string stored(n, '\0');
    r.bytes(stored.data(), n);
    if (stored != inputs) return "inputs differ";
    read_payload(r, M);
    r.finish();
  } catch (const Error& e) {
    return cat("corrupt: ", e.what());
  }
  return {};
}

// A temporary file of a write that was killed (SIGKILL, power loss) stays
// behind; one whose writer lives is flock()ed by it (write_file_atomic). A
// temporary file nobody locks and nobody has written for this long is stale.
// The age covers the moment between its creation and its lock.
constexpr auto kStaleTmpAge = std::chrono::seconds(60);

// True when `path` is a temporary file no live writer holds: its lock can be
// taken (flock works across processes and PID namespaces; a dead process's
// locks are gone), and it is old.
bool stale_tmp(const fs::path& path, fs::file_time_type written) {
  if (fs::file_time_type::clock::now() - written < kStaleTmpAge) return false;
  const UniqueFd fd(::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC));
  return fd && ::flock(fd.get(), LOCK_EX | LOCK_NB) == 0;  // closing the fd drops our lock
}

// Removes stale temporary files (".hybrid-<key>.bin.<pid>.<n>.tmp"), then the
// least recently used entries until all fit in max_bytes (keeping `keep`);
// the temporary files still being written count toward the bound.
int evict(const fs::path& dir, const fs::path& keep, double max_bytes, int* stale_removed) {
  struct Entry {
    fs::file_time_type time;
    std::uintmax_t size;
    fs::path path;
  };
  std::vector<Entry> all;
  double total = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (!e.is_regular_file(ec) || e.is_symlink(ec)) continue;
    const std::uintmax_t size = e.file_size(ec);
    if (ec) continue;
    if (name.rfind(".hybrid-", 0) == 0 && name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0) {
      const fs::file_time_type written = e.last_write_time(ec);
      if (!ec && stale_tmp(e.path(), written) && fs::remove(e.path(), ec)) ++*stale_removed;
      else total += double(size);
      continue;
    }
    if (name.rfind("hybrid-", 0) != 0 || e.path().extension() != ".bin") continue;
    Entry x{e.last_write_time(ec), size, e.path()};
    total += double(x.size);
    all.push_back(std::move(x));
  }
  std::sort(all.begin(), all.end(), [](const Entry& a, const Entry& b) { return a.time < b.time; });
  int removed = 0;
  for (const Entry& x : all) {
    if (total <= max_bytes) break;
    if (x.path == keep) continue;
    if (fs::remove(x.path, ec)) total -= double(x.size), ++removed;
  }
  return removed;
}

}  // namespace

fs::path default_cache_dir() {
  if (const char* d = std::getenv("SOFTCUT_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return fs::path(d) / "softcut";
  if (const char* d = std::getenv("HOME"); d && *d) return fs::path(d) / ".cache" / "softcut";
  return {};
}

Model precompute_cached(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material, const Partition& p,
                        const PrecomputeOptions& opt, const CacheOptions& cache, CacheReport* report) {
  CacheReport rep;
  if (cache.dir.empty()) {
    if (report) *report = rep;
    return precompute(m, tet_material, p, opt);
  }
  rep.enabled = true;
  Timer t;
  const std::string inputs = input_bytes(m, tet_material, p, opt);
  rep.key = key_of(inputs);
  const fs::path file = cache.dir / ("hybrid-" + rep.key + ".bin");
  rep.file = file.string();
  {
    Model M = setup_model(m, tet_material, p, opt);
    rep.miss_reason = try_load(file, inputs, M);
    if (rep.miss_reason.empty()) {
      build_operational(m, M);
      rep.hit = true;
      rep.load_ms = t.ms();
      rep.saved_ms = std::max(0.0, M.timings.total_ms - rep.load_ms);
      std::error_code ec;
      rep.bytes = double(fs::file_size(file, ec));
      fs::last_write_time(file, fs::file_time_type::clock::now(), ec);  // most recently used
      if (report) *report = rep;
      return M;
    }
  }
  Model M = precompute(m, tet_material, p, opt);
  Timer tw;
  try {
    std::error_code ec;
    fs::create_directories(cache.dir, ec);
    if (ec) fail("cannot create the cache folder ", cache.dir.string(), ": ", ec.message());
    rep.bytes = double(write_file_atomic(
        file,
        [&](std::ostream& os) {
          BinaryWriter w(os);
          w.bytes(kMagic, sizeof kMagic);
          w.pod(kFormat);
          w.array(inputs.data(), inputs.size());
          write_payload(w, M);
          w.finish();
        },
        true));
    rep.evicted = evict(cache.dir, file, cache.max_bytes, &rep.stale_removed);
  } catch (const std::exception& e) {
    rep.write_error = e.what();
  }
  rep.write_ms = tw.ms();
  if (report) *report = rep;
  return M;
}

}  // namespace softcut::hybrid
