#pragma once
// A segmented label image as a LabeledShape for the mesher: at p the label
// whose indicator, trilinearly interpolated between voxel centres, is the
// largest (background included). Boundaries come out smooth and sub-voxel
// instead of the voxel staircase that mesh_label_volume() keeps.
#include <vector>

#include "mesh/mesher/shape.hpp"
#include "mesh/volume/nrrd.hpp"

namespace softcut::mesh {

// `keep`: the labels to mesh (others count as outside); empty: every nonzero
// label. Fails naming v.source when a kept label does not occur.
LabeledShape volume_shape(const LabelVolume& v, const std::vector<int>& keep);

}  // namespace softcut::mesh
