//! Vertex-face continuous collision detection, the first local-detection strategy of the thesis
//! (section 7.4.4, equations (7.10)-(7.13); FORMULATION.md section 4, item 1).
//!
//! Over one step every node moves on a straight line, `x(t) = x(0) + t (x(1) - x(0))` with
//! `t` in `[0, 1]`. A slave node `p` can hit the face `(a, b, c)` only when the four points are
//! coplanar, i.e. at a root of the cubic (thesis (7.10), Provot 1997)
//!
//! `f(t) = ((b - a) x (c - a)) . (p - a) = a3 t^3 + a2 t^2 + a1 t + a0`          (7.13)
//!
//! and the hit is the earliest such root at which the node lies inside the triangle. The thesis
//! takes the roots as eigenvalues of the companion matrix (7.14); here they are bracketed instead
//! (faster, and no division by a possibly vanishing `a3`):
//! 1. the critical points of `f` (roots of the quadratic `f'`, solved in the stable
//!    `q = -(b + sign(b) sqrt(disc)) / 2` form) split `[0, 1]` into intervals where `f` is
//!    monotone, so each interval holds at most one root;
//! 2. an interval whose end values change sign holds a root, refined to full precision by
//!    Newton's method safeguarded by bisection;
//! 3. values of `f` below the rounding level `tol_f` (see `Motion::zero_tolerance`) count as
//!    zero. The set `{t : |f(t)| <= tol_f}` (one interval per monotone piece, its ends found by
//!    the same refinement) is where the node is in the plane *within rounding*; if the node is
//!    inside the triangle anywhere in it, that is a hit too. This one rule covers the degenerate
//!    cases explicitly: the node resting on the face at `t = 0` (the band starts at 0), a double
//!    root (`f` touching zero at a critical point without changing sign), an ill-conditioned
//!    root of nearly parallel motion, and the identically zero cubic of motion within the plane
//!    (the band is all of `[0, 1]`). Where the node is not inside at the start of a band, the
//!    times it may enter the triangle are the roots of three quartics (a weight reaching
//!    `-tolerance / 2`, see `Motion::earliest_inside`), isolated the same way. For in-plane
//!    motion this is exactly "check `t = 0` and the times the node crosses the (tolerance-offset)
//!    edge lines", for a face that may move, turn and deform within its plane.
//!
//! A vanishing leading coefficient needs no special case: the knots are `0`, `1` and whatever
//! critical points exist, and the stable quadratic formula degrades gracefully to the linear
//! root `-c0 / c1` (the other root becomes infinite and is discarded).

use nalgebra::Vector3;

pub mod touch;

/// Straight-line motion of a point over one step: position at t = 0 and at t = 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trajectory {
    /// Position at the start of the step, `t = 0` (m).
    pub start: Vector3<f64>,
    /// Position at the end of the step, `t = 1` (m).
    pub end: Vector3<f64>,
}

impl Trajectory {
    /// Position at the step fraction `t`: `x(t) = x(0) + t (x(1) - x(0))`, the constant
    /// velocity assumed over the step in thesis 7.4.4.
    pub fn at(&self, t: f64) -> Vector3<f64> {
        self.start + t * (self.end - self.start)
    }
}

/// A vertex-face collision found by [`vertex_face_ccd`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CcdHit {
    /// Step fraction in `[0, 1]` of the first contact.
    pub t: f64,
    /// barycentric weights (N_a, N_b, N_c) of the contact point on the face at time t
    pub weights: [f64; 3],
}

/// `tol_f = ZERO_FACTOR * eps * scale`: generous enough to cover the rounding of the
/// coefficients and of Horner's rule (a few `eps` each), small enough to stay far below any
/// physically meaningful gap.
const ZERO_FACTOR: f64 = 64.0;

/// A band of coplanarity (within rounding) narrower than this, in step fractions, is reported at
/// its best time (the root, or the critical point of a double root) rather than at its start:
/// both are equally valid contact times, and the root is the accurate one.
const SNAP: f64 = 1e-6;

/// Root refinement stops when the step or the bracket is below this, relative to `t`: a few
/// units in the last place.
const T_TOL: f64 = 2.0 * f64::EPSILON;

/// Safety cap on Newton/bisection iterations; bisection alone needs about 55 on `[0, 1]`.
const MAX_ITERATIONS: usize = 128;

