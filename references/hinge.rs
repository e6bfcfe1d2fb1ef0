//! An independent structural reference: the cohesive-crack hinge of a plain concrete beam in
//! three-point bending (Olesen 2001, "Fictitious crack propagation in fiber-reinforced concrete
//! beams", J. Eng. Mech. 127(3):272-280), fed with any stress-crack opening law `sigma(w)`.
//!
//! The hinge is a band of length `s = 0.5 h` (Olesen) at mid-span, made of independent
//! horizontal layers. Its two end faces stay plane and turn against each other by `phi`, the
//! total relative rotation of the hinge, so a layer at height `y` above the bottom face elongates
//! by `s eps(y)` with `eps(y) = (phi / s) (y0 - y)`, `y0` the height of the neutral axis. A layer
//! is linear elastic (modulus `E`, in compression throughout) up to the tensile strength
//! `f_t = sigma(0)`; beyond it, it carries `sigma = sigma(w)` with the crack opening
//! `w = s eps - s sigma / E` (the elongation less the elastic one).
//!
//! For each imposed `phi` the bottom strain `eps_b = (phi / s) y0` is found such that the normal
//! force vanishes (safeguarded regula falsi); the moment follows by the layers' midpoint sum.
//! Deflection at mid-span: `delta = P L^3 / (48 E I) + (phi - M s / (E I)) L / 4` with
//! `I = b h^3 / 12`, `P = 4 M / L`: the elastic beam (bending only, no shear term) plus the hinge
//! rotation beyond the elastic rotation of a beam segment of length `s` (which the first term
//! already holds). Laws that soften steeply snap back in deflection, so the hinge is driven by
//! rotation, which grows monotonically.
//!
//! The harness reference [`HingeSpec`] feeds it with the crack-opening law of the case's own
//! microplane material (`law: own`, from `crack_opening_curve`) or with the MC2010 or Hordijk
//! laws at that material's tensile strength and fracture energy.

/// A stress-crack opening law `sigma(w)` (Pa against m), zero past the end of its softening.
#[derive(Debug, Clone, PartialEq)]
pub enum SofteningLaw {
    /// `sigma = f_t (1 - w / w_c)` up to `w_c`.
    Linear {
        /// Tensile strength `f_t` (Pa).
        ft: f64,
        /// Opening `w_c` where the stress reaches zero (m).
        wc: f64,
    },
    /// fib MC2010 §5.1.8.2 bilinear law (`concrete::mc2010_bilinear_softening`).
    Mc2010 {
        /// Tensile strength `f_t` (Pa).
        ft: f64,
        /// Fracture energy `G_F` (N/m = J/m^2).
        gf: f64,
    },
    /// Hordijk (1991): `sigma / f_t = (1 + (c1 x)^3) exp(-c2 x) - x (1 + c1^3) exp(-c2)`,
    /// `x = w / w_c`, `c1 = 3`, `c2 = 6.93`, `w_c = 5.14 G_F / f_t`.
    Hordijk {
        /// Tensile strength `f_t` (Pa).
        ft: f64,
        /// Fracture energy `G_F` (N/m = J/m^2).
        gf: f64,
    },
    /// Piecewise linear through the points (`w` increasing from 0), zero past the last point.
    Tabulated {
        /// Crack openings (m), increasing from 0.
        w: Vec<f64>,
        /// Stress at each opening (Pa).
        sigma: Vec<f64>,
    },
}

impl SofteningLaw {
    /// The opening `w_c` past which the law carries no stress.
    pub fn critical_opening(&self) -> f64 {
        match self {
            SofteningLaw::Linear { wc, .. } => *wc,
            SofteningLaw::Mc2010 { ft, gf } => 5.0 * gf / ft,
            SofteningLaw::Hordijk { ft, gf } => 5.14 * gf / ft,
            SofteningLaw::Tabulated { w, .. } => w.last().copied().unwrap_or(0.0),
        }
    }

