#include "sim/selector.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "core/error.hpp"

namespace softcut::sim {

namespace {

std::string label_of(const std::string& item_where, const std::string& where) {
  return item_where.empty() ? where : item_where + ": " + where;
}

double diagonal(const mesh::TetMesh& m) {
  if (m.num_nodes() == 0) return 1.0;
  return (m.nodes.colwise().maxCoeff() - m.nodes.colwise().minCoeff()).norm();
}

bool in_box(const Eigen::Vector3d& x, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double tol) {
  return (x.array() >= lo.array() - tol).all() && (x.array() <= hi.array() + tol).all();
}

void check_shape(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double radius, const Eigen::Vector3d& normal,
                 bool is_box, bool is_sphere, bool is_half, const std::string& w) {
  if (is_box && (!lo.allFinite() || !hi.allFinite() || (hi.array() < lo.array()).any()))
    fail(w, ": box needs finite corners with min <= max on every axis (min = (", lo.transpose(), "), max = (",
         hi.transpose(), "))");
  if (is_sphere && !(radius >= 0 && std::isfinite(radius))) fail(w, ": sphere radius must be >= 0 m, got ", radius);
  if (is_half && !(normal.norm() > 0 && normal.allFinite())) fail(w, ": half-space normal must be nonzero");
}

std::vector<int> set_op(const std::vector<int>& a, const std::vector<int>& b, NodeSelector::Kind k) {
  std::vector<int> r;
  if (k == NodeSelector::Kind::union_of)
    std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(r));
  else if (k == NodeSelector::Kind::intersection)
    std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(r));
  else
    std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(r));
  return r;
}

void check_label_exists(const mesh::TetMesh& m, int label, const std::string& w) {
  for (int t = 0; t < m.num_tets(); ++t)
    if (m.labels(t) == label) return;
  fail(w, ": no tet has label ", label);
}

}  // namespace

std::vector<int> select_nodes(const NodeSelector& sel, const SelectContext& ctx, const std::string& where) {
  using K = NodeSelector::Kind;
  const std::string w = label_of(sel.where, where);
  const mesh::TetMesh& m = ctx.mesh;
  const std::vector<char> used = mesh::referenced_nodes(m);
  const double tol = sel.tolerance * diagonal(m);
  check_shape(sel.min, sel.max, sel.radius, sel.normal, sel.kind == K::box, sel.kind == K::sphere,
              sel.kind == K::halfspace, w);
  std::vector<int> out;
  auto keep_if = [&](auto pred) {
    for (int n = 0; n < m.num_nodes(); ++n)
      if (used[n] && pred(m.node(n))) out.push_back(n);
  };
  switch (sel.kind) {
    case K::all:
      keep_if([](const Eigen::Vector3d&) { return true; });
      break;
    case K::box:
      keep_if([&](const Eigen::Vector3d& x) { return in_box(x, sel.min, sel.max, tol); });
      break;
    case K::sphere:
      keep_if([&](const Eigen::Vector3d& x) { return (x - sel.center).norm() <= sel.radius + tol; });
      break;
    case K::halfspace: {
      const Eigen::Vector3d nrm = sel.normal.normalized();
      keep_if([&](const Eigen::Vector3d& x) { return (x - sel.point).dot(nrm) >= -tol; });
      break;
    }
    case K::label: {
      check_label_exists(m, sel.label, w);
      std::vector<char> mark(m.num_nodes(), 0);
      for (int t = 0; t < m.num_tets(); ++t)
        if (m.labels(t) == sel.label)
          for (int c = 0; c < 4; ++c) mark[m.tets(t, c)] = 1;
      for (int n = 0; n < m.num_nodes(); ++n)
        if (mark[n]) out.push_back(n);
      break;
    }
    case K::nodes:
      for (size_t k = 0; k < sel.ids.size(); ++k) {
        const int n = sel.ids[k];
        if (n < 0 || n >= m.num_nodes())
          fail(w, ": node id ", n, " (entry ", k + 1, ") is out of range: the mesh has ", m.num_nodes(),
               " nodes, ids 0..", m.num_nodes() - 1);
        if (!used[n]) fail(w, ": node ", n, " (entry ", k + 1, ") is used by no tet");
        out.push_back(n);
      }
      std::sort(out.begin(), out.end());
      out.erase(std::unique(out.begin(), out.end()), out.end());
      break;
    case K::surface:
      if (sel.label < 0) {
        out = ctx.surface.nodes;
      } else {
        check_label_exists(m, sel.label, w);
        std::vector<char> mask(m.num_tets(), 0);
        for (int t = 0; t < m.num_tets(); ++t) mask[t] = m.labels(t) == sel.label;
        out = mesh::extract_surface(m, mask).nodes;
      }
      break;
    case K::named: {
      auto it = ctx.named.find(sel.name);
      if (it == ctx.named.end()) {
        std::string known;
        for (const auto& [k, v] : ctx.named) known += (known.empty() ? "" : ", ") + k;
        fail(w, ": no node set named '", sel.name, "' (this mesh provides: ", known.empty() ? "none" : known, ")");
      }
      out = it->second;
      std::sort(out.begin(), out.end());
      out.erase(std::unique(out.begin(), out.end()), out.end());
      break;
    }
    case K::union_of:
    case K::intersection:
    case K::difference: {
      if (sel.children.empty()) fail(w, ": ", to_string(sel.kind), " needs at least one member");
      out = select_nodes(sel.children[0], ctx, w + " " + to_string(sel.kind) + "[1]");
      for (size_t k = 1; k < sel.children.size(); ++k)
        out = set_op(out, select_nodes(sel.children[k], ctx, cat(w, " ", to_string(sel.kind), "[", k + 1, "]")),
                     sel.kind);
      break;
    }
  }
  return out;
}