/// Earliest t in [0, 1] at which the node lies in the plane of the moving triangle (a, b, c) and
/// inside it (barycentric weights >= -tolerance), or None.
///
/// Coplanarity is the root of the cubic (7.13) with the coefficients (7.12), taken relative to
/// `a` (see `Motion::coplanarity_cubic`). "In the plane" means `|f(t)| <= tol_f`, the rounding
/// level of `f` (see `Motion::zero_tolerance`): around each root, or each near-touch of zero,
/// this is a band of times, and the hit is the earliest time in the earliest band at which the
/// node is inside. For a well-conditioned crossing the band is only a few ulps wide and the
/// reported time is the root itself, refined to full precision; a band narrower than `1e-6`
/// (a double root, say) is reported at the root or the critical point if the node is inside
/// there too; a wide band (nearly parallel or in-plane motion) at the earliest time inside.
/// `weights` are the barycentric weights of the node's projection on the face at that time.
///
/// A node that starts on the face (`f(0) = 0`, inside) is reported at `t = 0` whatever its
/// velocity, also when it is leaving the face: the test is geometric, and the caller (global
/// detection found the node inside a master element at the end of the step) can tell a
/// separating node from the relative normal velocity. A face that is degenerate (a segment or a
/// point) at a time has no weights and gives no hit at that time. `tolerance` should be at least
/// about `1e-12` so that rounding in the weights cannot reject a contact exactly on an edge.
///
/// Where no crossing is found, a point that comes within the minimum separation
/// [`touch::minimum_separation`] (1e-12 of the largest coordinate) of the triangle during the
/// step, from farther at its start, touches it ([`touch::earliest_touch`]): the hit is the first such time, with the
/// weights of the triangle's point nearest the node.
pub fn vertex_face_ccd(
    node: &Trajectory,
    face: [&Trajectory; 3],
    tolerance: f64,
) -> Option<CcdHit> {
    let motion = Motion::new(node, face);
    let cubic = motion.coplanarity_cubic();
    let tol_f = motion.zero_tolerance();
    if !tol_f.is_finite() {
        return None;
    }

    // Knots: 0, the critical points inside (0, 1) in increasing order, 1. Between two knots f is
    // monotone.
    let mut knots = [0.0; 4];
    let mut count = 1;
    let mut critical = quadratic_roots([cubic[1], 2.0 * cubic[2], 3.0 * cubic[3]]);
    if critical[0] > critical[1] {
        critical.swap(0, 1);
    }
    for t in critical {
        // NaN and infinities fail this test.
        if t > 0.0 && t < 1.0 {
            knots[count] = t;
            count += 1;
        }
    }
    knots[count] = 1.0;
    count += 1;
    let values = knots.map(|t| horner(&cubic, t));

    for i in 0..count - 1 {
        let (t0, t1, f0, f1) = (knots[i], knots[i + 1], values[i], values[i + 1]);
        let crosses = (f0 < 0.0 && f1 > 0.0) || (f0 > 0.0 && f1 < 0.0);
        let near_zero = f0.abs() <= tol_f || f1.abs() <= tol_f;
        if !crosses && !near_zero {
            continue;
        }
        // The point of the piece closest to the plane: the root, or the end nearer to zero.
        let mut root = None;
        let best = if crosses {
            let guess = regula_falsi(t0, t1, f0, f1);
            let t = refine(|t| horner(&cubic, t), &cubic, 0.0, t0, t1, f0, guess);
            root = Some(t);
            t
        } else if f0.abs() <= f1.abs() {
            t0
        } else {
            t1
        };
        // The rounding band of this piece: where it enters and leaves |f| <= tol_f.
        let band_edge = |f_end: f64, t_end: f64| {
            if f_end.abs() <= tol_f {
                return t_end;
            }
            let level = tol_f.copysign(f_end);
            let shifted = [cubic[0] - level, cubic[1], cubic[2], cubic[3]];
            // Start Newton from the root's linearisation when there is one: it is next to it.
            let guess = match root {
                Some(t) => t + level / horner_derivative(&cubic, t),
                None => regula_falsi(t0, t1, f0 - level, f1 - level),
            };
            refine(
                |t| horner(&shifted, t),
                &shifted,
                0.0,
                t0,
                t1,
                f0 - level,
                guess,
            )
        };
        let enter = band_edge(f0, t0);
        if let Some(weights) = motion.inside(enter, tolerance) {
            // Inside where the band begins. A narrow band (a well-conditioned root) is reported
            // at its most accurate time, `best`, if the node is inside there too; a wide one
            // (nearly parallel or in-plane motion) at its start, the earliest contact.
            if best - enter <= SNAP {
                if let Some(weights) = motion.inside(best, tolerance) {
                    return Some(CcdHit { t: best, weights });
                }
            }
            return Some(CcdHit { t: enter, weights });
        }
        // Otherwise the node enters the triangle (if at all) somewhere within the band.
        let leave = band_edge(f1, t1).max(enter);
        if let Some(hit) = motion.earliest_inside(enter, leave, best, tolerance) {
            return Some(hit);
        }
    }
    // No crossing seen: the point may still touch the triangle within the minimum separation
    // (grazing an edge or a vertex, in-plane a rounding error off the plane, by a sliver).
    touch::earliest_touch(node, face, touch::minimum_separation(node, face))
}

