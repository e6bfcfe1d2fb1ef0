//! Virtual experiments on one material point: the single-element tests of the calibration and of
//! the catalogue's material cases (CATALOGUE "Concrete material"), each returning its curve and the
//! numbers the targets of MICROPLANE.md are stated in.

use super::driver::{
    equivalent_rate, uniaxial_controls, Control, DriverError, MaterialPoint, PathPoint,
};
use super::{contract, MicroplaneConcrete, Sym, TensionDriver};

/// Strain rate of the quasi-static tests (1/s): the rate factor is 1.0003 here, so "static" tests
/// are static to well within every band.
pub const QUASI_STATIC_RATE: f64 = 1e-8;

/// A path and, if it stopped early, why.
#[derive(Debug, Clone)]
pub struct Curve {
    /// The committed points of the path, in order (the virgin start not included).
    pub points: Vec<PathPoint>,
    /// Why the path stopped before its end; `None` when it ran to the end.
    pub error: Option<DriverError>,
}

impl Curve {
    /// The axial Green-Lagrange strain `E_11` at each point (dimensionless).
    pub fn axial_strain(&self) -> Vec<f64> {
        self.points.iter().map(|p| p.strain[0]).collect()
    }

    /// The axial second Piola-Kirchhoff stress `S_11` at each point (Pa, tension positive).
    pub fn axial_stress(&self) -> Vec<f64> {
        self.points.iter().map(|p| p.stress[0]).collect()
    }

    /// Work per unit volume `int sigma : dE` along the path (trapezoidal).
    pub fn work(&self) -> f64 {
        self.points
            .windows(2)
            .map(|w| {
                let (a, b) = (&w[0], &w[1]);
                (0..6)
                    .map(|i| {
                        let factor = if i < 3 { 1.0 } else { 2.0 };
                        factor * 0.5 * (a.stress[i] + b.stress[i]) * (b.strain[i] - a.strain[i])
                    })
                    .sum::<f64>()
            })
            .sum()
    }

    /// Whether the path passed its peak: `|sigma_11|` fell below its largest value by 1e-3 of it
    /// afterwards. Otherwise the largest stress computed is only a lower bound of the peak (the
    /// path ended or stopped while the stress still rose).
    pub fn peak_passed(&self) -> bool {
        let s: Vec<f64> = self.points.iter().map(|p| p.stress[0].abs()).collect();
        let Some((i, &top)) = s.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)) else {
            return false;
        };
        s[i..].iter().any(|&x| x < (1.0 - 1e-3) * top)
    }

    /// The point of largest `|sigma_11|`.
    pub fn peak(&self) -> &PathPoint {
        self.points
            .iter()
            .max_by(|a, b| a.stress[0].abs().total_cmp(&b.stress[0].abs()))
            .expect("a curve has its starting point")
    }
}

/// Uniaxial tension: the numbers of the targets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TensionResult {
    /// Largest axial stress, the tensile strength (Pa).
    pub peak_stress: f64,
    /// Axial strain at the peak (dimensionless).
    pub peak_strain: f64,
    /// `sigma / eps` at the first increment.
    pub initial_slope: f64,
    /// `h int sigma d eps` to the end of the path (J/m^2 = N/m).
    pub fracture_energy: f64,
    /// `sigma / peak` at the end of the path: what the tail beyond it leaves out.
    pub final_stress_ratio: f64,
}

/// Uniaxial tension at strain rate `rate` on an element of size `h`, driven until the stress has
/// fallen below `1e-3` of its peak (or a strain of 5 %): increments of 2e-6 up to 4e-4, then 0.5 %
/// of the current strain. Lateral stresses stay zero throughout (see [`bonded_tension`] for the
/// path of a crack band in a structure).
pub fn uniaxial_tension(
    model: &MicroplaneConcrete,
    h: f64,
    rate: f64,
) -> Result<(Curve, TensionResult), DriverError> {
    tension(model, h, rate, false, 1.0)
}

