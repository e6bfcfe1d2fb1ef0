"""Elastic three-point bending of the thesis beam: quadratic tetrahedra (scikit-fem).

An independent cross-check of the project's own linear-tetrahedron solver: the same
boundary-value problem solved by code written by others (scikit-fem for the elements and the
assembly, SciPy / PyAMG for the linear algebra), with quadratic elements, on a sequence of
meshes, with a Richardson-extrapolated converged value.

Boundary-value problem
----------------------
Domain: the box  Omega = [0, Lx] x [0, Ly] x [0, Lz]  (metres), y vertical (the beam's depth),
z its width, x its length.

Small-strain isotropic linear elasticity, no body force:

    -div sigma(u) = 0                                   in Omega,
    sigma(u) = 2 mu eps(u) + lambda tr(eps(u)) I,       eps(u) = (grad u + grad u^T) / 2,
    lambda = E nu / ((1 + nu)(1 - 2 nu)),               mu = E / (2 (1 + nu)).

Boundary conditions (everything else is traction free, sigma n = 0):

  * supports: on each patch  {y = 0, x0 <= x <= x1, 0 <= z <= Lz}  of the bottom face,
    u_y = 0, and the tangential tractions are zero (a frictionless roller; u_x, u_z free);
  * loading plate: on the patch  {y = Ly, x0 <= x <= x1, 0 <= z <= Lz}  of the top face,
    u_y = d (the prescribed plate displacement, d < 0 downwards), tangential tractions zero;
  * pins: u_c = 0 for the listed components c at the listed points, only to remove the
    rigid-body modes that the y conditions leave (x and z translation, rotation about y).
    The problem has no x or z load, so these point constraints carry no force (their
    reactions are reported as a check) and do not change the solution.

Weak form: find u in H^1(Omega)^3 with the Dirichlet values above such that
    a(u, v) = int_Omega sigma(u) : eps(v) dx = 0   for all v vanishing on the Dirichlet set.

Discretisation
--------------
Each level is a tensor grid of (nx, ny, nz) hexahedral cells built by MeshTet.init_tensor from
numpy.linspace coordinates; init_tensor cuts each hexahedron into 6 tetrahedra (all along the
same main diagonal, so the mesh is NOT mirror-symmetric about mid-span: left and right support
reactions agree only up to the discretisation error, which is reported). The displacement is
ElementVector(ElementTetP2()): continuous piecewise quadratic, nodes at the vertices and the
edge midpoints, so the node spacing is half the cell size.

The Dirichlet conditions are imposed nodally: every P2 node (vertex or edge midpoint) lying on a
patch (coordinates compared with a tolerance of 1e-9 * max(Lx, Ly, Lz)) has its constrained
component fixed. The dofs are found by coordinate, not by facet markers. For this to represent
the patches exactly, their ends must be cell boundaries (vertex coordinates, multiples of the
cell size; an end at an edge midpoint only fixes the straddling face at two of its three nodes
along x, a mesh-dependent patch that spoils the convergence), and the pins and the deflection
points must be P2 nodes (multiples of half the cell size), on every level; a level for which
one is not raises ValueError naming it. With the request of the thesis beam (ends at 0.05,
0.15, 1.35, 1.65, 2.85, 2.95 m of a 3 m beam) nx must be a multiple of 60.

Reactions
---------
With no applied load, f = 0, the nodal force that the constraints exert on the beam is
r = K u - f = K u, evaluated at the constrained dofs. Reported, in newtons:
  * plate_force:   sum of r over the plate's y dofs: the force along y that the plate exerts on
                   the beam (negative = downwards, which it is for d < 0);
  * support_left / support_right (by the names in the request): sum of r over each support's
                   y dofs: the force along y that the support exerts on the beam (upwards
                   positive);
  * equilibrium_error: |plate_force + sum of supports| / |plate_force|, zero up to the solver's
                   residual (K annihilates a rigid y translation, so the sum of all y rows of
                   K u is zero; the free rows are zero up to the residual);
  * pin_reactions: the pins' reactions (should be zero up to the solver's residual).
Deflections: u_y (metres) at the requested points, which must be mesh nodes.

Convergence
-----------
The levels must refine all three axes by the same ratio (h = Lx / nx). From the last three
levels, with r1 = h1 / h2 and r2 = h2 / h3, the observed order p of each quantity solves
    (f1 - f2) / (f2 - f3) = r2^p (r1^p - 1) / (r2^p - 1)
(a scalar root find; r1 = r2 = r gives p = log((f1 - f2)/(f2 - f3)) / log r), and the
extrapolated value is f3 + (f3 - f2) / (r2^p - 1). The estimated relative error of the finest
level is |f3 - f_extrapolated| / |f_extrapolated|. When the differences change sign or do not
decrease (the order is not defined) the finest value is reported as the converged one, with a
note. Beware that the ends of the prescribed-displacement patches make the solution singular
(stresses ~ r^(-1/2) at the patch edges), so the observed orders are well below the P2 optimum.

Interface
---------
run(request: str) -> str: JSON request in, JSON answer out (see the README of this folder);
`python skfem_beam.py request.json` prints the answer. Progress goes to stderr only.
"""

