//! Microplane directions and weights on the unit hemisphere (thesis 5.2.1, Fig. 5.2).
//!
//! Integrals over the sphere become `(3 / 2 pi) int_S g dS ~ 6 sum_l w_l g(n_l)` over one
//! hemisphere, the weights summing to 1/2 (MICROPLANE "Directions and integration").

use serde::{Deserialize, Serialize};

/// The quadrature on the sphere.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SphereRule {
    /// Bažant & Oh (1986), 21 directions, exact to degree 9 (the thesis' rule).
    #[default]
    BazantOh21,
    /// 37 directions (the M7 code's table, exact to degree 11), for sensitivity checks of the
    /// fracture direction bias.
    Bazant37,
}

impl SphereRule {
    /// Number of directions (microplanes) of the rule on the hemisphere.
    pub fn len(self) -> usize {
        match self {
            SphereRule::BazantOh21 => 21,
            SphereRule::Bazant37 => 37,
        }
    }

    /// Always `false`: every rule has directions (the pair of `len` that clippy asks for).
    pub fn is_empty(self) -> bool {
        false
    }

    /// `(n, w)` of every direction of the rule.
    pub fn points(self) -> Vec<([f64; 3], f64)> {
        match self {
            SphereRule::BazantOh21 => bazant_oh_21(),
            SphereRule::Bazant37 => bazant_37(),
        }
    }
}

/// Bažant & Oh (1986) Table 1, with the 12-digit constants of MICROPLANE.md.
// The table's own digits (not `FRAC_1_SQRT_2`): the calibration was made with them.
#[allow(clippy::approx_constant)]
fn bazant_oh_21() -> Vec<([f64; 3], f64)> {
    let (a, b, c) = (0.707106781187, 0.387907304067, 0.836095596749);
    let (w1, w2, w3) = (0.0265214244093, 0.0199301476312, 0.0250712367487);
    let mut p = vec![
        ([1.0, 0.0, 0.0], w1),
        ([0.0, 1.0, 0.0], w1),
        ([0.0, 0.0, 1.0], w1),
    ];
    for d in [
        [a, a, 0.0],
        [a, -a, 0.0],
        [a, 0.0, a],
        [a, 0.0, -a],
        [0.0, a, a],
        [0.0, a, -a],
    ] {
        p.push((d, w2));
    }
    for d in [
        [b, b, c],
        [b, -b, c],
        [b, b, -c],
        [b, -b, -c],
        [b, c, b],
        [b, -c, b],
        [b, c, -b],
        [b, -c, -b],
        [c, b, b],
        [c, -b, b],
        [c, b, -b],
        [c, -b, -b],
    ] {
        p.push((d, w3));
    }
    p
}

/// The 37-point rule of the public M7 code (`m7fmaterial.f`, SETSYSTEM; research notes 1.5).
// The table's own digits (not `FRAC_1_SQRT_2`): the calibration was made with them.
#[allow(clippy::approx_constant)]
fn bazant_37() -> Vec<([f64; 3], f64)> {
    let a = 0.707106781187;
    let (b1, c1) = (0.308951267775, 0.951077869651);
    let (c2, b2) = (0.880535518310, 0.335154591939);
    let d = 0.57735026919;
    let mut p = vec![
        ([1.0, 0.0, 0.0], 0.0107238857303),
        ([0.0, 1.0, 0.0], 0.0107238857303),
        ([0.0, 0.0, 1.0], 0.0107238857303),
    ];
    for v in [
        [a, a, 0.0],
        [a, -a, 0.0],
        [a, 0.0, a],
        [a, 0.0, -a],
        [0.0, a, a],
        [0.0, a, -a],
    ] {
        p.push((v, 0.0211416095198));
    }
    // permutations of (0, +-b1, c1), one hemisphere each: 12 points.
    for v in [
        [0.0, b1, c1],
        [0.0, -b1, c1],
        [0.0, c1, b1],
        [0.0, c1, -b1],
        [b1, 0.0, c1],
        [-b1, 0.0, c1],
        [c1, 0.0, b1],
        [c1, 0.0, -b1],
        [b1, c1, 0.0],
        [-b1, c1, 0.0],
        [c1, b1, 0.0],
        [c1, -b1, 0.0],
    ] {
        p.push((v, 0.00535505590837));
    }
    for v in [
        [c2, b2, b2],
        [c2, -b2, b2],
        [c2, b2, -b2],
        [c2, -b2, -b2],
        [b2, c2, b2],
        [-b2, c2, b2],
        [b2, c2, -b2],
        [-b2, c2, -b2],
        [b2, b2, c2],
        [-b2, b2, c2],
        [b2, -b2, c2],
        [-b2, -b2, c2],
    ] {
        p.push((v, 0.0167770909156));
    }
    for v in [[d, d, d], [-d, d, d], [d, -d, d], [-d, -d, d]] {
        p.push((v, 0.0188482309508));
    }
    p
}