/// The crack band's path (issue 16): uniaxial stress up to the tensile peak, then the lateral
/// strains held at their values there while the axial strain grows, as in a band of elements
/// bonded to elastic neighbours, whose lateral strains (`-nu sigma / E`) only shrink once the crack
/// softens. A free single element instead contracts laterally after the peak by up to several
/// times its axial strain, which no bonded band can follow, so this is the path on which the
/// fracture energy `GF` of a crack is defined and calibrated (MICROPLANE "Crack band").
pub fn bonded_tension(
    model: &MicroplaneConcrete,
    h: f64,
    rate: f64,
) -> Result<(Curve, TensionResult), DriverError> {
    tension(model, h, rate, true, 1.0)
}

/// [`bonded_tension`] of an element whose tensile strength is `strength` times the material's
/// (a strength field, `material/strength_field.rs`): its peak is about `strength` times the
/// material's and its fracture energy the material's.
pub fn bonded_tension_with_strength(
    model: &MicroplaneConcrete,
    h: f64,
    rate: f64,
    strength: f64,
) -> Result<(Curve, TensionResult), DriverError> {
    tension(model, h, rate, true, strength)
}

/// The single-element path of a tension test: uniaxial stress throughout, or the crack band's
/// path ([`bonded_tension`]). The calibration measures GF on one of them
/// (`calibration::Targets::fracture_path`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FracturePath {
    /// Uniaxial stress throughout: lateral stresses zero ([`uniaxial_tension`]); the default.
    #[default]
    UniaxialStress,
    /// The crack band's path: lateral strains held after the peak ([`bonded_tension`]).
    Bonded,
}

impl FracturePath {
    /// The path on which the calibration defines GF for a tension driver (MICROPLANE "Tension
    /// driver"): uniaxial stress for the thesis' volumetric driver, the crack band's path for the
    /// equivalent one.
    pub fn of_driver(driver: TensionDriver) -> Self {
        match driver {
            TensionDriver::Volumetric => FracturePath::UniaxialStress,
            TensionDriver::Equivalent => FracturePath::Bonded,
        }
    }

    /// The tension test on this path.
    pub fn tension(
        self,
        model: &MicroplaneConcrete,
        h: f64,
        rate: f64,
    ) -> Result<(Curve, TensionResult), DriverError> {
        tension(model, h, rate, self == FracturePath::Bonded, 1.0)
    }
}

fn tension(
    model: &MicroplaneConcrete,
    h: f64,
    rate: f64,
    hold_after_peak: bool,
    strength: f64,
) -> Result<(Curve, TensionResult), DriverError> {
    let mut point = MaterialPoint::with_strength(model, h, strength)?;
    let mut points = vec![PathPoint {
        time: 0.0,
        strain: [0.0; 6],
        stress: [0.0; 6],
        rate_factor: 1.0,
    }];
    let mut error = None;
    let mut e = 0.0;
    let mut peak: f64 = 0.0;
    let mut held: Option<Sym> = None;
    while e < 0.05 {
        // A first increment of 1e-8 measures the initial slope inside the elastic range.
        let de = if e == 0.0 {
            1e-8
        } else if e < 4e-4 {
            2e-6
        } else {
            e / 200.0
        };
        e += de;
        let step = match held {
            Some(mut strain) => {
                strain[0] = e;
                Ok(point.strain_step(strain, de / rate))
            }
            None => point.mixed_step_subdivided(&uniaxial_controls(e), de / rate),
        };
        match step {
            Ok(p) => {
                if hold_after_peak && held.is_none() && p.stress[0] < peak {
                    held = Some(p.strain);
                }
                peak = peak.max(p.stress[0]);
                points.push(p);
                if e > 4e-4 && p.stress[0] < 1e-3 * peak {
                    break;
                }
            }
            Err(err) => {
                error = Some(err);
                break;
            }
        }
    }
    let curve = Curve { points, error };
    let top = *curve.peak();
    let last = curve.points.last().expect("starting point");
    let result = TensionResult {
        peak_stress: top.stress[0],
        peak_strain: top.strain[0],
        initial_slope: curve
            .points
            .get(1)
            .map_or(0.0, |p| p.stress[0] / p.strain[0]),
        fracture_energy: h * curve.work(),
        final_stress_ratio: last.stress[0] / top.stress[0].max(f64::MIN_POSITIVE),
    };
    Ok((curve, result))
}

