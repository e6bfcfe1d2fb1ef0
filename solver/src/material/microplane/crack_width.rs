//! The crack band measured across the crack (`crack_band: across_crack`): an element's band is
//! its width along the crack's normal, not its volume size `(6 V)^(1/3)`.
//!
//! A crack band element dissipates `h g` per unit crack area, with `g` the energy per unit
//! volume of its softening laws, and the band factors (`crack_band.rs`) make `h g = G_F` for the
//! element's `h`. That `h` must be the width of the band of material the crack softens, measured
//! along the crack's normal `n` (Oliver 1989, "A consistent characteristic length for smeared
//! cracking models", IJNME 28:461-474; Jirásek & Bauer 2012, "Numerical aspects of the crack
//! band approach", Computers & Structures 110-111:60-78). For an element much thinner across the
//! crack than its volume size, a crack running up a column of them (one strip of 0.625 mm
//! cells in 10 mm layers: `h = 1.57 mm`) softens a band of the column's width, and with the
//! volume size it dissipates `0.625 / 1.57 = 0.4 G_F`.
//!
//! **The width: Oliver's.** For a linear tetrahedron with shape functions `N_a`, Oliver's
//! (1989) length along the unit normal `n` is taken in its linear-element form
//!
//! `h(n) = 2 / sum_a |grad N_a . n|`,
//!
//! which, as `sum_a grad N_a = 0`, is `1 / sum_{grad N_a . n > 0} grad N_a . n`: the inverse of
//! the slope along `n` of the shape functions that rise along `n`. The projection of the element
//! on `n`, `w(n) = max_a x_a.n - min_a x_a.n`, bounds it: `sum_a (grad N_a . n) (x_a . n) = 1`
//! (the gradient of the linear field `x.n`) gives `1 <= w sum_{grad N_a . n > 0} grad N_a . n`,
//! so `h <= w`, with equality when the nodes lie on two planes normal to `n`. That is every
//! tetrahedron of a prism column cut across a straight crack, the case that sets the band in a
//! refined strip: there both give the column's width. Oliver's is used because it is not
//! thrown off by a normal slightly tilted toward the element's long side. In a layer of cells
//! 0.625 mm across and 10 mm thick, one tetrahedron through the layer (the 10 mm slice of the
//! notched beam, `cases/examples/notched-gregoire-d50-slice-10mm.yaml`), the principal direction
//! at the onset leaned out of the plane by `|n_z|` above 0.01 in 97 % of the onsets its Newton
//! iterations evaluated (presumably the faces' Poisson contraction, varying along the crack
//! front, read by one tetrahedron through the thickness as out-of-plane shear); with the
//! projection that slice peaked 3.4 % below the 0.625 mm slice. Tilted by `t`, `w = 0.625 cos t + 10 sin t` mm, 1.6 mm at `sin t = 0.1`,
//! while `h = 1 / (cos t / 0.625 + sin t / 10)` mm stays 0.624 mm: the projection weighs each
//! direction by the element's length along it, Oliver's by its inverse. Jirásek & Bauer (2012)
//! compare such definitions and show that for cracks inclined to a structured mesh no
//! element-wise length captures the band fully: this is a first-order correction, not a cure.
//!
//! **The crack's normal: one band per element, fixed at the crack's onset.** The first update in
//! which one of the element's tension laws (a plane's deviatoric tension, 5.19, or the
//! volumetric tension) passes its peak fixes `n` as the direction of the largest principal
//! stress of that update (the back-rotated stress, so in the reference configuration the width
//! is measured in), and that update is run again from the history before it with the band of
//! `h(n)`; from then on the element's laws use that band. Before the onset the band is the
//! volume size's, which changes nothing: every band factor scales only the post-peak part of its
//! law. The alternative, a band per microplane `w(n_p)` from the reference configuration, was
//! rejected: the volumetric tension law (with the equivalent driver) and the relaxation `psi`
//! soften with one band for the element and have no plane of their own, and planes oblique to
//! the crack, which soften inside the same crack, would take lengths up to the element's long
//! side (10 mm for a plane along the layer of a 0.625 x 10 mm strip cell), so the element's
//! energy per unit crack area would no longer be `G_F`. With one band per element every law
//! scales as with the volume size, `(6 V)^(1/3)` replaced by `h(n)`: an element of length `h`
//! across its crack dissipates what an element of volume size `h` did before
//! (`tests/microplane_crack_width.rs`). Shear-only failure (no tension law past its
//! peak) keeps the volume size's band.
//!
//! **Where it reduces to the volume size.** A tetrahedron of the six-tetrahedron cut of a cube of
//! edge `a` has `(6 V)^(1/3) = a` and `h = a` along the cube's axes: a crack normal to an axis of
//! a cube mesh gets the band it had (to the rounding of the two formulas). Along a face diagonal
//! it is `a / sqrt 2` or `a sqrt 2`, along the body diagonal `a sqrt 3`: an inclined crack in a
//! cube mesh now gets the band of its own direction.
//!
//! **Admissibility.** `h(n) <= w(n)`, at most the element's longest edge (the diameter of the four
//! nodes), so the snap-back check of `crack_band.rs` runs at setup on the longest edge: an element
//! whose longest edge is too large for its laws is refused before the run, whatever direction
//! its crack takes later.
//!
//! **History.** Three `f32` per element after the model's history ([`CRACK_HISTORY`]): the width
//! (0 before the onset) and the tension and shear band factors of that width.