/// The four trajectories in the frame of `a(t)`: `b - a = xb + t vb`, `c - a = xc + t vc`,
/// `p - a = xp + t vp` (the differences (7.11) of the thesis with node 1 = `a`, 4 = `p`).
///
/// The relative displacement is taken as (relative end position) - (relative start position),
/// so a large rigid motion of the whole group does not round away the small relative motion,
/// and nothing depends on the distance to the global origin.
struct Motion {
    xb: Vector3<f64>,
    vb: Vector3<f64>,
    xc: Vector3<f64>,
    vc: Vector3<f64>,
    xp: Vector3<f64>,
    vp: Vector3<f64>,
}

impl Motion {
    fn new(node: &Trajectory, [a, b, c]: [&Trajectory; 3]) -> Self {
        let relative = |q: &Trajectory| {
            let x0 = q.start - a.start;
            (x0, (q.end - a.end) - x0)
        };
        let (xb, vb) = relative(b);
        let (xc, vc) = relative(c);
        let (xp, vp) = relative(node);
        Self {
            xb,
            vb,
            xc,
            vc,
            xp,
            vp,
        }
    }

    /// Coefficients `[a0, a1, a2, a3]` of the coplanarity cubic (7.13),
    /// `f(t) = ((xb + t vb) x (xc + t vc)) . (xp + t vp)`, grouped as in thesis (7.12) (after
    /// Hutter & Fuhrmann 2007) so that each cross product is formed once:
    /// `a3 = (vb x vc).vp`, `a2 = (xb x vc + vb x xc).vp + (vb x vc).xp`,
    /// `a1 = (xb x xc).vp + (xb x vc + vb x xc).xp`, `a0 = (xb x xc).xp`.
    /// Working relative to `a(0)` keeps the coefficients free of the cancellation that absolute
    /// coordinates far from the origin would cause.
    fn coplanarity_cubic(&self) -> [f64; 4] {
        let n0 = self.xb.cross(&self.xc);
        let n1 = self.xb.cross(&self.vc) + self.vb.cross(&self.xc);
        let n2 = self.vb.cross(&self.vc);
        [
            n0.dot(&self.xp),
            n0.dot(&self.vp) + n1.dot(&self.xp),
            n1.dot(&self.vp) + n2.dot(&self.xp),
            n2.dot(&self.vp),
        ]
    }

    /// The rounding level below which `f` counts as zero:
    /// `tol_f = 64 eps (|xb| + |vb|)(|xc| + |vc|)(|xp| + |vp|)`.
    ///
    /// The product bounds `|b - a| |c - a| |p - a|` over the whole step, i.e. (edge length)^2
    /// times (distance plus displacement of the node), and also the sum of the magnitudes of all
    /// terms in the expanded coefficients, so it bounds the rounding error of both the
    /// coefficients and their evaluation by Horner's rule. `f` is six times the signed volume of
    /// the tetrahedron `(a, b, c, p)`: for a well-shaped face (`|n| ~ |b - a| |c - a|`),
    /// `|f| <= tol_f` means the node is within about `64 eps (|xp| + |vp|)` of the face's plane;
    /// a sliver's plane is known only that much less precisely, and the band is wider.
    fn zero_tolerance(&self) -> f64 {
        let m = |x: &Vector3<f64>, v: &Vector3<f64>| x.norm() + v.norm();
        ZERO_FACTOR
            * f64::EPSILON
            * m(&self.xb, &self.vb)
            * m(&self.xc, &self.vc)
            * m(&self.xp, &self.vp)
    }