import json
import math
import platform
import sys
import time
from datetime import datetime, timezone
from importlib import metadata

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.optimize import brentq

# Systems with at most this many free dofs are solved directly (SuperLU); larger ones by
# smoothed-aggregation AMG-preconditioned conjugate gradients, whose memory grows linearly.
DIRECT_MAX_FREE_DOFS = 60_000
# Relative residual ||b - A x|| / ||b|| asked of the iterative solver.
CG_TOL = 1e-11
# Elements assembled per chunk: keeps the COO triplets of one chunk (900 per element, 24 bytes
# each) to a few hundred MB, so the finest levels stay well under the memory budget.
CHUNK_ELEMENTS = 20_000


def _log(msg):
    print(f"[skfem_beam] {msg}", file=sys.stderr, flush=True)


def _provenance():
    packages = {}
    for name in ("numpy", "scipy", "scikit-fem", "pyamg"):
        try:
            packages[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            packages[name] = None
    return {
        "date": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "python": platform.python_version(),
        "packages": packages,
        "script": "skfem_beam.py",
    }


# ---------------------------------------------------------------------------------------------
# Request
# ---------------------------------------------------------------------------------------------

def _parse(req):
    size = [float(v) for v in req["size"]]
    if len(size) != 3 or min(size) <= 0:
        raise ValueError(f"size must be three positive lengths, got {req['size']}")
    young = float(req["young"])
    poisson = float(req["poisson"])
    if young <= 0 or not (-1.0 < poisson < 0.5):
        raise ValueError(f"bad material: young={young}, poisson={poisson}")

    def interval(obj, what):
        x0, x1 = (float(v) for v in obj["x"])
        if not (0.0 <= x0 < x1 <= size[0]):
            raise ValueError(f"{what}: x interval {obj['x']} not inside [0, {size[0]}]")
        return x0, x1

    supports = []
    for s in req["supports"]:
        supports.append({"name": str(s["name"]), "x": interval(s, f"support {s.get('name')}")})
    if len({s["name"] for s in supports}) != len(supports):
        raise ValueError("support names must be distinct")
    plate = req["plate"]
    plate = {"name": str(plate.get("name", "plate")), "x": interval(plate, "plate"),
             "displacement": float(plate["displacement"])}
    pins = []
    for p in req.get("pins", []):
        point = [float(v) for v in p["point"]]
        comps = [int(c) for c in p["components"]]
        if len(point) != 3 or any(c not in (0, 1, 2) for c in comps):
            raise ValueError(f"bad pin {p}")
        pins.append({"point": point, "components": comps})
    points = {str(k): [float(v) for v in p] for k, p in req["deflection_points"].items()}
    levels = []
    for lv in req["levels"]:
        lv = [int(n) for n in lv]
        if len(lv) != 3 or min(lv) < 1:
            raise ValueError(f"a level is three positive cell counts, got {lv}")
        levels.append(lv)
    if not levels:
        raise ValueError("no levels")
    return size, young, poisson, supports, plate, pins, points, levels


def _check_alignment(level, size, supports, plate, pins, points):
    """Raise ValueError naming the level unless (1) every patch end (supports, plate) is a
    VERTEX coordinate, i.e. a multiple of the cell size, and (2) the pins and the deflection
    points are P2 nodes (multiples of half the cell size).

    Why (1) and not merely "a node": with the ends on vertices the constrained P2 nodes are
    exactly the nodes of the boundary faces inside the patch, so u_y is prescribed on the whole
    patch and nowhere else (a face's trace is fixed by its six nodes). With an end at an edge
    midpoint, the face straddling the end has u_y fixed at two of the three nodes along x: the
    condition then holds only at points, the effective patch depends on the mesh, and the
    sequence of levels does not converge monotonically (seen: plate force -40989 N on 30 cells,
    -37996 N on 60, -38392 N on 90 along x, where 30 and 90 put the ends at midpoints)."""
    cell = [size[a] / level[a] for a in range(3)]
    tol = 1e-9 * max(size)
    needed = []  # (axis, value, spacing, what)
    for s in supports:
        needed += [(0, e, cell[0], f"support {s['name']} end (must be a cell boundary)")
                   for e in s["x"]]
    needed += [(0, e, cell[0], "plate end (must be a cell boundary)") for e in plate["x"]]
    for p in pins:
        needed += [(a, p["point"][a], cell[a] / 2, f"pin {p['point']} axis {a} (must be a P2 node)")
                   for a in range(3)]
    for name, pt in points.items():
        needed += [(a, pt[a], cell[a] / 2, f"deflection point {name} axis {a} (must be a P2 node)")
                   for a in range(3)]
    bad = []
    for axis, v, spacing, what in needed:
        k = round(v / spacing)
        if abs(v - k * spacing) > tol or v < -tol or v > size[axis] + tol:
            bad.append(f"{what} = {v}")
    if bad:
        raise ValueError(f"level {level} (cell size {cell}): " + "; ".join(bad))


# ---------------------------------------------------------------------------------------------
# One level
# ---------------------------------------------------------------------------------------------

def _rigid_body_modes(coords, comp):
    """The six rigid-body displacement fields at the dofs (dof j has component comp[j] at
    point coords[:, j]): the near-null space of elasticity, handed to smoothed aggregation."""
    n = coords.shape[1]
    B = np.zeros((n, 6))
    x, y, z = coords
    for c in range(3):
        B[comp == c, c] = 1.0
    # rotations about z, x, y (small rotation: u = omega x X)
    B[comp == 0, 3], B[comp == 1, 3] = -y[comp == 0], x[comp == 1]
    B[comp == 1, 4], B[comp == 2, 4] = -z[comp == 1], y[comp == 2]
    B[comp == 2, 5], B[comp == 0, 5] = -x[comp == 2], z[comp == 0]
    return B


def _solve_level(level, size, young, poisson, supports, plate, pins, points):
    # Imports here, so that importing the module (e.g. by the harness) is cheap and any failure
    # to import appears in the answer's error of the call.
    from skfem import Basis, ElementTetP2, ElementVector, MeshTet
    from skfem.assembly import Dofs
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    t0 = time.perf_counter()
    nx, ny, nz = level
    _check_alignment(level, size, supports, plate, pins, points)
    mesh = MeshTet.init_tensor(np.linspace(0.0, size[0], nx + 1),
                               np.linspace(0.0, size[1], ny + 1),
                               np.linspace(0.0, size[2], nz + 1))
    element = ElementVector(ElementTetP2())
    dofs = Dofs(mesh, element)
    N = int(dofs.N)
    nv, ne = mesh.p.shape[1], mesh.edges.shape[1]

    # P2 nodes: the vertices, then the edge midpoints; node_dofs[c, i] is the dof of component c
    # at node i (scikit-fem numbers the vertex dofs first, then the edge dofs).
    node_xyz = np.hstack([mesh.p, mesh.p[:, mesh.edges].mean(axis=1)])
    node_dofs = np.hstack([dofs.nodal_dofs, dofs.edge_dofs]).astype(np.int64)
    if node_dofs.shape != (3, nv + ne) or not np.array_equal(np.sort(node_dofs.ravel()),
                                                            np.arange(N)):
        raise RuntimeError("P2 vector dofs are not 3 per vertex and 3 per edge: "
                           "scikit-fem's numbering is not what this script assumes")
    dof_xyz = np.empty((3, N))
    dof_comp = np.empty(N, dtype=np.int64)
    for c in range(3):
        dof_xyz[:, node_dofs[c]] = node_xyz
        dof_comp[node_dofs[c]] = c

    lam, mu = lame_parameters(young, poisson)
    form = linear_elasticity(lam, mu)
    # Affine tetrahedra: the integrand eps(u):C:eps(v) of P2 functions is of degree 2, so
    # intorder=2 integrates the stiffness exactly (the default, 2 * maxdeg = 4, is wasteful).
    K = None
    nel = mesh.t.shape[1]
    for start in range(0, nel, CHUNK_ELEMENTS):
        chunk = np.arange(start, min(start + CHUNK_ELEMENTS, nel))
        first = start == 0
        basis = Basis(mesh, element, intorder=2, elements=chunk, dofs=dofs,
                      disable_doflocs=not first)
        if first:
            # Independent check of the coordinates given to the dofs above: scikit-fem's own
            # dof locations (mapped reference nodes) must agree wherever this chunk has dofs.
            used = np.unique(dofs.element_dofs[:, chunk])
            err = np.abs(basis.doflocs[:, used] - dof_xyz[:, used]).max()
            if err > 1e-9 * max(size):
                raise RuntimeError(f"dof coordinates disagree with scikit-fem's doflocs by {err}")
        Kc = form.assemble(basis)
        K = Kc if K is None else K + Kc
        del basis, Kc
    K = K.tocsr()
    t_asm = time.perf_counter() - t0

    # Dirichlet dofs, found by coordinate.
    tol = 1e-9 * max(size)
    X, Y = node_xyz[0], node_xyz[1]
    x_bc = np.zeros(N)
    constrained = {}  # dof -> value

    def fix(dof_list, value, what):
        if len(dof_list) == 0:
            raise ValueError(f"level {level}: {what} selects no node")
        for d in dof_list:
            d = int(d)
            if d in constrained and constrained[d] != value:
                raise ValueError(f"level {level}: {what} conflicts with another condition")
            constrained[d] = value

    support_dofs = {}
    for s in supports:
        x0, x1 = s["x"]
        nodes = np.nonzero((np.abs(Y) <= tol) & (X >= x0 - tol) & (X <= x1 + tol))[0]
        support_dofs[s["name"]] = node_dofs[1, nodes]
        fix(support_dofs[s["name"]], 0.0, f"support {s['name']}")
    x0, x1 = plate["x"]
    nodes = np.nonzero((np.abs(Y - size[1]) <= tol) & (X >= x0 - tol) & (X <= x1 + tol))[0]
    plate_dofs = node_dofs[1, nodes]
    fix(plate_dofs, plate["displacement"], "plate")

    def node_at(point, what):
        d = np.abs(node_xyz - np.asarray(point)[:, None]).max(axis=0)
        i = int(np.argmin(d))
        if d[i] > tol:
            raise ValueError(f"level {level}: {what} {point} is not a mesh node")
        return i

    pin_dofs = []
    for p in pins:
        i = node_at(p["point"], "pin")
        for c in p["components"]:
            pin_dofs.append((p["point"], c, int(node_dofs[c, i])))
            fix([node_dofs[c, i]], 0.0, "pin")

    D = np.fromiter(constrained.keys(), dtype=np.int64)
    x_bc[D] = np.fromiter(constrained.values(), dtype=float)
    free = np.ones(N, dtype=bool)
    free[D] = False
    I = np.nonzero(free)[0]

    # Condensed system A u_I = b, b = f_I - K_ID u_D with f = 0 (no body force, no traction).
    b = -(K @ x_bc)[I]  # x_bc vanishes on the free dofs, so this is -K_ID u_D
    # Keep only the constrained rows of K for the reactions, and drop K before the solve (the
    # largest matrices of the finest level would otherwise be held twice).
    K_D = K[D]
    A = K[I][:, I].tocsr()
    del K
    t1 = time.perf_counter()
    if len(I) <= DIRECT_MAX_FREE_DOFS:
        solver = "direct: scipy.sparse.linalg.splu (SuperLU, COLAMD ordering)"
        uI = spla.splu(A.tocsc()).solve(b)
    else:
        import pyamg
        from pyamg.krylov import cg
        B = _rigid_body_modes(dof_xyz[:, I], dof_comp[I])
        ml = pyamg.smoothed_aggregation_solver(A, B=B, symmetry="symmetric", max_coarse=500)
        res = []
        uI, info = cg(A, b, tol=CG_TOL, maxiter=2000, M=ml.aspreconditioner(cycle="V"),
                      residuals=res)
        solver = (f"pyamg {len(ml.levels)}-level smoothed aggregation (rigid-body modes "
                  f"as near-null space B) V-cycle preconditioned pyamg.krylov.cg, "
                  f"{len(res) - 1} iterations, tol {CG_TOL:g} (info {info})")
        del ml, B
    residual = float(np.linalg.norm(b - A @ uI) / np.linalg.norm(b))
    t_solve = time.perf_counter() - t1
    del A

    u = x_bc.copy()
    u[I] = uI
    # Internal force K u minus f = 0 at the constrained dofs: the force of the constraints on
    # the beam (zero at the free dofs up to the residual, so not needed there).
    r = np.zeros(N)
    r[D] = K_D @ u
    plate_force = float(r[plate_dofs].sum())
    reactions = {name: float(r[d].sum()) for name, d in support_dofs.items()}
    eq = abs(plate_force + sum(reactions.values())) / abs(plate_force)
    defl = {name: float(u[node_dofs[1, node_at(pt, f'deflection point {name}')]])
            for name, pt in points.items()}
    seconds = time.perf_counter() - t0
    out = {
        "cells": level,
        "elements": int(nel),
        "dofs": N,
        "free_dofs": int(len(I)),
        "seconds": round(seconds, 3),
        "seconds_assembly": round(t_asm, 3),
        "seconds_solve": round(t_solve, 3),
        "solver": solver,
        "residual": residual,
        "plate_force": plate_force,
        **reactions,
        "equilibrium_error": float(eq),
        "pin_reactions": [{"point": pt, "component": c, "force": float(r[d])}
                          for pt, c, d in pin_dofs],
        "deflection": defl,
    }
    _log(f"level {level}: {N} dofs, {seconds:.1f} s (assembly {t_asm:.1f}, solve "
         f"{t_solve:.1f}), residual {residual:.2e}, plate force {plate_force:.6g} N, "
         f"equilibrium {eq:.1e}")
    return out


# ---------------------------------------------------------------------------------------------
# Richardson extrapolation
# ---------------------------------------------------------------------------------------------

def _richardson(h, f):
    """Observed order and extrapolated value from the last three (h, f) pairs, h decreasing.
    Returns (value, order or None, estimated relative error or None, note)."""
    if len(f) < 3:
        return f[-1], None, None, "fewer than three levels: finest value, no estimate"
    (h1, h2, h3), (f1, f2, f3) = h[-3:], f[-3:]
    r1, r2 = h1 / h2, h2 / h3
    d12, d23 = f1 - f2, f2 - f3
    scale = max(abs(f1), abs(f2), abs(f3))
    if scale == 0.0 or max(abs(d12), abs(d23)) <= 1e-12 * scale:
        return f3, None, 0.0, "the same on the last three levels (to 1e-12): no discretisation error (e.g. prescribed)"
    if d23 == 0.0 or d12 == 0.0 or d12 / d23 <= 0.0:
        return f3, None, None, "differences change sign: order not defined, finest value"
    R = d12 / d23

    def g(p):
        return r2 ** p * (r1 ** p - 1.0) / (r2 ** p - 1.0) - R

    p_lo, p_hi = 1e-6, 30.0
    if g(p_lo) >= 0.0 or g(p_hi) <= 0.0:
        return f3, None, None, ("differences not decreasing fast enough for a positive order: "
                                "order not defined, finest value")
    p = brentq(g, p_lo, p_hi, xtol=1e-12)
    fe = f3 + (f3 - f2) / (r2 ** p - 1.0)
    err = abs(f3 - fe) / abs(fe) if fe != 0.0 else None
    return fe, float(p), (None if err is None else float(err)), "extrapolated"


def _converged(levels_out, size, support_names):
    h = [size[0] / lv["cells"][0] for lv in levels_out]
    quantities = {"plate_force": [lv["plate_force"] for lv in levels_out]}
    for k in support_names:
        quantities[k] = [lv[k] for lv in levels_out]
    for k in levels_out[0]["deflection"]:
        quantities[f"deflection.{k}"] = [lv["deflection"][k] for lv in levels_out]
    conv = {"deflection": {}}
    order, error, notes = {}, {}, {}
    for q, f in quantities.items():
        value, p, err, note = _richardson(h, f)
        if q.startswith("deflection."):
            conv["deflection"][q.split(".", 1)[1]] = value
        else:
            conv[q] = value
        order[q], error[q], notes[q] = p, err, note
    conv["order"] = order
    conv["estimated_relative_error"] = error
    conv["notes"] = notes
    if len(levels_out) >= 3:
        r = [h[-3] / h[-2], h[-2] / h[-1]]
        conv["method"] = (
            "Richardson extrapolation from the last three levels (h = Lx/nx, ratios "
            f"{r[0]:.4g} and {r[1]:.4g}): observed order p per quantity from "
            "(f1-f2)/(f2-f3) = r2^p (r1^p-1)/(r2^p-1) by brentq, extrapolated value "
            "f3 + (f3-f2)/(r2^p-1), estimated relative error |f3 - extrapolated|/|extrapolated|; "
            "where the order is not defined (see notes) the finest value is reported")
    else:
        conv["method"] = "fewer than three levels: the finest value, no extrapolation"
    return conv


# ---------------------------------------------------------------------------------------------
# Entry points
# ---------------------------------------------------------------------------------------------

def run(request: str) -> str:
    req = json.loads(request)
    size, young, poisson, supports, plate, pins, points, levels = _parse(req)
    # Richardson needs a single mesh size per level: refine the three axes alike.
    base = levels[0]
    for lv in levels:
        ratios = [lv[a] / base[a] for a in range(3)]
        if max(ratios) - min(ratios) > 1e-12:
            raise ValueError(f"level {lv} does not refine the three axes of {base} alike")
    # Check every level before spending time on any.
    for lv in levels:
        _check_alignment(lv, size, supports, plate, pins, points)
    levels_out = []
    for lv in levels:
        levels_out.append(_solve_level(lv, size, young, poisson, supports, plate, pins, points))
    answer = {
        "provenance": _provenance(),
        "method": (
            "scikit-fem, quadratic tetrahedra (ElementVector(ElementTetP2())), "
            "MeshTet.init_tensor (6 tetrahedra per hexahedral cell), small-strain isotropic "
            "linear elasticity (skfem.models.elasticity.linear_elasticity, exact quadrature of "
            "order 2), Dirichlet conditions imposed nodally at the P2 nodes found by coordinate "
            "(u_y on the support and plate patches, pins for the rigid-body modes), condensed "
            "system solved directly (small levels) or by AMG-preconditioned CG; reactions "
            "r = K u at the constrained dofs: plate_force = force of the plate on the beam along "
            "y (negative = downwards), supports = force of each support on the beam along y "
            "(upwards positive); deflections = u_y at the named nodes"),
        "levels": levels_out,
        "converged": _converged(levels_out, size, [s["name"] for s in supports]),
    }
    return json.dumps(answer, indent=2)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print("usage: python skfem_beam.py request.json", file=sys.stderr)
        sys.exit(2)
    with open(sys.argv[1]) as fh:
        print(run(fh.read()))
