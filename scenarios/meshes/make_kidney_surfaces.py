#!/usr/bin/env python3
"""Writes the surfaces of scenarios/kidney_surface.lua as a segmentation tool
would export them, in millimetres, with numpy and meshio (Debian python3-numpy,
python3-meshio), tools independent of softcut:

  kidney_mm.stl         binary STL, 5120 triangles: a bean-shaped kidney,
                        110 x 60 x 48 mm, long axis x, its hilum (the concave
                        middle) facing +y
  kidney_lesion_mm.obj  OBJ, 320 triangles: a spherical lesion of radius
                        7 mm at (25, -5, 2) mm, inside the kidney

Run from this folder: /usr/bin/python3 make_kidney_surfaces.py; then the tet
mesh the scenario loads is made once by the command in kidney_surface.lua.
"""
import meshio
import numpy as np


def icosphere(subdivisions):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    pts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        mid, g = {}, []

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                m = pts[a] + pts[b]
                pts.append(m / np.linalg.norm(m))
                mid[key] = len(pts) - 1
            return mid[key]

        for a, b, c in f:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            g += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = g
    return np.array(pts), np.array(f, dtype=np.int32)


def kidney():
    p, f = icosphere(4)
    x, y, z = 55 * p[:, 0], 30 * p[:, 1], 24 * p[:, 2]
    y = y - 6 * p[:, 0] ** 2                                                  # the bean's bend
    y = y - 11 * np.exp(-(p[:, 0] ** 2 + p[:, 2] ** 2) / 0.12) * np.clip(p[:, 1], 0, None) ** 2  # the hilum
    return np.column_stack([x, y, z]), f


def lesion():
    p, f = icosphere(2)
    return 7 * p + np.array([25.0, -5.0, 2.0]), f


def main():
    k, kf = kidney()
    meshio.write("kidney_mm.stl", meshio.Mesh(k, [("triangle", kf)]), binary=True)
    l, lf = lesion()
    meshio.write("kidney_lesion_mm.obj", meshio.Mesh(l, [("triangle", lf)]))


if __name__ == "__main__":
    main()
