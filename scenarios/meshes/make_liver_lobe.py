#!/usr/bin/env python3
"""Writes liver_lobe.msh (Gmsh 2.2 ASCII) for scenarios/liver_retraction.lua.

A liver-lobe-like slab: rounded footprint 0.12 m x 0.08 m (x: left-right,
y: anterior(-) to posterior(+)), thick (0.04 m) on the right, thin (0.015 m)
toward the left and anterior edges, a domed upper face. Built from a
12 x 8 x 4 hex grid mapped onto that shape, each hex split into six tets
around its main diagonal (conforming). Label 1: parenchyma; label 2: a
stiffer lesion (tets whose centroid lies within 0.012 m of (0.02, 0.0, 0.018)).
Deterministic: rerunning gives the same bytes.
"""
import math
import os

NX, NY, NZ = 12, 8, 4
A, B = 0.06, 0.04  # semi-axes of the footprint, m


def shape(i, j, k):
    u = -1 + 2 * i / NX
    v = -1 + 2 * j / NY
    w = k / NZ
    # square -> rounded rectangle (a mild elliptic grid mapping keeps the
    # corner cells well shaped)
    x = A * u * math.sqrt(1 - 0.35 * v * v)
    y = B * v * math.sqrt(1 - 0.35 * u * u)
    r2 = (x / A) ** 2 + (y / B) ** 2
    thick = (0.015 + 0.025 * (u + 1) / 2) * (1 - 0.45 * r2) + 0.004 * (v + 1) / 2
    z = w * thick
    return x, y, z


def signed_volume(a, b, c, d):
    ab = [b[i] - a[i] for i in range(3)]
    ac = [c[i] - a[i] for i in range(3)]
    ad = [d[i] - a[i] for i in range(3)]
    cross = [ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]]
    return sum(cross[i] * ad[i] for i in range(3)) / 6


def main():
    nid = lambda i, j, k: i + (NX + 1) * (j + (NY + 1) * k)
    nodes = [shape(i, j, k) for k in range(NZ + 1) for j in range(NY + 1) for i in range(NX + 1)]
    # Kuhn split: the six tets of a cube around the diagonal (0,0,0)-(1,1,1)
    perms = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
    tets, labels = [], []
    for k in range(NZ):
        for j in range(NY):
            for i in range(NX):
                for p in perms:
                    c = [0, 0, 0]
                    vs = [nid(i, j, k)]
                    for axis in p:
                        c[axis] += 1
                        vs.append(nid(i + c[0], j + c[1], k + c[2]))
                    if signed_volume(*(nodes[n] for n in vs)) < 0:
                        vs[2], vs[3] = vs[3], vs[2]
                    tets.append(vs)
                    cx = sum(nodes[n][0] for n in vs) / 4
                    cy = sum(nodes[n][1] for n in vs) / 4
                    cz = sum(nodes[n][2] for n in vs) / 4
                    d = math.sqrt((cx - 0.02) ** 2 + cy ** 2 + (cz - 0.018) ** 2)
                    labels.append(2 if d < 0.012 else 1)
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "liver_lobe.msh")
    with open(out, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(nodes))
        for n, (x, y, z) in enumerate(nodes):
            f.write("%d %.9g %.9g %.9g\n" % (n + 1, x, y, z))
        f.write("$EndNodes\n$Elements\n%d\n" % len(tets))
        for e, (t, l) in enumerate(zip(tets, labels)):
            f.write("%d 4 2 %d %d %d %d %d %d\n" % (e + 1, l, l, t[0] + 1, t[1] + 1, t[2] + 1, t[3] + 1))
        f.write("$EndElements\n")


if __name__ == "__main__":
    main()