/// The shape of the softening branch of a uniaxial tension curve against the crack opening
/// `w = h (eps - sigma / E)` (crack band: the inelastic strain spread over the element).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SofteningShape {
    /// `sigma / peak` where, after the peak, the opening reaches `w1` (NaN if it never does).
    pub stress_ratio_at_w1: f64,
    /// Opening where, after the peak, the stress first falls to 1 % of the peak (m; NaN if it
    /// never does): the end `w_c` of the softening law.
    pub opening_at_one_percent: f64,
}

/// The [`SofteningShape`] of a tension curve on an element of size `h` with Young's modulus
/// `youngs`, at `w1` (m; MC2010 and Hordijk compare at `w1 = GF / ft`), interpolating linearly
/// between the path's points.
pub fn softening_shape(curve: &Curve, h: f64, youngs: f64, w1: f64) -> SofteningShape {
    let top = curve
        .points
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.stress[0].total_cmp(&b.1.stress[0]))
        .map_or(0, |(i, _)| i);
    let peak = curve.points[top].stress[0];
    let pts: Vec<(f64, f64)> = curve.points[top..]
        .iter()
        .map(|p| (h * (p.strain[0] - p.stress[0] / youngs), p.stress[0]))
        .collect();
    let mut shape = SofteningShape {
        stress_ratio_at_w1: f64::NAN,
        opening_at_one_percent: f64::NAN,
    };
    for pair in pts.windows(2) {
        let ((w0, s0), (w1_, s1)) = (pair[0], pair[1]);
        if shape.stress_ratio_at_w1.is_nan() && w0 <= w1 && w1_ >= w1 && w1_ > w0 {
            let t = (w1 - w0) / (w1_ - w0);
            shape.stress_ratio_at_w1 = (s0 + t * (s1 - s0)) / peak;
        }
        let end = 0.01 * peak;
        if shape.opening_at_one_percent.is_nan() && s0 >= end && s1 < end {
            let t = (s0 - end) / (s0 - s1);
            shape.opening_at_one_percent = w0 + t * (w1_ - w0);
        }
    }
    shape
}

/// The stress-crack opening law `(w, sigma)` of the model at element size `h` (m), from the
/// tension test on which the calibration defines GF for the model's tension driver
/// ([`uniaxial_tension`] for the thesis' volumetric driver, [`bonded_tension`] for the
/// equivalent one; MICROPLANE "Tension driver") at the quasi-static rate, in the crack band's
/// reading: after the peak,
/// `w = h (eps - sigma / E)`, the inelastic strain of the element times its size, with `E` the
/// initial Young's modulus as the unloading modulus (an elastic unloading). The opening already
/// reached at the peak (the pre-peak inelastic strain) is lumped at `f_t`: the law starts at
/// `(0, f_t)`, then follows the points after the peak with `w` rising, so its area differs from
/// the fracture energy `h int sigma d eps` of the test by less than that plateau
/// `f_t h (eps_p - f_t / E)` (4.8 N/m, 5 % of GF, for the thesis concrete at h = 50 mm; the
/// areas differ by 0.8 %). The hinge with `pre_peak: own` counts the opening from the peak.
/// Empty vectors if the experiment cannot start (an element size the crack band rejects).
pub fn crack_opening_curve(model: &MicroplaneConcrete, element_size: f64) -> (Vec<f64>, Vec<f64>) {
    tension_branches(model, element_size).opening
}