    /// `(b - a, c - a, p - a)` at time `t`.
    fn at(&self, t: f64) -> [Vector3<f64>; 3] {
        [
            self.xb + t * self.vb,
            self.xc + t * self.vc,
            self.xp + t * self.vp,
        ]
    }

    /// Barycentric weights `(N_a, N_b, N_c)` of the node's projection on the face's plane at
    /// time `t`, if all are `>= -tolerance`. With `n = (b - a) x (c - a)`, each weight is a
    /// signed sub-area over the whole: `N_a = ((c - b) x (p - b)).n / n.n`,
    /// `N_b = ((p - a) x (c - a)).n / n.n`, `N_c = ((b - a) x (p - a)).n / n.n`
    /// (the local coordinates of thesis (7.6)-(7.7)). Each is computed directly rather than as
    /// `1 - N_b - N_c` so that the test on the edge `bc` is as accurate as on the others.
    /// A degenerate face (`n = 0`) has no weights.
    fn inside(&self, t: f64, tolerance: f64) -> Option<[f64; 3]> {
        let (areas, nn) = self.areas(t);
        if !(nn > 0.0 && nn.is_finite()) {
            return None;
        }
        let weights = areas.map(|s| s / nn);
        weights.iter().all(|&w| w >= -tolerance).then_some(weights)
    }

    /// The numerators `s_k . n` of the weights of [`Self::inside`] and the denominator `n . n`
    /// at time `t`, from the positions.
    fn areas(&self, t: f64) -> ([f64; 3], f64) {
        let [b, c, p] = self.at(t);
        let n = b.cross(&c);
        let areas = [
            (c - b).cross(&(p - b)).dot(&n),
            p.cross(&c).dot(&n),
            b.cross(&p).dot(&n),
        ];
        (areas, n.norm_squared())
    }

    /// Earliest time in `(enter, leave]` (a piece of the band where the node is in the plane
    /// within rounding; the caller has checked `enter`) at which the node is inside the
    /// triangle.
    ///
    /// With `n = (b - a) x (c - a)`, weight `k` is `N_k = (s_k . n) / (n . n)` where `s_k` is
    /// the cross product of [`Self::areas`] (quadratic in `t`, as is `n`). `N_k >= -tolerance / 2`
    /// is `g_k(t) = s_k . n + (tolerance / 2) n . n >= 0`, a quartic in `t`, so inside-ness can
    /// only change at a root of one of the three `g_k`. The candidates, in time order, are each
    /// such root and the middle of each gap between consecutive ones (inside-ness is constant
    /// there, so the middle is the sample least exposed to rounding), plus `best` (the root of
    /// `f` or the critical point); the first at which [`Self::inside`] accepts the weights wins.
    /// The half tolerance leaves room for rounding at the roots themselves.
    ///
    /// The quartics are expanded about the band's middle (the band is usually tiny) and their
    /// signs evaluated from the positions, as in [`Self::inside`], so that root finding and
    /// acceptance agree even where the expanded coefficients lose digits (a face that nearly
    /// collapses to a segment, where the weights change very fast).
    fn earliest_inside(&self, enter: f64, leave: f64, best: f64, tolerance: f64) -> Option<CcdHit> {
        // Coefficient vectors of b - a, c - a and p - a and of their products, in powers of
        // u = t - mid: expanding about the band's middle keeps the coefficients free of the
        // cancellation that an expansion about t = 0 suffers where values are tiny (a nearly
        // collapsed face) far from 0.
        let mid = 0.5 * (enter + leave);
        let cross = |u: [Vector3<f64>; 2], w: [Vector3<f64>; 2]| {
            [
                u[0].cross(&w[0]),
                u[0].cross(&w[1]) + u[1].cross(&w[0]),
                u[1].cross(&w[1]),
            ]
        };
        let dot = |u: &[Vector3<f64>; 3], w: &[Vector3<f64>; 3]| {
            let mut q = [0.0; 5];
            for (i, ui) in u.iter().enumerate() {
                for (j, wj) in w.iter().enumerate() {
                    q[i + j] += ui.dot(wj);
                }
            }
            q
        };
        let [b0, c0, p0] = self.at(mid);
        let (b, c, p) = ([b0, self.vb], [c0, self.vc], [p0, self.vp]);
        let n = cross(b, c);
        let nn = dot(&n, &n);
        let sub = [
            cross([c[0] - b[0], c[1] - b[1]], [p[0] - b[0], p[1] - b[1]]),
            cross(p, c),
            cross(b, p),
        ];
        let half = 0.5 * tolerance;
        let mut times = [f64::INFINITY; 14];
        times[0] = best;
        let mut count = 1;
        for (k, s) in sub.iter().enumerate() {
            let sn = dot(s, &n);
            let g: [f64; 5] = std::array::from_fn(|i| sn[i] + half * nn[i]);
            // Signs from the positions, as in `inside`, so that the two agree at a root even
            // where the expanded coefficients lose digits (a nearly collapsed face).
            let direct = |u: f64| {
                let (areas, nn) = self.areas(mid + u);
                areas[k] + half * nn
            };
            let mut roots = [0.0; 4];
            let found = roots_in(&g, &direct, mid, enter - mid, leave - mid, &mut roots);
            for u in &roots[..found] {
                times[count] = mid + u;
                count += 1;
            }
        }
        times[..count].sort_unstable_by(f64::total_cmp);
        // Inside-ness is constant between consecutive boundary times, so besides each boundary
        // time (where the weight is exactly -tolerance / 2 and rounding may still reject it) the
        // middle of each gap is checked: it is the most robust sample of its stretch.
        let mut previous = enter;
        for &t in times[..count].iter().chain(std::iter::once(&leave)) {
            if t <= previous || t > leave {
                continue;
            }
            for t in [0.5 * (previous + t), t] {
                if let Some(weights) = self.inside(t, tolerance) {
                    return Some(CcdHit { t, weights });
                }
            }
            previous = t;
        }
        None
    }
}

