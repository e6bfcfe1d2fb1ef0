//! The Hordijk tail of the tension law solved without iterating: a table of its inverse and one
//! Newton step.
//!
//! Past the peak, the tension law follows Hordijk's (1991) curve in the inelastic strain
//! (`ExponentialLaw::with_hordijk_tail`): at law strain `x` the inelastic strain `u` solves
//! `x = u + g_p H(k (u - u_p))`. With `y = k (u - u_p)`, `z = k (x - u_p)` and `a = k g_p` this is
//!
//! `F(y) = y + a H(y) = z`,  `y` in `[0, 1]`, `z` in `[a, 1]`,
//!
//! one equation in two parameters: `z` moves with the strain, `a` is fixed by the element's crack
//! band (`k = band / tail`). `F` rises monotonically while `a |H'|` stays below 1, which the crack
//! band guarantees (`ExponentialLaw::band_factor` refuses larger elements). Newton's method from
//! an explicit guess took four or five evaluations of `H` per call, a chain of dependent
//! latencies that made the tail 70 % of a tensile-softening update.
//!
//! Here `y(w, a)`, `w = (z - a) / (1 - a)` in `[0, 1]`, is tabulated as bicubic Hermite patches on
//! a uniform grid ([`CELLS_W`] by [`CELLS_A`] cells over `a` up to [`A_FRACTION`] of its
//! admissible limit), with the derivatives at the nodes from implicit differentiation of `F`:
//!
//! `y_w = (1 - a) / F'`,  `y_a = (1 - w - H) / F'`,  `y_wa = -(1 + (1 - a)(H' + a H'' y_a) / F') / F'`,
//!
//! `F' = 1 + a H'(y)`. The patch's guess is within `1e-6` of the root; one Newton step on `F`
//! squares that error (`|F'' / 2 F'| < 4` on the grid), to below `1e-12`. Both bounds are
//! measured, not assumed, by `tests::inverse_matches_the_iterated_root` on a dense sample of the
//! whole grid. Beyond the grid's `a` (elements within a fifth of the largest admissible size,
//! where `F'` at the peak falls toward 0) the caller iterates as before.

use super::tabulated::DecayTable;

/// Hordijk's `c1`.
const C1: f64 = 3.0;
/// Hordijk's `c2`: `H` decays like `exp(-c2 y)`.
pub(super) const HORDIJK_DECAY: f64 = 6.93;
/// `exp(-c2)`.
pub(super) const EXP_MINUS_C2: f64 = 0.000_978_000_868_395_394_6;
/// `(1 + c1^3) exp(-c2)`, the slope of the straight term that closes the curve at `y = 1`.
const CLOSURE: f64 = 28.0 * EXP_MINUS_C2;
/// Largest `|dH/dy|` (at `y = 0`): `c2 + (1 + c1^3) exp(-c2)`.
pub(super) const HORDIJK_STEEPEST: f64 = 6.93 + 28.0 * 0.000_977_7;

/// Cells of the table along `w`.
const CELLS_W: usize = 64;
/// Cells of the table along `a`.
const CELLS_A: usize = 16;
/// The table covers `a` up to this fraction of its limit `1 / |H'|max`, where `F' >= 1 - A_FRACTION`.
pub(super) const A_FRACTION: f64 = 0.6;
/// The grid is uniform in `xi = w^(1/GRADING)`: near `w = 0` (the peak), where `F'` changes
/// fastest, its cells are finest.
const GRADING: i32 = 2;

/// `(H, H', H'')` of Hordijk's curve at `y` without the cut at zero, given `decay = exp(-c2 y)`.
#[inline(always)]
pub(super) fn curve(y: f64, decay: f64) -> (f64, f64, f64) {
    let c = C1 * y;
    let cubic = 1.0 + c * c * c;
    let d_cubic = 3.0 * C1 * c * c;
    let dd_cubic = 6.0 * C1 * C1 * c;
    let h = cubic * decay - y * CLOSURE;
    let dh = (d_cubic - HORDIJK_DECAY * cubic) * decay - CLOSURE;
    let ddh =
        (dd_cubic - 2.0 * HORDIJK_DECAY * d_cubic + HORDIJK_DECAY * HORDIJK_DECAY * cubic) * decay;
    (h, dh, ddh)
}

/// The root of `y + a H(y) = z` by safeguarded Newton iteration with `exp` itself, to round-off:
/// the reference the table is built from and checked against.
pub(super) fn iterated_root(z: f64, a: f64) -> f64 {
    if z >= 1.0 {
        return 1.0;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut y = (z - a).clamp(lo, hi);
    for _ in 0..100 {
        let (h, dh, _) = curve(y, (-HORDIJK_DECAY * y).exp());
        let f = y + a * h - z;
        if f > 0.0 {
            hi = y;
        } else {
            lo = y;
        }
        let next = y - f / (1.0 + a * dh);
        let next = if next > lo && next < hi {
            next
        } else {
            0.5 * (lo + hi)
        };
        if (next - y).abs() <= 1e-17 {
            return next;
        }
        y = next;
    }
    y
}

/// `y(w, a)` of `y + a H(y) = z`, `z = a + w (1 - a)`, as bicubic Hermite patches (see the module
/// documentation).
#[derive(Clone, PartialEq)]
pub struct HordijkInverse {
    /// Largest `a` of the grid.
    a_max: f64,
    /// `1 / a_max`.
    inverse_a_max: f64,
    /// Per node `(i, j)` of `(xi, a)`, row-major in `xi`: `[y, y_xi, y_a, y_xia]` in grid units
    /// (derivatives times the cell widths).
    nodes: Vec<[f64; 4]>,
}

impl std::fmt::Debug for HordijkInverse {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HordijkInverse")
            .field("a_max", &self.a_max)
            .field("nodes", &self.nodes.len())
            .finish()
    }
}