    /// `sigma(w)` (Pa); `sigma(0) = f_t`.
    pub fn stress(&self, w: f64) -> f64 {
        let w = w.max(0.0);
        match self {
            SofteningLaw::Linear { ft, wc } => ft * (1.0 - w / wc).max(0.0),
            SofteningLaw::Mc2010 { ft, gf } => {
                super::concrete::mc2010_bilinear_softening(w, *ft, *gf)
            }
            SofteningLaw::Hordijk { ft, gf } => super::concrete::hordijk_softening(w, *ft, *gf),
            SofteningLaw::Tabulated { w: ws, sigma } => {
                let n = ws.len();
                if n == 0 || w > ws[n - 1] {
                    return 0.0;
                }
                if w <= ws[0] {
                    return sigma[0];
                }
                let i = ws.partition_point(|&x| x <= w).clamp(1, n - 1);
                let (w0, w1, s0, s1) = (ws[i - 1], ws[i], sigma[i - 1], sigma[i]);
                if w1 <= w0 {
                    s1
                } else {
                    s0 + (s1 - s0) * (w - w0) / (w1 - w0)
                }
            }
        }
    }

    /// `f_t = sigma(0)`.
    pub fn tensile_strength(&self) -> f64 {
        self.stress(0.0)
    }

    /// `G_F = int_0^w_c sigma dw` (N/m): exact for the tabulated law, composite Simpson on
    /// 20 000 intervals otherwise.
    pub fn fracture_energy(&self) -> f64 {
        if let SofteningLaw::Tabulated { w, sigma } = self {
            return w
                .windows(2)
                .zip(sigma.windows(2))
                .map(|(w, s)| 0.5 * (s[0] + s[1]) * (w[1] - w[0]))
                .sum();
        }
        let (wc, n) = (self.critical_opening(), 20_000);
        let dw = wc / n as f64;
        let sum: f64 = (0..=n)
            .map(|i| {
                let weight = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                weight * self.stress(i as f64 * dw)
            })
            .sum();
        sum * dw / 3.0
    }
}