/// `p(t) = p0 + t (p1 + t (p2 + ...))` by Horner's rule (coefficients from the constant up).
fn horner(p: &[f64], t: f64) -> f64 {
    p.iter().rev().fold(0.0, |acc, &c| acc * t + c)
}

/// `p'(t)` by Horner's rule.
fn horner_derivative(p: &[f64], t: f64) -> f64 {
    p.iter()
        .enumerate()
        .skip(1)
        .rev()
        .fold(0.0, |acc, (i, &c)| acc * t + i as f64 * c)
}

/// Secant through the bracket ends: the starting point for Newton's method.
fn regula_falsi(t0: f64, t1: f64, f0: f64, f1: f64) -> f64 {
    let t = t0 - f0 * (t1 - t0) / (f1 - f0);
    if t > t0 && t < t1 {
        t
    } else {
        0.5 * (t0 + t1)
    }
}

/// Roots of `c0 + c1 t + c2 t^2` in the cancellation-free form (Numerical Recipes 5.6):
/// `q = -(c1 + sign(c1) sqrt(c1^2 - 4 c2 c0)) / 2`, roots `q / c2` and `c0 / q`.
///
/// A vanishing `c2` turns `q / c2` into an infinity (discarded by the caller's range test)
/// while `c0 / q = -c0 / c1` stays the linear root, so no special case is needed. The
/// discriminant is formed with fused multiply-adds (Kahan's trick) so that nearly equal roots
/// are not lost to cancellation. Missing roots (negative discriminant, or `c1 = c2 = 0`) are NaN
/// or infinite; the caller's range test discards them.
fn quadratic_roots([c0, c1, c2]: [f64; 3]) -> [f64; 2] {
    let b2 = c1 * c1;
    let ac4 = 4.0 * c2 * c0;
    let disc = (b2 - ac4) + (c1.mul_add(c1, -b2) - (4.0 * c2).mul_add(c0, -ac4));
    if disc < 0.0 {
        return [f64::NAN; 2];
    }
    let q = -0.5 * (c1 + disc.sqrt().copysign(c1));
    [q / c2, c0 / q]
}