/// One microplane: its normal, two tangents (5.2-5.4) and the weight of its direction, with the
/// projection tensors (5.8, 5.15, 5.16) stored in the 6-component form of [`Sym`].
#[derive(Debug, Clone, Copy)]
pub struct Microplane {
    /// Unit normal `n` of the plane (5.2), on the hemisphere.
    pub normal: [f64; 3],
    /// First unit tangent `m`, orthogonal to `n` (5.3).
    pub m: [f64; 3],
    /// Second unit tangent `k = m x n`, orthogonal to `n` and `m` (5.4).
    pub k: [f64; 3],
    /// Quadrature weight of the direction; the weights of a rule sum to 1/2 over the hemisphere.
    pub weight: f64,
    /// `N = n (x) n`.
    pub nn: Sym,
    /// `M = sym(m (x) n)`.
    pub mn: Sym,
    /// `K = sym(k (x) n)`.
    pub kn: Sym,
}

/// A symmetric tensor by its components `[11, 22, 33, 23, 13, 12]` (tensor, not engineering,
/// shears).
pub type Sym = [f64; 6];

/// `A : B` of two symmetric tensors.
#[inline(always)]
pub fn contract(a: &Sym, b: &Sym) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5])
}

fn sym_outer(a: &[f64; 3], b: &[f64; 3]) -> Sym {
    [
        a[0] * b[0],
        a[1] * b[1],
        a[2] * b[2],
        0.5 * (a[1] * b[2] + a[2] * b[1]),
        0.5 * (a[0] * b[2] + a[2] * b[0]),
        0.5 * (a[0] * b[1] + a[1] * b[0]),
    ]
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalized(a: [f64; 3]) -> [f64; 3] {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

impl Microplane {
    /// The plane of unit normal `n`; `m` is `n` crossed with the coordinate axis least aligned with
    /// it (a deterministic choice, made once), and `k = m x n` (5.4).
    pub fn new(normal: [f64; 3], weight: f64) -> Self {
        let n = normalized(normal);
        let axis = (0..3)
            .min_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs()))
            .unwrap_or(0);
        let mut e = [0.0; 3];
        e[axis] = 1.0;
        let m = normalized(cross(&n, &e));
        let k = cross(&m, &n);
        Self {
            normal: n,
            m,
            k,
            weight,
            nn: sym_outer(&n, &n),
            mn: sym_outer(&m, &n),
            kn: sym_outer(&k, &n),
        }
    }
}

/// The microplanes of a rule.
pub fn microplanes(rule: SphereRule) -> Vec<Microplane> {
    rule.points()
        .into_iter()
        .map(|(n, w)| Microplane::new(n, w))
        .collect()
}

/// The most microplanes a rule has (37), rounded up: the size of the per-update scratch arrays.
pub(super) const MAX_PLANES: usize = 40;

