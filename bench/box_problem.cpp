#include "bench/box_problem.hpp"

#include "mesh/generate/box.hpp"

namespace softcut::bench {

BoxProblem box_problem(const BoxSpec& spec) {
  mesh::BoxOptions o;
  o.nx = spec.cells[0], o.ny = spec.cells[1], o.nz = spec.cells[2];
  o.max_corner = spec.size;
  o.jitter = spec.jitter;
  BoxProblem b{mesh::generate_box(o), {}, {}, {}};
  b.materials.assign(size_t(b.mesh.num_tets()), fem::Material{3e3, 0.45});
  b.fixed_mask.assign(size_t(b.mesh.num_nodes()), 0);
  if (spec.fixed_axis >= 0)
    for (int v = 0; v < b.mesh.num_nodes(); ++v)
      if (b.mesh.nodes(v, spec.fixed_axis) == 0) {  // the face's nodes sit exactly on it (jitter moves interior ones)
        b.fixed.push_back(v);
        b.fixed_mask[size_t(v)] = 1;
      }
  return b;
}

}  // namespace softcut::bench