use std::cell::RefCell;

use nalgebra::{Matrix3, SymmetricEigen};

use super::{state, CrackBand, CrackBandError, MicroplaneConcrete, Sym, UpdateInfo};

/// Number of `f32` values of history per element after the model's own: the band's width (m, 0
/// before the crack's onset), its tension and its shear factors.
pub const CRACK_HISTORY: usize = 3;

/// An element's reference shape, as far as its length along a direction needs it: the gradients
/// `grad N_1`, `grad N_2`, `grad N_3` of three of its shape functions (1/m; `grad N_0` is minus
/// their sum), and its longest edge (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementShape {
    gradients: [[f64; 3]; 3],
    longest_edge: f64,
}

impl ElementShape {
    /// The shape of the tetrahedron with nodes `corners` (reference configuration, m), or `None`
    /// for a degenerate one. The barycentric coordinates are `J^-1 (x - x_0)` with `J` the
    /// edges from the first node as columns, so `grad N_a` (a = 1, 2, 3) are the rows of `J^-1`.
    pub fn new(corners: &[[f64; 3]; 4]) -> Option<Self> {
        let edge =
            |a: usize| -> [f64; 3] { std::array::from_fn(|i| corners[a][i] - corners[0][i]) };
        let edges = [edge(1), edge(2), edge(3)];
        let j = Matrix3::from_fn(|i, a| edges[a][i]);
        let inverse = j.try_inverse()?;
        let gradients = std::array::from_fn(|a| std::array::from_fn(|i| inverse[(a, i)]));
        let length = |d: [f64; 3]| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let between = |x: [f64; 3], y: [f64; 3]| length(std::array::from_fn(|i| x[i] - y[i]));
        let [a, b, c] = edges;
        let longest_edge = [
            length(a),
            length(b),
            length(c),
            between(b, a),
            between(c, a),
            between(c, b),
        ]
        .into_iter()
        .fold(0.0, f64::max);
        Some(Self {
            gradients,
            longest_edge,
        })
    }

    /// Oliver's length `h(n) = 2 / sum_a |grad N_a . n|` along a unit vector `n` (m).
    pub fn width(&self, n: &[f64; 3]) -> f64 {
        let slope = |g: &[f64; 3]| g[0] * n[0] + g[1] * n[1] + g[2] * n[2];
        let [g1, g2, g3] = self.gradients.each_ref().map(slope);
        2.0 / ((g1 + g2 + g3).abs() + g1.abs() + g2.abs() + g3.abs())
    }

    /// The longest edge (m): no length along any direction is larger.
    pub fn longest_edge(&self) -> f64 {
        self.longest_edge
    }
}

/// The unit direction of the largest principal value of `s` (`[11, 22, 33, 23, 13, 12]`).
pub fn crack_normal(s: &Sym) -> [f64; 3] {
    let m = Matrix3::new(s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2]);
    let eigen = SymmetricEigen::new(m);
    let largest = eigen.eigenvalues.imax();
    let v = eigen.eigenvectors.column(largest).normalize();
    [v[0], v[1], v[2]]
}

thread_local! {
    /// The model's history before an update of an element whose crack has not yet started, to
    /// run that update again with the band across the crack when it starts (one per thread: the
    /// element loops run in parallel).
    static BEFORE: RefCell<Vec<f32>> = const { RefCell::new(Vec::new()) };
}