/// A root of `f` in `[a, b]`, where `f(a)` and `f(b)` differ in sign (or one is zero): the
/// Illinois variant of regula falsi, with a bisection step whenever the bracket shrinks slowly.
fn bracketed_root(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> f64 {
    let (mut fa, mut fb) = (f(a), f(b));
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    if (fa > 0.0) == (fb > 0.0) {
        return if fa.abs() <= fb.abs() { a } else { b };
    }
    let mut side = 0;
    for _ in 0..200 {
        let width = (b - a).abs();
        if width <= tol {
            break;
        }
        let mut c = (a * fb - b * fa) / (fb - fa);
        if !c.is_finite() || c <= a.min(b) || c >= a.max(b) {
            c = 0.5 * (a + b);
        }
        let fc = f(c);
        if fc == 0.0 {
            return c;
        }
        if (fc > 0.0) == (fb > 0.0) {
            b = c;
            fb = fc;
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            a = c;
            fa = fc;
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
        // Guard against a slow side: bisect when regula falsi kept less than half the bracket.
        if (b - a).abs() > 0.5 * width {
            let m = 0.5 * (a + b);
            let fm = f(m);
            if fm == 0.0 {
                return m;
            }
            if (fm > 0.0) == (fb > 0.0) {
                b = m;
                fb = fm;
            } else {
                a = m;
                fa = fm;
            }
            side = 0;
        }
    }
    0.5 * (a + b)
}

/// A beam in three-point bending with a cohesive hinge at mid-span.
#[derive(Debug, Clone, PartialEq)]
pub struct Hinge {
    /// Depth `h`, width `b`, span `L` (m).
    pub depth: f64,
    /// Width `b` (m).
    pub width: f64,
    /// Span `L` between the supports (m).
    pub span: f64,
    /// Hinge length `s` (m); Olesen takes `s = 0.5 h`.
    pub length: f64,
    /// Young's modulus `E` (Pa).
    pub youngs_modulus: f64,
    /// The stress-crack opening law of the layers once cracked.
    pub law: SofteningLaw,
    /// Number of layers over the depth.
    pub layers: usize,
    /// The layers' law before the crack opens: `None` linear up to `f_t` (Olesen), or the
    /// material's own rising branch, which the bulk of a smeared-crack beam follows.
    pub pre_peak: Option<PrePeak>,
    /// Depth of a notch at mid-span (m), 0 for none: the layers below it carry nothing, and the
    /// hinge spans the ligament, `s = 0.5 (h - a_0)` (Olesen's hinge on the ligament, as in its
    /// use for notched beams).
    pub notch: f64,
}

/// A rising stress-strain branch `(eps, sigma)` from the origin to the peak `(eps_p, f_t)`,
/// strains increasing. A layer follows it up to `eps_p`; past it the crack opens while the
/// layer's bulk unloads elastically from the peak, keeping its pre-peak inelastic strain
/// `eps_p - f_t / E`: the linear-hinge layer law at `eps - (eps_p - f_t / E)`.
#[derive(Debug, Clone, PartialEq)]
pub struct PrePeak {
    /// Strains `eps` of the branch, increasing from 0 to `eps_p` (dimensionless).
    pub strain: Vec<f64>,
    /// Stress at each strain (Pa), ending at `f_t`.
    pub stress: Vec<f64>,
}

impl PrePeak {
    /// The peak strain `eps_p`.
    pub fn peak_strain(&self) -> f64 {
        self.strain.last().copied().unwrap_or(0.0)
    }

    /// `sigma(eps)` for `0 <= eps <= eps_p`, linear between the points.
    fn stress(&self, eps: f64) -> f64 {
        let (e, s) = (&self.strain, &self.stress);
        let i = e.partition_point(|&x| x <= eps).clamp(1, e.len() - 1);
        let (e0, e1, s0, s1) = (e[i - 1], e[i], s[i - 1], s[i]);
        if e1 <= e0 {
            s1
        } else {
            s0 + (s1 - s0) * (eps - e0) / (e1 - e0)
        }
    }
}

/// One state of the hinge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HingePoint {
    /// Total relative rotation of the hinge (rad).
    pub rotation: f64,
    /// Bending moment (N m).
    pub moment: f64,
    /// Mid-span load `P = 4 M / L` (N).
    pub load: f64,
    /// Mid-span deflection (m).
    pub deflection: f64,
    /// Strain of the bottom fibre.
    pub bottom_strain: f64,
    /// Height of the crack tip (where the strain is `eps_p`, `f_t / E` for the linear pre-peak)
    /// above the bottom face (m), 0 uncracked (with a notch: the notch's depth included).
    pub crack_tip: f64,
}

/// The response of the hinge to a rising rotation.
#[derive(Debug, Clone, PartialEq)]
pub struct HingeCurve {
    /// The states at the grid rotations, from zero rotation upwards.
    pub points: Vec<HingePoint>,
    /// The point of largest moment, refined between the grid points around it.
    pub peak: HingePoint,
}

impl Hinge {
    /// Olesen's hinge (`s = h / 2`, 400 layers).
    pub fn new(depth: f64, width: f64, span: f64, youngs_modulus: f64, law: SofteningLaw) -> Self {
        Self {
            depth,
            width,
            span,
            length: 0.5 * depth,
            youngs_modulus,
            law,
            layers: 400,
            pre_peak: None,
            notch: 0.0,
        }
    }

    /// The same hinge on the ligament above a notch of depth `notch` at mid-span.
    pub fn with_notch(mut self, notch: f64) -> Self {
        self.notch = notch;
        self.length = 0.5 * (self.depth - notch);
        self
    }

    /// Depth of the ligament above the notch `h - a_0`.
    pub fn ligament(&self) -> f64 {
        self.depth - self.notch
    }

    /// The same hinge whose layers rise along `pre_peak` (its last point the peak, at the law's
    /// `f_t`) instead of linearly.
    pub fn with_pre_peak(mut self, pre_peak: PrePeak) -> Self {
        self.pre_peak = Some(pre_peak);
        self
    }

    /// The strain at which a layer reaches `f_t`: `f_t / E`, or the pre-peak branch's end.
    pub fn peak_strain(&self) -> f64 {
        match &self.pre_peak {
            Some(p) => p.peak_strain(),
            None => self.law.tensile_strength() / self.youngs_modulus,
        }
    }

    /// Second moment of area `b h^3 / 12`.
    pub fn inertia(&self) -> f64 {
        self.width * self.depth.powi(3) / 12.0
    }

    /// The rotation at which the bottom fibre of the ligament reaches `f_t` (in a linear
    /// section): `2 eps_p s / (h - a_0)`, `eps_p = f_t / E` for the linear pre-peak.
    pub fn cracking_rotation(&self) -> f64 {
        2.0 * self.peak_strain() * self.length / self.ligament()
    }

    /// Stress of a layer at strain `eps`: elastic up to `f_t / E`, then the root of
    /// `sigma = sigma_law(s eps - s sigma / E)` (the crack opening between 0 and `s eps`).
    /// With a pre-peak branch: that branch up to `eps_p`, then the same root at
    /// `eps - (eps_p - f_t / E)` ([`PrePeak`]); compression stays linear.
    pub fn layer_stress(&self, eps: f64) -> f64 {
        let (e, s) = (self.youngs_modulus, self.length);
        let ft = self.law.tensile_strength();
        let eps = match &self.pre_peak {
            Some(p) if eps > 0.0 && eps <= p.peak_strain() => return p.stress(eps),
            Some(p) if eps > 0.0 => eps - (p.peak_strain() - ft / e),
            _ => eps,
        };
        if e * eps <= ft {
            return e * eps;
        }
        // Written with the opening left to the elastic part, `s eps - w`, so that the bracket's
        // end `w = s eps` gives exactly `sigma_law(s eps) >= 0`.
        let wmax = s * eps;
        let g = |w: f64| self.law.stress(w) - e / s * (wmax - w);
        let w = bracketed_root(g, 0.0, wmax, 1e-15 * wmax.max(1e-12));
        e / s * (wmax - w)
    }

    /// Crack opening of a layer at strain `eps`: `w = s eps - s sigma / E` once it has passed
    /// `f_t` (with a pre-peak branch, from the branch's end on, the strain shifted as in
    /// [`Self::layer_stress`]), 0 before.
    pub fn layer_opening(&self, eps: f64) -> f64 {
        let (e, s) = (self.youngs_modulus, self.length);
        let ft = self.law.tensile_strength();
        let shifted = match &self.pre_peak {
            Some(p) if eps > p.peak_strain() => eps - (p.peak_strain() - ft / e),
            Some(_) => return 0.0,
            None => eps,
        };
        if e * shifted <= ft {
            return 0.0;
        }
        (s * shifted - s * self.layer_stress(eps) / e).max(0.0)
    }

    /// Height above the bottom face (m) where the crack opening of the state `p` falls to
    /// `w_front` (the opening front a crack-tip tracker follows): the openings fall with height,
    /// so the front is found by bisection between the ligament's bottom and the top; 0 when
    /// the lowest layer opens less than `w_front`.
    pub fn opening_front(&self, p: &HingePoint, w_front: f64) -> f64 {
        let k = p.rotation / self.length;
        let opening = |y: f64| self.layer_opening(p.bottom_strain - k * y);
        if !(k > 0.0) || opening(self.notch) < w_front {
            return 0.0;
        }
        let (mut lo, mut hi) = (self.notch, self.depth);
        if opening(hi) >= w_front {
            return hi;
        }
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if opening(mid) >= w_front {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    /// Normal force and moment (about mid-depth, bottom in tension positive) of the layers at
    /// curvature `k = phi / s` and bottom strain `eps_b`.
    fn section_forces(&self, k: f64, bottom_strain: f64) -> (f64, f64) {
        let n = self.layers;
        let dy = self.ligament() / n as f64;
        let (mut force, mut moment) = (0.0, 0.0);
        for i in 0..n {
            let y = self.notch + (i as f64 + 0.5) * dy;
            let sigma = self.layer_stress(bottom_strain - k * y);
            force += sigma;
            moment += sigma * (0.5 * self.depth - y);
        }
        (force * self.width * dy, moment * self.width * dy)
    }

    /// The state at rotation `phi`: the bottom strain lies between `k h / 2` (symmetric strains:
    /// the force is at most zero) and `k h` (the whole depth in tension: at least zero).
    pub fn state(&self, phi: f64) -> HingePoint {
        let k = phi / self.length;
        let h = self.depth;
        let bottom_strain = if phi <= 0.0 {
            0.0
        } else {
            // From the ligament's strains symmetric about its middle (force at most zero) to
            // the whole ligament in tension (at least zero); `eb` is the strain the plane
            // section gives at the beam's bottom face, `eb - k a_0` the ligament's lowest.
            bracketed_root(
                |eb| self.section_forces(k, eb).0,
                k * (self.notch + 0.5 * self.ligament()),
                k * h,
                1e-14 * k * h,
            )
        };
        let moment = self.section_forces(k, bottom_strain).1;
        let ei = self.youngs_modulus * self.inertia();
        let load = 4.0 * moment / self.span;
        let et = self.peak_strain();
        HingePoint {
            rotation: phi,
            moment,
            load,
            deflection: load * self.span.powi(3) / (48.0 * ei)
                + (phi - moment * self.length / ei) * self.span / 4.0,
            bottom_strain,
            crack_tip: if bottom_strain - k * self.notch > et && k > 0.0 {
                ((bottom_strain - et) / k).min(h)
            } else {
                0.0
            },
        }
    }

    /// The response from zero rotation: 20 steps to the cracking rotation, then steps of 2 %
    /// until the moment has fallen below 2 % of its peak (`stop_fraction`), the crack tip passes 0.98 h or the
    /// rotation reaches `max_rotation_ratio` times the cracking rotation. The peak is refined by
    /// golden-section search between the grid neighbours of the largest grid moment.
    pub fn curve(&self, max_rotation_ratio: f64) -> HingeCurve {
        self.curve_until(max_rotation_ratio, 0.02)
    }

    /// The peak alone: the curve stops once the moment has fallen below half its peak (a
    /// plain-concrete law's hinge does not rise again), about a third of the full curve's work.
    pub fn peak(&self, max_rotation_ratio: f64) -> HingePoint {
        self.curve_until(max_rotation_ratio, 0.5).peak
    }

    fn curve_until(&self, max_rotation_ratio: f64, stop_fraction: f64) -> HingeCurve {
        let phi_cr = self.cracking_rotation();
        let mut points: Vec<HingePoint> = (0..=20)
            .map(|i| self.state(phi_cr * i as f64 / 20.0))
            .collect();
        let mut phi = phi_cr;
        let mut best = points.last().expect("21 points").moment;
        while phi < max_rotation_ratio * phi_cr {
            phi *= 1.02;
            let p = self.state(phi);
            points.push(p);
            best = best.max(p.moment);
            if p.moment < stop_fraction * best || p.crack_tip > 0.98 * self.depth {
                break;
            }
        }
        let top = (0..points.len())
            .max_by(|&a, &b| points[a].moment.total_cmp(&points[b].moment))
            .expect("points");
        let lo = points[top.saturating_sub(1)].rotation;
        let hi = points[(top + 1).min(points.len() - 1)].rotation;
        let peak = self.refine_peak(lo, hi, points[top]);
        HingeCurve { points, peak }
    }

    /// Golden-section search for the largest moment on `[lo, hi]`.
    fn refine_peak(&self, mut lo: f64, mut hi: f64, grid_best: HingePoint) -> HingePoint {
        let r = 0.5 * (5f64.sqrt() - 1.0);
        let mut c = hi - r * (hi - lo);
        let mut d = lo + r * (hi - lo);
        let (mut pc, mut pd) = (self.state(c), self.state(d));
        for _ in 0..40 {
            if (hi - lo) <= 1e-10 * hi {
                break;
            }
            if pc.moment > pd.moment {
                hi = d;
                d = c;
                pd = pc;
                c = hi - r * (hi - lo);
                pc = self.state(c);
            } else {
                lo = c;
                c = d;
                pc = pd;
                d = lo + r * (hi - lo);
                pd = self.state(d);
            }
        }
        [grid_best, pc, pd]
            .into_iter()
            .max_by(|a, b| a.moment.total_cmp(&b.moment))
            .expect("three candidates")
    }
}

mod spec;
pub use spec::*;

#[cfg(test)]
mod tests;