impl Default for HordijkInverse {
    fn default() -> Self {
        Self::new()
    }
}

impl HordijkInverse {
    /// Builds the table (about 1100 roots, once per model).
    pub fn new() -> Self {
        let a_max = A_FRACTION / HORDIJK_STEEPEST;
        let (d_xi, da) = (1.0 / CELLS_W as f64, a_max / CELLS_A as f64);
        let mut nodes = Vec::with_capacity((CELLS_W + 1) * (CELLS_A + 1));
        for i in 0..=CELLS_W {
            let xi = i as f64 * d_xi;
            let w = xi.powi(GRADING);
            // dw / dxi: the derivatives in w times it are those in xi.
            let dw = GRADING as f64 * xi.powi(GRADING - 1) * d_xi;
            for j in 0..=CELLS_A {
                let a = j as f64 * da;
                let z = a + w * (1.0 - a);
                let y = iterated_root(z, a);
                let (h, dh, ddh) = curve(y, (-HORDIJK_DECAY * y).exp());
                let slope = 1.0 + a * dh;
                let y_w = (1.0 - a) / slope;
                let y_a = (1.0 - w - h) / slope;
                let y_wa = -(1.0 + (1.0 - a) * (dh + a * ddh * y_a) / slope) / slope;
                nodes.push([y, y_w * dw, y_a * da, y_wa * dw * da]);
            }
        }
        Self {
            a_max,
            inverse_a_max: 1.0 / a_max,
            nodes,
        }
    }

    /// Largest `a` the table covers; beyond it the caller iterates.
    pub fn a_max(&self) -> f64 {
        self.a_max
    }

    /// The table's guess of the root at `(z, a)`, `a` in `[0, a_max]`, `z` in `[a, 1]`.
    #[inline(always)]
    pub fn guess(&self, z: f64, a: f64) -> f64 {
        let w = ((z - a) / (1.0 - a)).clamp(0.0, 1.0).sqrt() * CELLS_W as f64;
        let v = (a * self.inverse_a_max).clamp(0.0, 1.0) * CELLS_A as f64;
        let i = (w as usize).min(CELLS_W - 1);
        let j = (v as usize).min(CELLS_A - 1);
        let (s, t) = (w - i as f64, v - j as f64);
        // Cubic Hermite basis: values h0, h1 and slopes g0, g1 on [0, 1].
        let basis = |x: f64| {
            let x2 = x * x;
            let x3 = x2 * x;
            (
                [2.0 * x3 - 3.0 * x2 + 1.0, -2.0 * x3 + 3.0 * x2],
                [x3 - 2.0 * x2 + x, x3 - x2],
            )
        };
        let ((hs, gs), (ht, gt)) = (basis(s), basis(t));
        let mut y = 0.0;
        for (di, (h_s, g_s)) in hs.iter().zip(gs).enumerate() {
            for (dj, (h_t, g_t)) in ht.iter().zip(gt).enumerate() {
                let n = &self.nodes[(i + di) * (CELLS_A + 1) + j + dj];
                y += h_s * h_t * n[0] + g_s * h_t * n[1] + h_s * g_t * n[2] + g_s * g_t * n[3];
            }
        }
        y
    }

    /// The root of `y + a H(y) = z` for `a` in `[0, a_max]` and `z` in `[a, 1)`: the table's guess
    /// and one Newton step, with `exp(-c2 y)` from `decay`.
    #[inline(always)]
    pub fn root(&self, z: f64, a: f64, decay: &DecayTable) -> f64 {
        let y = self.guess(z, a).clamp(0.0, 1.0);
        let (h, dh, _) = curve(y, decay.eval(y));
        y - (y + a * h - z) / (1.0 + a * dh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a sample of every cell (5 by 5 points each, and the nodes; and as many uniform in `w`),
    /// the guess lies within
    /// `1e-6` of the iterated root and the root after one Newton step within `1e-12`; the root
    /// solves the equation.
    #[test]
    fn inverse_matches_the_iterated_root() {
        let table = HordijkInverse::new();
        let decay = DecayTable::new(HORDIJK_DECAY, 1.0);
        let (mut worst_guess, mut worst_root): (f64, f64) = (0.0, 0.0);
        let n_w = CELLS_W * 5;
        let n_a = CELLS_A * 5;
        for (i, grid) in (0..=n_w).flat_map(|i| [(i, true), (i, false)]) {
            for j in 0..=n_a {
                let a = table.a_max() * j as f64 / n_a as f64;
                // Uniform in the grid's coordinate and uniform in w, up to just below w = 1
                // (z < 1: at z = 1 the caller returns zero stress).
                let t = i as f64 / n_w as f64;
                let w = if grid { t.powi(GRADING) } else { t }.min(1.0 - 1e-9);
                let z = a + w * (1.0 - a);
                let exact = iterated_root(z, a);
                let (h, _, _) = curve(exact, (-HORDIJK_DECAY * exact).exp());
                assert!(
                    (exact + a * h - z).abs() < 1e-15,
                    "F({exact}) at z = {z}, a = {a}"
                );
                worst_guess = worst_guess.max((table.guess(z, a) - exact).abs());
                worst_root = worst_root.max((table.root(z, a, &decay) - exact).abs());
            }
        }
        eprintln!("worst guess {worst_guess:.2e}, worst root {worst_root:.2e}");
        assert!(worst_guess < 1e-6, "guess off by {worst_guess}");
        assert!(worst_root < 1e-12, "root off by {worst_root}");
    }
}