/// Roots of the polynomial `p` (degree at most 4) in `[lo, hi]`, in increasing order, written to
/// `out`; returns how many. The same isolation as for the cubic, applied recursively: the
/// roots of `p'` split `[lo, hi]` into monotone pieces, a piece whose ends change sign holds one
/// root, refined by [`refine`], and an end where `p` is exactly zero is a root too. Degree 2
/// and below use [`quadratic_roots`]. Signs and the refinement use `value`, which evaluates the
/// same function as `p` but may do it more accurately (directly from the positions). The
/// variable is the time minus `origin` (see [`refine`]).
fn roots_in(
    p: &[f64],
    value: &dyn Fn(f64) -> f64,
    origin: f64,
    lo: f64,
    hi: f64,
    out: &mut [f64; 4],
) -> usize {
    let mut count = 0;
    if p.len() <= 3 {
        let mut r = quadratic_roots([
            p[0],
            p.get(1).copied().unwrap_or(0.0),
            p.get(2).copied().unwrap_or(0.0),
        ]);
        if r[0] > r[1] {
            r.swap(0, 1);
        }
        for t in r {
            if t >= lo && t <= hi {
                out[count] = t;
                count += 1;
            }
        }
        return count;
    }
    let mut derivative = [0.0; 4];
    for i in 1..p.len() {
        derivative[i - 1] = i as f64 * p[i];
    }
    let mut knots = [0.0; 6];
    let derivative = &derivative[..p.len() - 1];
    let critical = roots_in(
        derivative,
        &|t| horner(derivative, t),
        origin,
        lo,
        hi,
        (&mut knots[1..5])
            .try_into()
            .expect("knots[1..5] has exactly four elements"),
    );
    knots[0] = lo;
    knots[critical + 1] = hi;
    let knots = &knots[..critical + 2];
    let mut previous = value(lo);
    if previous == 0.0 {
        out[count] = lo;
        count += 1;
    }
    for w in knots.windows(2) {
        let next = value(w[1]);
        if count < out.len() && ((previous < 0.0 && next > 0.0) || (previous > 0.0 && next < 0.0)) {
            let guess = regula_falsi(w[0], w[1], previous, next);
            out[count] = refine(value, p, origin, w[0], w[1], previous, guess);
            count += 1;
        }
        if count < out.len() && next == 0.0 && w[1] > w[0] {
            out[count] = w[1];
            count += 1;
        }
        previous = next;
    }
    count
}

/// Root in `[lo, hi]` of a function that changes sign there (`value(lo)` has the sign of
/// `v_lo`) and is evaluated by `value`, with the slope of the polynomial `p` (its
/// coefficients); the variable is the time minus `origin`. Newton's method safeguarded by
/// bisection (`rtsafe`, Numerical Recipes 9.4): a Newton step is taken only if it stays inside
/// the current bracket and at least halves the step before last, otherwise the bracket is
/// bisected. The bracket shrinks every iteration and the iterations are capped, so the cost is
/// bounded even where Newton converges only linearly (a double root); usually it takes 3-6
/// quadratically convergent steps.
fn refine(
    value: impl Fn(f64) -> f64,
    p: &[f64],
    origin: f64,
    mut lo: f64,
    mut hi: f64,
    v_lo: f64,
    guess: f64,
) -> f64 {
    let lo_negative = v_lo < 0.0;
    let mut t = if guess > lo && guess < hi {
        guess
    } else {
        0.5 * (lo + hi)
    };
    let mut step_old = hi - lo;
    let mut step = step_old;
    for _ in 0..MAX_ITERATIONS {
        let v = value(t);
        if v == 0.0 {
            return t;
        }
        if (v < 0.0) == lo_negative {
            lo = t;
        } else {
            hi = t;
        }
        let newton = t - v / horner_derivative(p, t);
        let next = if newton > lo && newton < hi && 2.0 * (newton - t).abs() <= step_old.abs() {
            newton
        } else {
            0.5 * (lo + hi)
        };
        step_old = step;
        step = next - t;
        t = next;
        // Precision relative to the time `origin + t`: a root near t = 0 (a contact at the very
        // start of the step) needs as many significant digits as any other, as the weights may
        // change fast there.
        let scale = T_TOL * (origin + t).abs();
        if step.abs() <= scale || hi - lo <= scale {
            break;
        }
    }
    t
}