impl MicroplaneConcrete {
    /// The band of an element of the shape `shape` and the volume size's band `volume_band` whose
    /// widest crack (its longest edge) its laws admit, or why not: [`CrackBandError::TooWide`].
    pub fn check_widest_crack(
        &self,
        shape: &ElementShape,
        volume_band: &CrackBand,
    ) -> Result<(), CrackBandError> {
        let widest = shape.longest_edge();
        match self.crack_band_with_strength(widest, volume_band.strength) {
            Ok(_) => Ok(()),
            Err(_) => {
                let s2 = volume_band.strength * volume_band.strength;
                let h_ref = self.parameters.h_ref;
                Err(CrackBandError::TooWide {
                    width_mm: widest * 1e3,
                    strength: volume_band.strength,
                    largest_mm: (self.tension.largest_element(h_ref) / s2)
                        .min(self.shear.largest_element(h_ref))
                        * 1e3,
                })
            }
        }
    }

    /// Whether a tension law of the history `history` (the model's part) is past its peak: the
    /// volumetric one (its largest strain or driver reached, 5.19) or a plane's deviatoric one,
    /// against the peak strain `x_p e1` at the last update's rate factor and the element's
    /// strength factor `strength`.
    pub fn tension_peak_passed(&self, history: &[f32], strength: f64) -> bool {
        let f = history[state::RATE_FACTOR] as f64;
        let peak = self.tension.peak(f * strength * self.parameters.e1, 1.0).0;
        if history[state::V_TENSION] as f64 > peak {
            return true;
        }
        let planes = &history[state::HEADER..state::HEADER + state::PER_PLANE * self.planes.len()];
        planes
            .chunks_exact(state::PER_PLANE)
            .any(|p| p[state::D_POSITIVE] as f64 > peak)
    }