/// Both branches of the tension test behind [`crack_opening_curve`], read from one run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TensionBranches {
    /// `(eps, sigma)` from the origin to the peak (inclusive): the material's own stress-strain
    /// law before it cracks, for references whose bulk is not linear up to `f_t` (the hinge with
    /// `pre_peak: own`).
    pub rising: (Vec<f64>, Vec<f64>),
    /// `(w, sigma)`: [`crack_opening_curve`].
    pub opening: (Vec<f64>, Vec<f64>),
}

/// The tension test on the path the calibration defines GF on for the model's driver, at the
/// quasi-static rate, read as its rising branch and its crack-opening law. Empty vectors if the
/// experiment cannot start (an element size the crack band rejects).
pub fn tension_branches(model: &MicroplaneConcrete, element_size: f64) -> TensionBranches {
    let path = FracturePath::of_driver(model.parameters.tension_driver);
    let Ok((curve, result)) = path.tension(model, element_size, QUASI_STATIC_RATE) else {
        return TensionBranches::default();
    };
    let e = model.parameters.youngs_modulus;
    let top = curve
        .points
        .iter()
        .position(|p| p.stress[0] == result.peak_stress)
        .unwrap_or(0);
    let (mut strain, mut stress) = (vec![0.0], vec![0.0]);
    for p in &curve.points[..=top] {
        if p.strain[0] > *strain.last().expect("origin") {
            strain.push(p.strain[0]);
            stress.push(p.stress[0]);
        }
    }
    let (mut w, mut sigma) = (vec![0.0], vec![result.peak_stress]);
    for p in &curve.points[top..] {
        let opening = element_size * (p.strain[0] - p.stress[0] / e);
        if opening > *w.last().expect("first point") {
            w.push(opening);
            sigma.push(p.stress[0].max(0.0));
        }
    }
    TensionBranches {
        rising: (strain, stress),
        opening: (w, sigma),
    }
}

/// Uniaxial compression: the numbers of the targets (stresses and strains as magnitudes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompressionResult {
    /// Largest axial compressive stress, the compressive strength (Pa, magnitude).
    pub peak_stress: f64,
    /// Axial strain at the peak (magnitude, dimensionless).
    pub peak_strain: f64,
    /// Apparent Poisson ratio `-eps_lateral / eps_axial` at the first increment, at the peak, and
    /// its largest value after the peak.
    pub initial_poisson: f64,
    /// Apparent Poisson ratio at the peak stress.
    pub poisson_at_peak: f64,
    /// Largest apparent Poisson ratio after the peak (above 0.5 once the material dilates).
    pub largest_poisson_after_peak: f64,
    /// Axial strain magnitude where the volumetric strain is most compressive (onset of
    /// dilatancy), if it turns before the end of the path.
    pub dilatancy_onset: Option<f64>,
}

/// Uniaxial compression to an axial strain of `-end` in increments of `end / steps`.
pub fn uniaxial_compression(
    model: &MicroplaneConcrete,
    h: f64,
    rate: f64,
    end: f64,
    steps: usize,
) -> Result<(Curve, CompressionResult), DriverError> {
    let mut point = MaterialPoint::new(model, h)?;
    let de = end / steps as f64;
    let (points, error) =
        point.run((1..=steps).map(|i| (uniaxial_controls(-de * i as f64), de / rate)));
    let curve = Curve { points, error };
    let poisson = |p: &PathPoint| -p.strain[1] / p.strain[0];
    let (peak_index, top) = curve
        .points
        .iter()
        .enumerate()
        .max_by(|a, b| (-a.1.stress[0]).total_cmp(&-b.1.stress[0]))
        .expect("starting point");
    let volumetric: Vec<f64> = curve
        .points
        .iter()
        .map(|p| p.strain[0] + p.strain[1] + p.strain[2])
        .collect();
    let most_compressed = volumetric
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i)
        .unwrap_or(0);
    let result = CompressionResult {
        peak_stress: -top.stress[0],
        peak_strain: -top.strain[0],
        initial_poisson: curve.points.get(1).map_or(0.0, poisson),
        poisson_at_peak: poisson(top),
        largest_poisson_after_peak: curve.points[peak_index..]
            .iter()
            .skip(1)
            .map(poisson)
            .fold(f64::NAN, f64::max),
        dilatancy_onset: (most_compressed + 1 < curve.points.len())
            .then(|| -curve.points[most_compressed].strain[0]),
    };
    Ok((curve, result))
}

