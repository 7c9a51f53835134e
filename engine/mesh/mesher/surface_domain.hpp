#pragma once
// Closed surfaces as a labelled domain for the mesher: the first file's solid
// is label 1 (the organ), each later file's solid label 2, 3, ... (a lesion,
// a vessel: an inner surface overrides the outer one where it lies inside
// it). Within one file, nested pieces alternate (a cavity is outside the
// file's solid). Checks the surfaces a user brings, failing with the file,
// what is wrong and where: not closed (border edges, with their count and
// one), edges in more than two faces, pieces touching at a point,
// self-intersecting (two triangles that cross, with a point of each),
// enclosing no volume. Inconsistently oriented faces are turned, with a
// warning (code surface_reoriented); surfaces wound inward are turned
// silently (exporters differ on the convention).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "mesh/io/surface_io.hpp"
#include "mesh/mesher/shape.hpp"

namespace softcut::mesh {

// One closed, connected piece of surface.
struct Shell {
  Eigen::MatrixX3d points;     // (npoint x 3), m
  Eigen::MatrixX3i triangles;  // (ntri x 3), counter-clockwise seen from outside
  int inside = 0, outside = 0; // the labels on its two sides (0: outside every solid)
  double volume = 0;           // enclosed, m^3 (> 0)
  std::string where;           // "liver.stl (piece 2 of 3)", for messages
};

struct SurfaceDomain {
  std::string name;            // "surface liver.stl" (+ " + lesion.stl" ...), for messages
  std::vector<Shell> shells;   // those separating two different labels
  LabeledShape shape;          // the same labels by point-in-solid tests (sizing, estimates)
  std::vector<double> volumes; // (max label + 1) the volume of each label, m^3, from the surfaces; [0] unused
};

// Pieces of surface beyond this are refused (each is tested against every
// other for nesting).
inline constexpr int kMaxSurfacePieces = 1000;

// `soups` in their files' unit, each times `scale` (m per file unit, > 0);
// locations in messages are in the file's unit.
SurfaceDomain surface_domain(const std::vector<SurfaceSoup>& soups, double scale, Diagnostics& diag);

}  // namespace softcut::mesh