    /// [`MicroplaneConcrete::update`] with the band across the crack (module documentation):
    /// `history` is the model's history followed by [`CRACK_HISTORY`] values, `volume_band` the
    /// element's band of its volume size (and strength), `shape` its reference shape. The shape
    /// must have passed [`MicroplaneConcrete::check_widest_crack`].
    pub fn update_across_crack(
        &self,
        history: &mut [f32],
        strain: &Sym,
        gamma_dot: f64,
        volume_band: &CrackBand,
        shape: &ElementShape,
    ) -> (Sym, UpdateInfo) {
        let (laws, crack) = history.split_at_mut(self.state_len());
        if crack[0] > 0.0 {
            let band = CrackBand {
                size: crack[0] as f64,
                tension: crack[1] as f64,
                shear: crack[2] as f64,
                strength: volume_band.strength,
            };
            return self.update(laws, strain, gamma_dot, &band);
        }
        BEFORE.with_borrow_mut(|before| {
            before.clear();
            before.extend_from_slice(laws);
            let (s, info) = self.update(laws, strain, gamma_dot, volume_band);
            if !self.tension_peak_passed(laws, volume_band.strength) {
                return (s, info);
            }
            let width = shape.width(&crack_normal(&s));
            // Admitted at setup (the longest edge bounds every width); the volume size's band
            // stays should rounding put a width just past it.
            let band = self
                .crack_band_with_strength(width, volume_band.strength)
                .unwrap_or(*volume_band);
            crack[0] = band.size as f32;
            crack[1] = band.tension as f32;
            crack[2] = band.shear as f32;
            laws.copy_from_slice(before);
            self.update(laws, strain, gamma_dot, &band)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::ElementShape;

    const FRAC_1_SQRT_2: f64 = std::f64::consts::FRAC_1_SQRT_2;

    fn unit(v: [f64; 3]) -> [f64; 3] {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / l)
    }

    /// The corner tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1): `N_1 = x`, `N_2 = y`,
    /// `N_3 = z`, `N_0 = 1 - x - y - z`, so `grad N . n = (-n_x - n_y - n_z, n_x, n_y, n_z)`.
    #[test]
    fn width_of_the_corner_tetrahedron() {
        let t = ElementShape::new(&[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ])
        .unwrap();
        let cases = [
            // (-1, 1, 0, 0): 2 / 2 (the projection, 0 to 1, agrees: nodes on x = 0 and x = 1)
            ([1.0, 0.0, 0.0], 1.0),
            // a direction and its opposite give one length
            ([-1.0, 0.0, 0.0], 1.0),
            // (-sqrt3, 1, 1, 1) / sqrt3: 2 / (2 sqrt3) (projection 1/sqrt3 as well)
            ([1.0, 1.0, 1.0], 1.0 / 3f64.sqrt()),
            // (0, 1, -1, 0) / sqrt2: 2 / sqrt2 (projection -1/sqrt2 to 1/sqrt2 as well)
            ([1.0, -1.0, 0.0], 2.0 * FRAC_1_SQRT_2),
            // (-3, 2, 1, 0) / sqrt5: 2 sqrt5 / 6, below the projection 2 / sqrt5 (node 2 lies
            // between the extreme planes)
            ([2.0, 1.0, 0.0], 5f64.sqrt() / 3.0),
        ];
        for (n, w) in cases {
            let got = t.width(&unit(n));
            assert!((got - w).abs() < 1e-15, "{n:?}: {got} against {w}");
        }
        assert!((t.longest_edge() - 2f64.sqrt()).abs() < 1e-15);
    }

    /// A tetrahedron of the six-tetrahedron cut of a cube of edge a, (0,0,0), (a,0,0), (a,a,0),
    /// (a,a,a): `grad N = (-e_x, e_x - e_y, e_y - e_z, e_z) / a`. Along the axes `h = a =
    /// (6 V)^(1/3)`; along the diagonals, by the same sum, as below.
    #[test]
    fn width_of_a_cube_cut_tetrahedron() {
        let a = 0.002;
        let t =
            ElementShape::new(&[[0.0, 0.0, 0.0], [a, 0.0, 0.0], [a, a, 0.0], [a, a, a]]).unwrap();
        let h = (6.0 * a * a * a / 6.0f64).cbrt();
        for axis in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
            assert!((t.width(&axis) - h).abs() < 1e-18);
        }
        let cases = [
            // (-1, 0, 1, 0) / (a sqrt2): 2 / (2 / (a sqrt2))
            ([1.0, 1.0, 0.0], a * 2f64.sqrt()),
            // (-1, 2, -1, 0) / (a sqrt2): 2 / (4 / (a sqrt2))
            ([1.0, -1.0, 0.0], a * FRAC_1_SQRT_2),
            // (-1, 0, 0, 1) / (a sqrt3): a sqrt3, the body diagonal
            ([1.0, 1.0, 1.0], a * 3f64.sqrt()),
        ];
        for (n, w) in cases {
            let got = t.width(&unit(n));
            assert!((got - w).abs() < 1e-18, "{n:?}: {got} against {w}");
        }
        assert!((t.longest_edge() - a * 3f64.sqrt()).abs() < 1e-18);
    }

    /// A cell of a strip column 0.625 mm across (x), in a 10 mm layer (z), (0,0,0), (c,0,0),
    /// (c,c,0), (c,c,t): `grad N = (-e_x / c, (e_x - e_y) / c, e_y / c - e_z / t, e_z / t)`.
    /// Across the column its length is the column's, 0.625 mm, where its volume size is
    /// (6 V)^(1/3) = 1.57 mm; tilted by sin = 0.1 toward z it is `1 / (cos / c + sin / t)`,
    /// 0.6242 mm, where the projection `c cos + t sin` is 1.62 mm.
    #[test]
    fn width_of_a_strip_cell_across_the_column() {
        let (c, t) = (0.625e-3, 10e-3);
        let cell =
            ElementShape::new(&[[0.0, 0.0, 0.0], [c, 0.0, 0.0], [c, c, 0.0], [c, c, t]]).unwrap();
        assert!((cell.width(&[1.0, 0.0, 0.0]) - c).abs() < 1e-18);
        assert!((cell.width(&[0.0, 0.0, 1.0]) - t).abs() < 1e-17);
        let (sin, cos) = (0.1, 0.99f64.sqrt());
        let tilted = cell.width(&[cos, 0.0, sin]);
        let by_hand = 1.0 / (cos / c + sin / t);
        assert!(
            (tilted - by_hand).abs() < 1e-18,
            "{tilted} against {by_hand}"
        );
        assert!((tilted - 0.6242e-3).abs() < 1e-7);
        let volume = c * c * t / 6.0;
        assert!(((6.0 * volume).cbrt() - 1.5749e-3).abs() < 1e-7);
    }

    /// A flat tetrahedron has no shape.
    #[test]
    fn a_degenerate_tetrahedron_has_no_shape() {
        let flat = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
        assert!(ElementShape::new(&flat).is_none());
    }
}
