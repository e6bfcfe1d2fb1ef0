#!/usr/bin/env python3
"""Empirical penetration depths of the nail of this folder into the thesis concrete.

Reproduces the numbers of PENETRATION-REFERENCE.md, section (d), and writes the speed-travel
curve of Forrestal's model that the nail case draws (forrestal-1994-speed.csv). Standard library
only:
    python3 penetration_reference.py

Formulas (SI units unless said):
  Forrestal, Altman, Cargile & Hanchak 1994 (rigid ogive-nose projectile, P > 4a):
    N    = (8 psi - 1) / (24 psi^2)                 nose factor of a tangent ogive
    S    = 82.6 fc^-0.544                           fc in MPa, S dimensionless
    V1^2 = (m Vs^2 - 4 pi a^3 S fc) / (m + 4 pi a^3 N rho)   speed at the end of the crater (z = 4a)
    P    = m / (2 pi a^2 rho N) ln(1 + N rho V1^2 / (S fc)) + 4a
  Modified NDRC (Kennedy 1976), SI form (Li et al. 2005):
    G    = 3.8e-5 N* M / (d sqrt(fc)) (V / d)^1.8   M kg, d m, fc Pa, V m/s
    x/d  = 2 G^0.5  for G <= 1,   x/d = G + 1  for G > 1
    N*   = 0.72 + 0.25 (psi - 0.25)^0.5 for an ogive nose (1.14 "very sharp" in Kennedy's table)
  Li & Chen 2003: Forrestal's model in dimensionless form, crater depth k d, k = 0.707 + h/d.
"""

import math
import os

# The nail of nail.geo (full, not the quarter): steel, 4 mm shank of 40 mm, tangent ogive psi = 3.
RHO_STEEL = 8000.0
A = 0.002                  # shank radius (m)
D = 2 * A
PSI = 3.0
L_SHANK = 0.040
S_ARC = PSI * D            # ogive arc radius
L_NOSE = math.sqrt(S_ARC**2 - (S_ARC - A) ** 2)  # = d sqrt(psi - 1/4)
MESH_QUARTER_VOLUME = 1.333786e-07  # m^3, nail.msh as generated (check_meshes.py)

# Impact and concrete (thesis 10.4)
VS = 200.0                 # striking speed (m/s)
FC_MPA = 45.0              # uniaxial compressive strength (MPa)
RHO_C = 2300.0             # concrete density (kg/m^3)


def ogive_volume(a, s, l):
    """pi * int_0^l (sqrt(s^2 - x^2) - (s - a))^2 dx, exactly."""
    c = s - a
    integral = (s * s + c * c) * l - l**3 / 3 - 2 * c * (
        0.5 * l * math.sqrt(s * s - l * l) + 0.5 * s * s * math.asin(l / s))
    return math.pi * integral


def forrestal_1994(m, a, psi, vs, fc_mpa, rho, verbose=True):
    fc = fc_mpa * 1e6
    n = (8 * psi - 1) / (24 * psi**2)
    s = 82.6 * fc_mpa**-0.544
    crater_energy = 4 * math.pi * a**3 * s * fc         # J: 1/2 m (Vs^2 - V1^2) = ... (see text)
    v1_sq = (m * vs**2 - crater_energy) / (m + 4 * math.pi * a**3 * n * rho)
    length = m / (2 * math.pi * a**2 * rho * n)
    arg = n * rho * v1_sq / (s * fc)
    p = length * math.log1p(arg) + 4 * a
    if verbose:
        print("Forrestal et al. 1994")
        print(f"  N = (8*{psi:g} - 1)/(24*{psi:g}^2) = {n:.5f}")
        print(f"  S = 82.6 * {fc_mpa:g}^-0.544 = {s:.4f};  S fc = {s * fc / 1e6:.2f} MPa")
        print(f"  m Vs^2 = {m * vs**2:.3f} J;  4 pi a^3 S fc = {crater_energy:.3f} J;"
              f"  4 pi a^3 N rho = {4 * math.pi * a**3 * n * rho:.4e} kg")
        print(f"  V1^2 = {v1_sq:.1f} m^2/s^2, V1 = {math.sqrt(v1_sq):.2f} m/s")
        print(f"  m/(2 pi a^2 rho N) = {length:.5f} m;  N rho V1^2/(S fc) = {arg:.5f};"
              f"  ln(1 + .) = {math.log1p(arg):.5f}")
        print(f"  P = {length * math.log1p(arg) * 1e3:.2f} mm + 4a = {4 * a * 1e3:.1f} mm"
              f" -> P = {p * 1e3:.2f} mm  (P/d = {p / (2 * a):.2f}; needs P > 4a: {p > 4 * a})")
    return p