/// The projection tensors `N = n (x) n`, `M = sym(m (x) n)`, `K = sym(k (x) n)` of every plane,
/// stored component by component (`nn[i][p]` is component `i` of plane `p`), so that the strains
/// of all planes are six multiply-adds over contiguous arrays.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Projections {
    nn: [Vec<f64>; 6],
    mn: [Vec<f64>; 6],
    kn: [Vec<f64>; 6],
}

impl Projections {
    pub(super) fn new(planes: &[Microplane]) -> Self {
        assert!(
            planes.len() <= MAX_PLANES,
            "{} microplanes, at most {MAX_PLANES}",
            planes.len()
        );
        let component = |pick: fn(&Microplane) -> &Sym| -> [Vec<f64>; 6] {
            std::array::from_fn(|i| planes.iter().map(|p| pick(p)[i]).collect())
        };
        Self {
            nn: component(|p| &p.nn),
            mn: component(|p| &p.mn),
            kn: component(|p| &p.kn),
        }
    }

    /// `N : E`, `M : E`, `K : E` of every plane into `normal`, `along_m`, `along_k` (each as long
    /// as there are planes), with the sums in the order of [`contract`], so bitwise its values.
    #[inline(always)]
    pub(super) fn contract_all(
        &self,
        e: &Sym,
        normal: &mut [f64],
        along_m: &mut [f64],
        along_k: &mut [f64],
    ) {
        for (tensor, out) in [(&self.nn, normal), (&self.mn, along_m), (&self.kn, along_k)] {
            let [a0, a1, a2, a3, a4, a5] = tensor;
            let n = out.len();
            let (a0, a1, a2, a3, a4, a5) =
                (&a0[..n], &a1[..n], &a2[..n], &a3[..n], &a4[..n], &a5[..n]);
            for p in 0..n {
                out[p] = a0[p] * e[0]
                    + a1[p] * e[1]
                    + a2[p] * e[2]
                    + 2.0 * (a3[p] * e[3] + a4[p] * e[4] + a5[p] * e[5]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both rules integrate the even monomials of degree <= 8 exactly over the sphere:
    /// `<n_i^2> = 1/3`, `<n_1^2 n_2^2> = 1/15`, `<n_1^4> = 1/5`, with `<g> = 2 sum w g`.
    #[test]
    fn rules_reproduce_sphere_moments() {
        for rule in [SphereRule::BazantOh21, SphereRule::Bazant37] {
            let p = rule.points();
            assert_eq!(p.len(), rule.len());
            let avg =
                |g: &dyn Fn(&[f64; 3]) -> f64| 2.0 * p.iter().map(|(n, w)| w * g(n)).sum::<f64>();
            assert!((avg(&|_| 1.0) - 1.0).abs() < 1e-10, "{rule:?}");
            assert!((avg(&|n| n[0] * n[0]) - 1.0 / 3.0).abs() < 1e-10);
            assert!((avg(&|n| n[0].powi(4)) - 0.2).abs() < 1e-10);
            assert!((avg(&|n| (n[0] * n[1]).powi(2)) - 1.0 / 15.0).abs() < 1e-10);
            assert!((avg(&|n| n[2].powi(8)) - 1.0 / 9.0).abs() < 1e-10);
            assert!((avg(&|n| (n[0] * n[1] * n[2]).powi(2)) - 1.0 / 105.0).abs() < 1e-10);
        }
    }

    #[test]
    fn frames_are_orthonormal() {
        for plane in microplanes(SphereRule::Bazant37) {
            let d = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            assert!((d(&plane.m, &plane.m) - 1.0).abs() < 1e-14);
            assert!((d(&plane.k, &plane.k) - 1.0).abs() < 1e-14);
            assert!(d(&plane.m, &plane.normal).abs() < 1e-14);
            assert!(d(&plane.k, &plane.normal).abs() < 1e-14);
            assert!(d(&plane.m, &plane.k).abs() < 1e-14);
        }
    }
}