std::vector<int> select_tets(const TetSelector& sel, const SelectContext& ctx, const std::string& where) {
  using K = TetSelector::Kind;
  const std::string w = label_of(sel.where, where);
  const mesh::TetMesh& m = ctx.mesh;
  check_shape(sel.min, sel.max, sel.radius, sel.normal, sel.kind == K::box, sel.kind == K::sphere,
              sel.kind == K::halfspace, w);
  std::vector<int> out;
  auto keep_if = [&](auto pred) {
    for (int t = 0; t < m.num_tets(); ++t) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int k = 0; k < 4; ++k) c += m.node(m.tets(t, k));
      if (pred(t, Eigen::Vector3d(c / 4.0))) out.push_back(t);
    }
  };
  switch (sel.kind) {
    case K::all:
      keep_if([](int, const Eigen::Vector3d&) { return true; });
      break;
    case K::none:
      break;
    case K::label:
      check_label_exists(m, sel.label, w);
      keep_if([&](int t, const Eigen::Vector3d&) { return m.labels(t) == sel.label; });
      break;
    case K::box:
      keep_if([&](int, const Eigen::Vector3d& c) { return in_box(c, sel.min, sel.max, 0.0); });
      break;
    case K::sphere:
      keep_if([&](int, const Eigen::Vector3d& c) { return (c - sel.center).norm() <= sel.radius; });
      break;
    case K::halfspace: {
      const Eigen::Vector3d nrm = sel.normal.normalized();
      keep_if([&](int, const Eigen::Vector3d& c) { return (c - sel.point).dot(nrm) >= 0; });
      break;
    }
    case K::tets:
      for (size_t k = 0; k < sel.ids.size(); ++k) {
        const int t = sel.ids[k];
        if (t < 0 || t >= m.num_tets())
          fail(w, ": tet id ", t, " (entry ", k + 1, ") is out of range: the mesh has ", m.num_tets(),
               " tets, ids 0..", m.num_tets() - 1);
        out.push_back(t);
      }
      std::sort(out.begin(), out.end());
      out.erase(std::unique(out.begin(), out.end()), out.end());
      break;
    case K::union_of: {
      if (sel.children.empty()) fail(w, ": union_of needs at least one member");
      for (size_t k = 0; k < sel.children.size(); ++k) {
        std::vector<int> part = select_tets(sel.children[k], ctx, cat(w, " union_of[", k + 1, "]")), r;
        std::set_union(out.begin(), out.end(), part.begin(), part.end(), std::back_inserter(r));
        out.swap(r);
      }
      break;
    }
  }
  return out;
}

NodeSelector NodeSelector::box(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  NodeSelector s;
  s.kind = Kind::box, s.min = min, s.max = max;
  return s;
}
NodeSelector NodeSelector::sphere(const Eigen::Vector3d& center, double radius) {
  NodeSelector s;
  s.kind = Kind::sphere, s.center = center, s.radius = radius;
  return s;
}
NodeSelector NodeSelector::halfspace(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  NodeSelector s;
  s.kind = Kind::halfspace, s.point = point, s.normal = normal;
  return s;
}
NodeSelector NodeSelector::list(std::vector<int> ids) {
  NodeSelector s;
  s.kind = Kind::nodes, s.ids = std::move(ids);
  return s;
}
NodeSelector NodeSelector::combine(Kind op, std::vector<NodeSelector> children) {
  NodeSelector s;
  s.kind = op, s.children = std::move(children);
  return s;
}

const char* to_string(NodeSelector::Kind k) {
  using K = NodeSelector::Kind;
  switch (k) {
    case K::all: return "all";
    case K::box: return "box";
    case K::sphere: return "sphere";
    case K::halfspace: return "halfspace";
    case K::label: return "label";
    case K::nodes: return "nodes";
    case K::surface: return "surface";
    case K::named: return "named";
    case K::union_of: return "union";
    case K::intersection: return "intersection";
    case K::difference: return "difference";
  }
  return "?";
}

const char* to_string(TetSelector::Kind k) {
  using K = TetSelector::Kind;
  switch (k) {
    case K::all: return "all";
    case K::none: return "none";
    case K::label: return "label";
    case K::box: return "box";
    case K::sphere: return "sphere";
    case K::halfspace: return "halfspace";
    case K::tets: return "tets";
    case K::union_of: return "union";
  }
  return "?";
}

}  // namespace softcut::sim