/// Equal biaxial compression (`E_11 = E_22` prescribed, `sigma_33 = 0`): the peak of `-sigma_11`.
pub fn equal_biaxial_compression(
    model: &MicroplaneConcrete,
    h: f64,
    end: f64,
    steps: usize,
) -> Result<(Curve, f64), DriverError> {
    let mut point = MaterialPoint::new(model, h)?;
    let de = end / steps as f64;
    let (points, error) = point.run((1..=steps).map(|i| {
        let e = -de * i as f64;
        (
            [
                Control::Strain(e),
                Control::Strain(e),
                Control::Stress(0.0),
                Control::Strain(0.0),
                Control::Strain(0.0),
                Control::Strain(0.0),
            ],
            de / QUASI_STATIC_RATE,
        )
    }));
    let curve = Curve { points, error };
    let peak = -curve.peak().stress[0];
    Ok((curve, peak))
}

/// Tension under a held lateral stress (Kupfer, Hilsdorf & Rüsch 1969's tension-compression
/// tests): `sigma_22 = lateral` applied first in 20 increments (`sigma_11 = sigma_33 = 0`), then
/// held while `E_11` grows by `end` in `steps` increments (`sigma_33 = 0`, no shear). The curve
/// holds the second stage; it ends early (with the driver's error) where the point can no longer
/// carry the lateral stress. A preload the point cannot carry is the error.
pub fn tension_under_lateral_stress(
    model: &MicroplaneConcrete,
    h: f64,
    lateral: f64,
    end: f64,
    steps: usize,
) -> Result<Curve, DriverError> {
    let controls = |axial: Control, lateral: f64| {
        [
            axial,
            Control::Stress(lateral),
            Control::Stress(0.0),
            Control::Strain(0.0),
            Control::Strain(0.0),
            Control::Strain(0.0),
        ]
    };
    let mut point = MaterialPoint::new(model, h)?;
    // The preload's time step follows the strain its stress gives in elastic uniaxial stress.
    let preload_step = (lateral / model.parameters.youngs_modulus).abs() / 20.0;
    let (preload, error) = point.run((1..=20).map(|i| {
        let s = lateral * f64::from(i) / 20.0;
        (
            controls(Control::Stress(0.0), s),
            preload_step.max(1e-12) / QUASI_STATIC_RATE,
        )
    }));
    if let Some(error) = error {
        return Err(error);
    }
    let start = preload.last().map_or(0.0, |p| p.strain[0]);
    let de = end / steps as f64;
    let (points, error) = point.run((1..=steps).map(|i| {
        (
            controls(Control::Strain(start + de * i as f64), lateral),
            de / QUASI_STATIC_RATE,
        )
    }));
    Ok(Curve { points, error })
}

/// Hydrostatic compression to a volumetric strain `-end` (all normal strains `-end`), then back
/// to zero: the pressure-volume curve, and whether any microplane branch lost stiffness.
pub fn hydrostatic_compression(
    model: &MicroplaneConcrete,
    h: f64,
    end: f64,
    steps: usize,
) -> Result<(Curve, bool), DriverError> {
    let mut point = MaterialPoint::new(model, h)?;
    let de = end / steps as f64;
    let strains = (1..=steps).chain((0..steps).rev()).map(|i| -de * i as f64);
    let (points, error) = point.run(strains.map(|e| {
        (
            [
                Control::Strain(e),
                Control::Strain(e),
                Control::Strain(e),
                Control::Strain(0.0),
                Control::Strain(0.0),
                Control::Strain(0.0),
            ],
            de / QUASI_STATIC_RATE,
        )
    }));
    let damaged = point
        .state
        .secants(
            model.planes().len(),
            model.parameters.tension_boundary.is_some(),
        )
        .iter()
        .any(|&s| {
            s.is_finite()
                && s < 0.999 * model.parameters.youngs_modulus
                    / (1.0 + model.parameters.poisson_ratio)
        });
    Ok((Curve { points, error }, damaged))
}