def forrestal_speed_curve(m, a, psi, vs, fc_mpa, rho, gap, points=200):
    """The nail's speed against its tip's travel under Forrestal's force law (the same model as
    forrestal_1994): constant Vs across the gap, then the crater, F = c z for z <= 4a with
    c 4a = pi a^2 (S fc + N rho V1^2), so v^2 = Vs^2 - c z^2 / m; then the tunnel,
    m v dv/dz = -pi a^2 (S fc + N rho v^2), so
    v^2 = (S fc / (N rho) + V1^2) exp(-2 pi a^2 N rho (z - 4a) / m) - S fc / (N rho).
    Rows (tip displacement along the nail's motion, negative: -(gap + z); speed), to the stop."""
    fc = fc_mpa * 1e6
    n = (8 * psi - 1) / (24 * psi**2)
    s = 82.6 * fc_mpa**-0.544
    v1_sq = (m * vs**2 - 4 * math.pi * a**3 * s * fc) / (m + 4 * math.pi * a**3 * n * rho)
    c = math.pi * a**2 * (s * fc + n * rho * v1_sq) / (4 * a)
    stop = forrestal_1994(m, a, psi, vs, fc_mpa, rho, False)
    rows = [(0.0, vs)]
    for i in range(points + 1):
        z = stop * i / points
        if z <= 4 * a:
            v_sq = vs**2 - c * z * z / m
        else:
            k = s * fc / (n * rho)
            v_sq = (k + v1_sq) * math.exp(-2 * math.pi * a**2 * n * rho * (z - 4 * a) / m) - k
        rows.append((-(gap + z), math.sqrt(max(v_sq, 0.0))))
    return rows


def li_chen_2003(m, a, psi, nose_length, vs, fc_mpa, rho, verbose=True):
    """Forrestal's model in Li & Chen's dimensionless form, crater depth k d with
    k = 0.707 + h/d (h the nose length) instead of Forrestal's k = 2; same S and N."""
    d = 2 * a
    fc = fc_mpa * 1e6
    n = (8 * psi - 1) / (24 * psi**2)
    s = 82.6 * fc_mpa**-0.544
    impact = m * vs**2 / (d**3 * s * fc)          # I
    mass_ratio = m / (n * rho * d**3)            # N (Li & Chen's notation)
    k = 0.707 + nose_length / d
    x_over_d = (2 / math.pi) * mass_ratio * math.log(
        (1 + impact / mass_ratio) / (1 + k * math.pi / (4 * mass_ratio))) + k
    if x_over_d <= k:  # crater branch
        x_over_d = math.sqrt((1 + k * math.pi / (4 * mass_ratio)) / (1 + impact / mass_ratio)
                             * 4 * k * impact / math.pi)
    if verbose:
        print("Li & Chen 2003 form of the same model")
        print(f"  I = m Vs^2/(d^3 S fc) = {impact:.3f};  N = m/(N* rho d^3) = {mass_ratio:.2f};"
              f"  k = 0.707 + h/d = {k:.3f}")
        print(f"  X/d = {x_over_d:.3f} -> X = {x_over_d * d * 1e3:.2f} mm"
              f"  (with k = 2 this form gives Forrestal's P exactly)")
    return x_over_d * d


def ndrc_modified(m, d, psi, v, fc_mpa, verbose=True):
    fc = fc_mpa * 1e6
    n_star = 0.72 + 0.25 * math.sqrt(psi - 0.25)
    g = 3.8e-5 * n_star * m / (d * math.sqrt(fc)) * (v / d) ** 1.8
    x_over_d = 2 * math.sqrt(g) if g <= 1 else g + 1
    if verbose:
        print("Modified NDRC (Kennedy 1976)")
        print(f"  N* = 0.72 + 0.25 sqrt({psi:g} - 0.25) = {n_star:.4f}")
        print(f"  G = 3.8e-5 * {n_star:.4f} * {m:.5e} / ({d:g} * sqrt({fc:.3g}))"
              f" * ({v:g}/{d:g})^1.8 = {g:.4f}")
        branch = "2 G^0.5" if g <= 1 else "G + 1"
        print(f"  x/d = {branch} = {x_over_d:.3f} -> x = {x_over_d * d * 1e3:.2f} mm")
    return x_over_d * d


