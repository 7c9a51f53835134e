// solve::Cholesky's numeric factor as bytes (the precompute cache) and back,
// with the loaded factor's own layout check.
#include <cstdint>

#include "core/binary_io.hpp"
#include "core/error.hpp"
#include "solve/supernodes.hpp"

namespace softcut::solve {

namespace {

// Why a loaded supernodal factor cannot be used, or "" when it can: what the
// solves read, in one pass over its row indices: Perm a permutation and the
// column counts in range; the supernodes tile 0..n-1, each one's rows start
// with its own columns and the rows below them increase within 0..n-1; each
// block is exactly rows x columns values and the arrays end where the last
// one does (CHOLMOD's own layout); and maxesize covers every supernode's rows
// below its columns, since cholmod_solve sizes its workspace by it.
// cholmod_check_factor is not used here: it visits every stored entry (66 ms
// of box_111132's 340 ms cache hit), lets a first supernode start past 0, the
// last end before n or a row index equal n, and does not check maxesize. A
// loaded factor is never refactored (factor() starts afresh), so maxcsize is
// not read.
std::string supernodal_problem(const cholmod_factor& L) {
  const long n = long(L.n);
  const int* perm = static_cast<const int*>(L.Perm);
  const int* count = static_cast<const int*>(L.ColCount);
  std::vector<char> seen(size_t(n), 0);
  for (long k = 0; k < n; ++k) {
    if (perm[k] < 0 || perm[k] >= n || seen[size_t(perm[k])]) return "its permutation repeats or leaves out a row";
    seen[size_t(perm[k])] = 1;
    if (count[k] < 0 || count[k] > n - k) return cat("column ", k, "'s count is out of range");
  }
  // First the small arrays, so that the pass over the row indices stays
  // inside them: supernode s's columns, rows and values follow s-1's.
  const Supernodes sn(L);
  if (sn.count < 1 && n > 0) return "it has no supernodes";
  if (sn.super[0] != 0 || sn.pi[0] != 0 || sn.px[0] != 0) return "its first supernode does not start at 0";
  long below = 0;
  for (int s = 0; s < sn.count; ++s) {
    const long nscol = sn.cols(s), nsrow = sn.rows(s);
    if (nscol < 1 || nsrow < nscol) return cat("supernode ", s, " has fewer rows than columns");
    if (long(sn.px[s + 1]) - sn.px[s] != nsrow * nscol) return cat("supernode ", s, "'s values are not rows x columns");
    below = std::max(below, nsrow - nscol);
  }
  if (sn.super[sn.count] != n) return "its supernodes do not cover its columns";
  if (size_t(std::max(1, sn.pi[sn.count])) != L.ssize || size_t(std::max(1, sn.px[sn.count])) != L.xsize)
    return "its row or value arrays do not end where its last supernode does";
  for (int s = 0; s < sn.count; ++s) {
    const int* rows = sn.Ls + sn.pi[s];
    for (long i = 0; i < sn.rows(s); ++i)
      if (i < sn.cols(s) ? rows[i] != sn.super[s] + i : (rows[i] >= n || rows[i] <= rows[i - 1]))
        return cat("supernode ", s, "'s row indices are out of place");
  }
  if (size_t(below) > L.maxesize) return "its maxesize is smaller than a supernode's rows below its columns";
  return {};
}

// The factor's layout, as saved (CHOLMOD int version, real LL').
struct FactorHeader {
  std::int64_t n = 0, minor = 0, is_super = 0, ordering = 0, is_monotonic = 0;
  std::int64_t nzmax = 0;                                           // simplicial
  std::int64_t nsuper = 0, ssize = 0, xsize = 0, maxcsize = 0, maxesize = 0;  // supernodal
};

template <class T>
T* alloc(size_t n, cholmod_common& c) {
  void* p = cholmod_malloc(std::max<size_t>(n, 1), sizeof(T), &c);
  if (!p) fail("Cholesky::load: out of memory for ", n, " entries");
  return static_cast<T*>(p);
}

}  // namespace

void Cholesky::save(BinaryWriter& w) const {
  if (!llt_) fail("Cholesky::save called before factor()");
  const cholmod_factor* L = llt_->raw();
  if (!L->is_ll || L->xtype != CHOLMOD_REAL || L->itype != CHOLMOD_INT)
    fail("Cholesky::save: only real LL' factors with int indices are saved");
  FactorHeader h;
  h.n = std::int64_t(L->n), h.minor = std::int64_t(L->minor), h.is_super = L->is_super, h.ordering = L->ordering;
  h.is_monotonic = L->is_monotonic;
  h.nzmax = std::int64_t(L->nzmax), h.nsuper = std::int64_t(L->nsuper), h.ssize = std::int64_t(L->ssize);
  h.xsize = std::int64_t(L->xsize), h.maxcsize = std::int64_t(L->maxcsize), h.maxesize = std::int64_t(L->maxesize);
  w.pod(h);
  const size_t n = size_t(L->n);
  w.array(static_cast<const int*>(L->Perm), n);
  w.array(static_cast<const int*>(L->ColCount), n);
  if (L->is_super) {
    const size_t ns = size_t(L->nsuper) + 1;
    w.array(static_cast<const int*>(L->super), ns);
    w.array(static_cast<const int*>(L->pi), ns);
    w.array(static_cast<const int*>(L->px), ns);
    w.array(static_cast<const int*>(L->s), size_t(L->ssize));
    w.array(static_cast<const double*>(L->x), size_t(L->xsize));
  } else {
    w.array(static_cast<const int*>(L->p), n + 1);
    w.array(static_cast<const int*>(L->i), size_t(L->nzmax));
    w.array(static_cast<const double*>(L->x), size_t(L->nzmax));
    w.array(static_cast<const int*>(L->nz), n);
    w.array(static_cast<const int*>(L->next), n + 2);
    w.array(static_cast<const int*>(L->prev), n + 2);
  }
  w.pod(lnz_);
}

void Cholesky::load(BinaryReader& r) {
  llt_.reset();
  item_.clear();
  items_ = 0;
  rows_ = 0;
  lnz_ = 0;
  flops_ = 0;
  FactorHeader h;
  r.pod(h);
  const std::string& what = r.what();
  // Every size is checked against the bytes left in the file before it is
  // allocated (BinaryReader::count), so a corrupt header cannot ask for more.
  if (h.n < 0 || h.n > (std::int64_t(1) << 31) - 3 || h.minor != h.n || (h.is_super != 0 && h.is_super != 1) ||
      h.nzmax < 0 || h.nsuper < 0 || h.ssize < 0 || h.xsize < 0 || h.maxcsize < 0 || h.maxesize < 0)
    fail(what, ": the saved Cholesky factor has an impossible header");
  auto llt = std::make_shared<Llt>();
  llt->cholmod().print = 0;
  cholmod_common& c = llt->cholmod();
  const size_t n = size_t(h.n);
  cholmod_factor* L = cholmod_allocate_factor(n, &c);
  if (!L) fail(what, ": out of memory for a factor of ", n, " rows");
  auto read_ints = [&](void*& dst, size_t count) {
    if (r.count(sizeof(int)) != count) fail(what, ": an array of the saved factor has the wrong size");
    int* p = alloc<int>(count, c);
    dst = p;
    r.bytes(p, count * sizeof(int));
  };
  auto read_doubles = [&](void*& dst, size_t count) {
    if (r.count(sizeof(double)) != count) fail(what, ": an array of the saved factor has the wrong size");
    double* p = alloc<double>(count, c);
    dst = p;
    r.bytes(p, count * sizeof(double));
  };
  try {
    r.array_into(static_cast<int*>(L->Perm), n);
    r.array_into(static_cast<int*>(L->ColCount), n);
    L->ordering = int(h.ordering);
    L->is_monotonic = int(h.is_monotonic);
    L->is_ll = 1;
    L->xtype = CHOLMOD_REAL;
    if (h.is_super) {
      L->is_super = 1;
      L->nsuper = size_t(h.nsuper), L->ssize = size_t(h.ssize), L->xsize = size_t(h.xsize);
      L->maxcsize = size_t(h.maxcsize), L->maxesize = size_t(h.maxesize);
      read_ints(L->super, L->nsuper + 1);
      read_ints(L->pi, L->nsuper + 1);
      read_ints(L->px, L->nsuper + 1);
      read_ints(L->s, L->ssize);
      read_doubles(L->x, L->xsize);
    } else {
      L->nzmax = size_t(h.nzmax);
      read_ints(L->p, n + 1);
      read_ints(L->i, L->nzmax);
      read_doubles(L->x, L->nzmax);
      read_ints(L->nz, n);
      read_ints(L->next, n + 2);
      read_ints(L->prev, n + 2);
    }
    L->minor = n;
    double lnz = 0;
    r.pod(lnz);
    if (L->is_super) {
      const std::string why = supernodal_problem(*L);
      if (!why.empty()) fail(what, ": the saved Cholesky factor is inconsistent: ", why);
    } else if (!cholmod_check_factor(L, &c)) {  // simplicial: small factors, one pass
      fail(what, ": the saved Cholesky factor is inconsistent (CHOLMOD status ", c.status, ")");
    }
    llt->adopt(L);
    L = nullptr;
    llt_ = std::move(llt);
    if (llt_->raw()->is_super) set_items();
    rows_ = int(n);
    lnz_ = lnz;
  } catch (...) {
    // A partly filled factor: cholmod_free_factor frees by the fields set so
    // far; arrays not read yet are null.
    if (L) cholmod_free_factor(&L, &c);
    throw;
  }
}

}  // namespace softcut::solve