/// The largest relative difference, over `samples` strain states of random direction and a
/// magnitude of 1e-20 (far inside the elastic range), between the model's stress and Hooke's law
/// with its `E` and `nu`, relative to the norm of Hooke's stress.
pub fn isotropy_error(model: &MicroplaneConcrete, samples: usize) -> f64 {
    let c = model.parameters.elastic();
    let (lambda, mu) = (c.lambda(), c.mu());
    let band = model
        .crack_band(model.parameters.h_ref)
        .expect("the calibration size is admissible");
    let mut rng = crate::rng::SplitMix64::new(20_091_121);
    let mut worst: f64 = 0.0;
    for _ in 0..samples {
        let raw: Sym = std::array::from_fn(|_| 2.0 * rng.next_f64() - 1.0);
        let norm = raw.iter().map(|x| x * x).sum::<f64>().sqrt();
        let strain: Sym = std::array::from_fn(|i| 1e-20 * raw[i] / norm);
        let mut state = model.initial_state();
        let (stress, _) = model.update(&mut state.values, &strain, 0.0, &band);
        let trace = strain[0] + strain[1] + strain[2];
        let hooke: Sym = std::array::from_fn(|i| {
            2.0 * mu * strain[i] + if i < 3 { lambda * trace } else { 0.0 }
        });
        let diff = (0..6)
            .map(|i| (stress[i] - hooke[i]).powi(2) * if i < 3 { 1.0 } else { 2.0 })
            .sum::<f64>()
            .sqrt();
        let size = (0..6)
            .map(|i| hooke[i].powi(2) * if i < 3 { 1.0 } else { 2.0 })
            .sum::<f64>()
            .sqrt();
        worst = worst.max(diff / size);
    }
    worst
}

/// A strain-controlled path through `corners` and back to the first one, each leg cut into
/// `steps` increments: the work per unit volume over the closed cycle (the dissipation) and
/// whether any branch's secant rose (damage healed) along the way.
pub fn closed_strain_cycle(
    model: &MicroplaneConcrete,
    h: f64,
    corners: &[Sym],
    steps: usize,
) -> Result<(Curve, f64, bool), DriverError> {
    let mut point = MaterialPoint::new(model, h)?;
    let mut points = vec![point.strain_step(corners[0], 1.0)];
    let start_work_index = points.len() - 1;
    let mut previous = point.state.secants(
        model.planes().len(),
        model.parameters.tension_boundary.is_some(),
    );
    let mut healed = false;
    let legs = corners.iter().zip(corners.iter().cycle().skip(1));
    for (from, to) in legs {
        for i in 1..=steps {
            let t = i as f64 / steps as f64;
            let strain: Sym = std::array::from_fn(|j| from[j] + t * (to[j] - from[j]));
            let dt = equivalent_rate(&point.strain, &strain, 1.0) / QUASI_STATIC_RATE;
            points.push(point.strain_step(strain, dt));
            let now = point.state.secants(
                model.planes().len(),
                model.parameters.tension_boundary.is_some(),
            );
            healed |= now
                .iter()
                .zip(&previous)
                .any(|(a, b)| a.is_finite() && b.is_finite() && *a > *b * (1.0 + 1e-6));
            previous = now;
        }
    }
    let curve = Curve {
        points: points[start_work_index..].to_vec(),
        error: None,
    };
    let dissipation = curve.work();
    Ok((curve, dissipation, healed))
}

