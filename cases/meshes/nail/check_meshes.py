#!/usr/bin/env python3
"""Checks and measures the meshes of this folder (nail.msh, block.msh, block-path.msh, plate.msh).

For each file: every tetrahedron has a positive volume with its nodes in the file's order (the
solver's convention: (x1 - x0) x (x2 - x0) . (x3 - x0) > 0; it rejects inverted elements), every
physical group gives a non-empty node set, and the figures quoted in README.md: node and tetrahedron
counts, volume, edge lengths, smallest altitude, smallest and largest dihedral angle, Gmsh's gamma
quality, and the explicit time step h_min_altitude / c of the material.

Needs the gmsh Python module (pip install gmsh==4.15.2) and numpy. Run from anywhere:
    python3 check_meshes.py
Exits with status 1 if a check fails.
"""

import math
import os
import sys

import gmsh
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def p_wave_speed(E, nu, rho):
    """Dilatational wave speed sqrt(E (1 - nu) / (rho (1 + nu) (1 - 2 nu))) (m/s)."""
    return math.sqrt(E * (1 - nu) / (rho * (1 + nu) * (1 - 2 * nu)))


# file, expected physical groups, material (E, nu, rho), exact volume of the geometry (m^3)
A, PSI, L_SHANK = 0.002, 3.0, 0.040
S_ARC = PSI * 2 * A
L_NOSE = math.sqrt(S_ARC**2 - (S_ARC - A) ** 2)


def ogive_volume(a, s, l):
    """Exact volume of a tangent-ogive nose: pi * int_0^l (sqrt(s^2 - x^2) - (s - a))^2 dx."""
    c = s - a
    integral = (s * s + c * c) * l - l**3 / 3 - 2 * c * (
        0.5 * l * math.sqrt(s * s - l * l) + 0.5 * s * s * math.asin(l / s)
    )
    return math.pi * integral


NAIL_FULL = math.pi * A * A * L_SHANK + ogive_volume(A, S_ARC, L_NOSE)
MESHES = [
    ("nail.msh", ["nail", "sym_x", "sym_z", "tip"], (200e9, 0.3, 8000.0), NAIL_FULL / 4),
    ("block.msh", ["block", "sym_x", "sym_z", "bottom", "top"], (30e9, 0.18, 2300.0),
     0.25 * 0.5 * 0.25),
    ("block-path.msh", ["block", "sym_x", "sym_z", "bottom", "top"], (30e9, 0.18, 2300.0),
     0.25 * 0.5 * 0.25),
    ("plate.msh", ["plate", "sym_x", "sym_z", "top"], (200e9, 0.3, 8000.0),
     (0.05 * 0.05 - math.pi * 0.006**2 / 4) * 0.010),
]


def dihedral_angles(x):
    """The six dihedral angles (degrees) of the tetrahedron x (4 x 3)."""
    faces = [(1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1)]  # outward for a positive tetrahedron
    normals = []
    for f in faces:
        n = np.cross(x[f[1]] - x[f[0]], x[f[2]] - x[f[0]])
        normals.append(n / np.linalg.norm(n))
    angles = []
    for i in range(4):
        for j in range(i + 1, 4):
            angles.append(math.degrees(math.pi - math.acos(np.clip(normals[i] @ normals[j], -1, 1))))
    return angles


def check(name, groups, material, exact_volume):
    ok = True
    gmsh.clear()
    gmsh.open(os.path.join(HERE, name))
    tags, coords, _ = gmsh.model.mesh.getNodes()
    index = {int(t): i for i, t in enumerate(tags)}
    xyz = coords.reshape(-1, 3)
    etags, enodes = gmsh.model.mesh.getElementsByType(4)
    conn = np.array([index[int(n)] for n in enodes]).reshape(-1, 4)
    x = xyz[conn]  # (n, 4, 3)
    d1, d2, d3 = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]
    vol = np.einsum("ij,ij->i", np.cross(d1, d2), d3) / 6.0
    if not (vol > 0).all():
        print(f"{name}: {(vol <= 0).sum()} tetrahedra not positive")
        ok = False
    used = np.unique(conn)
    # edges
    pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    edges = np.stack([np.linalg.norm(x[:, j] - x[:, i], axis=1) for i, j in pairs], axis=1)
    # altitudes: 3 V / area of the opposite face
    faces = [(1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1)]
    areas = np.stack(
        [0.5 * np.linalg.norm(np.cross(x[:, b] - x[:, a], x[:, c] - x[:, a]), axis=1)
         for a, b, c in faces], axis=1)
    alt = 3 * vol[:, None] / areas
    min_alt = alt.min()
    ratio = (alt.min(axis=1) / edges.max(axis=1)).min()
    dih = np.array([dihedral_angles(t) for t in x])
    gamma = np.array(gmsh.model.mesh.getElementQualities(etags, "gamma"))
    E, nu, rho = material
    c = p_wave_speed(E, nu, rho)
    print(f"== {name}")
    print(f"  nodes (in tetrahedra) {len(used)}, tetrahedra {len(conn)}, nodes in file {len(tags)}")
    print(f"  volume {vol.sum():.6e} m^3, exact geometry {exact_volume:.6e} m^3,"
          f" error {vol.sum() / exact_volume - 1:+.2e}")
    print(f"  mass ({rho:g} kg/m^3): mesh {rho * vol.sum() * 1e3:.4f} g,"
          f" exact {rho * exact_volume * 1e3:.4f} g (quarter)")
    lo, hi = xyz[used].min(axis=0), xyz[used].max(axis=0)
    print(f"  bounding box {lo} .. {hi}")
    print(f"  edge min / mean / max: {edges.min() * 1e3:.3f} / {edges.mean() * 1e3:.3f} /"
          f" {edges.max() * 1e3:.3f} mm")
    print(f"  min altitude {min_alt * 1e3:.3f} mm; worst min altitude / longest edge {ratio:.3f}")
    print(f"  dihedral angle min / max: {dih.min():.1f} / {dih.max():.1f} deg")
    print(f"  gamma worst / mean: {gamma.min():.3f} / {gamma.mean():.3f}")
    print(f"  c = {c:.0f} m/s, dt = h_min_alt / c = {min_alt / c:.3e} s")
    for g in groups:
        found = [(d, t) for d, t in gmsh.model.getPhysicalGroups()
                 if gmsh.model.getPhysicalName(d, t) == g]
        n = 0
        for d, t in found:
            n += len(gmsh.model.mesh.getNodesForPhysicalGroup(d, t)[0])
        print(f"  node set {g!r}: {n} nodes")
        if n == 0:
            print(f"{name}: node set {g!r} is empty or missing")
            ok = False
    return ok


def main():
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    ok = all([check(*m) for m in MESHES])
    gmsh.finalize()
    print("all checks passed" if ok else "CHECKS FAILED")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