def main():
    v_exact = math.pi * A * A * L_SHANK + ogive_volume(A, S_ARC, L_NOSE)
    m = RHO_STEEL * v_exact
    m_mesh = RHO_STEEL * 4 * MESH_QUARTER_VOLUME
    print(f"nail: d = {D * 1e3:g} mm, shank {L_SHANK * 1e3:g} mm, ogive psi = {PSI:g},"
          f" s = {S_ARC * 1e3:g} mm, nose l = {L_NOSE * 1e3:.4f} mm,"
          f" total length {(L_SHANK + L_NOSE) * 1e3:.3f} mm")
    print(f"  volume: shank {math.pi * A * A * L_SHANK * 1e9:.3f} mm^3 + nose"
          f" {ogive_volume(A, S_ARC, L_NOSE) * 1e9:.3f} mm^3 = {v_exact * 1e9:.3f} mm^3")
    print(f"  mass: full {m * 1e3:.4f} g, quarter {m / 4 * 1e3:.4f} g"
          f" (mesh: full {m_mesh * 1e3:.4f} g, {m_mesh / m - 1:+.2%})")
    print(f"impact: Vs = {VS:g} m/s, fc = {FC_MPA:g} MPa, rho = {RHO_C:g} kg/m^3,"
          f" kinetic energy {0.5 * m * VS**2:.2f} J\n")
    p_f = forrestal_1994(m, A, PSI, VS, FC_MPA, RHO_C)
    print()
    p_n = ndrc_modified(m, D, PSI, VS, FC_MPA)
    print()
    li_chen_2003(m, A, PSI, L_NOSE, VS, FC_MPA, RHO_C)
    print()
    # The meshed nail's facets cut its cross-section and its mass by the same factor: it is a
    # nail of equivalent radius a sqrt(m_mesh / m) and mass m_mesh.
    a_eq = A * math.sqrt(m_mesh / m)
    print(f"the meshed nail (mass {m_mesh * 1e3:.4f} g, equivalent radius {a_eq * 1e3:.4f} mm):")
    print(f"  Forrestal {forrestal_1994(m_mesh, a_eq, PSI, VS, FC_MPA, RHO_C, False) * 1e3:.2f} mm,"
          f" NDRC {ndrc_modified(m_mesh, 2 * a_eq, PSI, VS, FC_MPA, False) * 1e3:.2f} mm")
    print("sensitivity (Forrestal / NDRC, mm):")
    for fc in (30.0, 45.0, 60.0):
        for v in (150.0, 200.0, 250.0):
            print(f"  fc {fc:4.0f} MPa, Vs {v:4.0f} m/s:"
                  f" {forrestal_1994(m, A, PSI, v, fc, RHO_C, False) * 1e3:6.2f}"
                  f" / {ndrc_modified(m, D, PSI, v, fc, False) * 1e3:6.2f}")
    # The curve the nail case draws beside its run (cases/penetration/nail-200ms.yaml): the
    # meshed nail, its tip 0.5 mm above the block at the start.
    curve = forrestal_speed_curve(m_mesh, a_eq, PSI, VS, FC_MPA, RHO_C, 0.5e-3)
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "forrestal-1994-speed.csv")
    with open(path, "w") as out:
        out.write("# Forrestal et al. 1994, the meshed nail (penetration_reference.py)\n")
        out.write("tip_y,speed\n")
        for x, v in curve:
            out.write(f"{x:.6e},{v:.4f}\n")
    print(f"wrote {path} ({len(curve)} rows, stop at {-curve[-1][0] * 1e3:.2f} mm of travel)")
    gm = math.sqrt(p_f * p_n)
    print(f"\ngeometric mean of the two: {gm * 1e3:.1f} mm; factor-2 band about it:"
          f" {gm / 2 * 1e3:.1f} to {gm * 2 * 1e3:.1f} mm")


if __name__ == "__main__":
    main()