/// `sigma : C0^-1 : sigma / 2` of the isotropic virgin stiffness (Young's modulus `youngs`,
/// Poisson's ratio `poisson`): the least elastic energy a point at the stress `sigma` gives back
/// on unloading, its unloading stiffness being at most the virgin one. A dissipative point has
/// taken in at least this much work from the virgin state.
pub fn least_recoverable_energy(sigma: &Sym, youngs: f64, poisson: f64) -> f64 {
    let trace = sigma[0] + sigma[1] + sigma[2];
    let normal: f64 = (0..3)
        .map(|i| sigma[i] * ((1.0 + poisson) * sigma[i] - poisson * trace))
        .sum();
    let shear: f64 = (3..6)
        .map(|i| 2.0 * (1.0 + poisson) * sigma[i] * sigma[i])
        .sum();
    0.5 * (normal + shear) / youngs
}

/// The work `sigma : dE` of one step from `(strain0, stress0)` to `(strain1, stress1)`, by the
/// trapezoidal rule (as [`Curve::work`]).
pub fn step_work(strain0: &Sym, stress0: &Sym, strain1: &Sym, stress1: &Sym) -> f64 {
    let mean: Sym = std::array::from_fn(|i| 0.5 * (stress0[i] + stress1[i]));
    let change: Sym = std::array::from_fn(|i| strain1[i] - strain0[i]);
    contract(&mean, &change)
}

/// Peak uniaxial tensile stress at each strain rate, with the rate factor at the peak.
pub fn tension_rate_sweep(
    model: &MicroplaneConcrete,
    h: f64,
    rates: &[f64],
) -> Result<Vec<(f64, TensionResult, f64)>, DriverError> {
    rates
        .iter()
        .map(|&rate| {
            let (curve, result) = uniaxial_tension(model, h, rate)?;
            Ok((rate, result, curve.peak().rate_factor))
        })
        .collect()
}

/// The unit check of the rate law: uniaxial strain in tension (`E_11` rising at `rate`, all other
/// strains zero, so the equivalent rate `rate / sqrt 2` and the factor `F` are constant), against
/// the same path at the quasi-static rate on a strain grid scaled by `F_rate / F_static`. The
/// virgin laws scale their strains by `F`, so the stresses must scale by the same ratio at every
/// point; returns `(F_rate / F_static, peak stress ratio, largest relative misfit along the path)`.
/// The misfit is limited by the `f32` history (about 1e-7).
pub fn rate_scaling(
    model: &MicroplaneConcrete,
    h: f64,
    rate: f64,
    end: f64,
    steps: usize,
) -> Result<(f64, f64, f64), DriverError> {
    let run = |rate: f64, scale: f64| -> Result<Vec<PathPoint>, DriverError> {
        let mut point = MaterialPoint::new(model, h)?;
        let de = scale * end / steps as f64;
        let mut out = Vec::with_capacity(steps);
        for i in 1..=steps {
            let strain = [de * i as f64, 0.0, 0.0, 0.0, 0.0, 0.0];
            out.push(point.strain_step(strain, de / rate));
        }
        Ok(out)
    };
    let gamma = |rate: f64| rate / std::f64::consts::SQRT_2;
    let ratio = model.rate_factor(gamma(rate)) / model.rate_factor(gamma(QUASI_STATIC_RATE));
    let slow = run(QUASI_STATIC_RATE, 1.0)?;
    let fast = run(rate, ratio)?;
    let peak = |p: &[PathPoint]| p.iter().map(|q| q.stress[0]).fold(f64::MIN, f64::max);
    let (peak_slow, peak_fast) = (peak(&slow), peak(&fast));
    let misfit = slow
        .iter()
        .zip(&fast)
        .map(|(a, b)| (b.stress[0] - ratio * a.stress[0]).abs() / (ratio * peak_slow))
        .fold(0.0, f64::max);
    Ok((ratio, peak_fast / peak_slow, misfit))
}
