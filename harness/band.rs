//! The crack band inside a structure (CATALOGUE `fracture/band-in-prism`, issue 16): a prism of
//! tetrahedra pulled apart with one layer of microplane concrete (a material region) between
//! elastic neighbours, compared with the material point of the same size.
//!
//! From the run's history (`BandSpec`):
//! - traction `t = F / A` (end reaction over the cross-section),
//! - opening `w = (u_right - u_left) - t h / K_b`: the band's elongation (mean displacements of
//!   its two faces) less its elastic part, `K_b` the band's initial modulus fitted on `t` against
//!   the band strain up to 30 % of the peak (so it is `E` with free sides and the uniaxial-strain
//!   modulus with restrained sides, whatever the band's lateral state),
//! - dissipated energy per crack area `G = (int F du_end - F_end^2 / (2 K)) / A`: the external work
//!   less the elastic energy still stored at the end (`K` the prism's initial stiffness).
//!
//! The material point (`PointPath`): the same microplane parameters at the same element size `h`,
//! driven quasi-statically in uniaxial stress (free sides), uniaxial strain (lateral strains held
//! at zero: restrained sides; Rots 1988, Jirasek & Zimmermann 1998 on stress locking) or tension
//! followed by tension with shear; its `sigma(w)` with `w = h (eps - sigma / E)` (Bazant & Oh
//! 1983), `E` its initial slope, and its `G = h int sigma : d eps`.

use impact_solver::material::microplane::driver::{uniaxial_controls, MaterialPoint};
use impact_solver::material::microplane::experiments::QUASI_STATIC_RATE;
use impact_solver::material::microplane::{MicroplaneConcrete, MicroplaneParameters};
use impact_solver::material::MaterialModel;
use impact_solver::scene::Scene;
use serde::{Deserialize, Serialize};

use crate::beam::history::HistoryError;
use crate::curve::CurveError;

/// Why a crack-band measure has no value: the material point fails, the band's body is not
/// microplane concrete, or the run's history lacks what the band needs.
#[derive(Debug, thiserror::Error)]
pub enum BandError {
    /// The band's microplane parameters are refused.
    #[error(transparent)]
    Parameters(#[from] impact_solver::material::microplane::ParameterError),
    /// The material point cannot be driven along the path.
    #[error(transparent)]
    Point(#[from] impact_solver::material::microplane::driver::DriverError),
    /// The scene's material of the band cannot be read.
    #[error(transparent)]
    Material(impact_solver::SolverError),
    /// The scene has no body or region of that name.
    #[error("the scene has no body or region `{name}`")]
    NoRegion {
        /// The name asked for.
        name: String,
    },
    /// The model has no body or region of that name.
    #[error("the model has no body or region `{name}`")]
    NoModelRegion {
        /// The name asked for.
        name: String,
    },
    /// The band's material is not microplane concrete.
    #[error("`{name}` is not microplane concrete")]
    NotMicroplane {
        /// The body or region.
        name: String,
    },
    /// A history column of the band is missing.
    #[error(transparent)]
    Column(#[from] CurveError),
    /// A stiffness of the band's history cannot be fitted.
    #[error(transparent)]
    History(#[from] HistoryError),
    /// The history has no record.
    #[error("empty history")]
    Empty,
    /// The run's softening branch and the point's curve do not overlap.
    #[error("no softening record of the run lies within the point's w")]
    NoSoftening,
}

/// Which material-point path stands for the band.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum PointPath {
    /// Uniaxial stress along x (lateral stresses zero): the free prism.
    #[default]
    UniaxialStress,
    /// Uniaxial strain along x (lateral strains zero throughout): the restrained prism.
    UniaxialStrain,
    /// Uniaxial stress to the tensile peak, then lateral strains held: the band bonded to elastic
    /// neighbours with free sides, and the path on which the calibration defines GF
    /// (`experiments::bonded_tension`).
    Bonded,
    /// Uniaxial stress to the tensile peak, then lateral strains held and the shear strain
    /// `gamma_xy = 2 E_12` rising with the normal strain at `ratio` (d gamma / d eps_xx).
    TensionShear {
        /// `d gamma_xy / d eps_xx` after the peak (dimensionless).
        ratio: f64,
    },
}

/// A material point's curve against the crack opening.
#[derive(Debug, Clone)]
pub struct PointCurve {
    /// Crack opening `w = h (eps - sigma / E)` at each point (m).
    pub w: Vec<f64>,
    /// `sigma_xx` (Pa).
    pub sigma: Vec<f64>,
    /// `sigma_xy` (Pa), zero except in tension with shear.
    pub shear: Vec<f64>,
    /// Largest `sigma_xx`, the point's tensile strength (Pa).
    pub peak: f64,
    /// `h int sigma : d eps` over the path (N/m).
    pub fracture_energy: f64,
    /// `sigma_xx / peak` at the end of the path.
    pub residual_ratio: f64,
    /// Largest `|sigma_ij|` (any component) over `peak` in the last tenth of the path's strain.
    pub residual_any_ratio: f64,
    /// Lateral strain `E_yy` at the end of the path.
    pub final_lateral_strain: f64,
    /// Axial strain `E_xx` at the end of the path.
    pub final_axial_strain: f64,
}

/// Axial strain increments of the paths: 2e-6 to 4e-4, then 0.5 % of the strain, to `end`.
fn strains(end: f64) -> Vec<f64> {
    let mut out = vec![1e-8];
    let mut e = 1e-8;
    while e < end {
        e += if e < 4e-4 { 2e-6 } else { e / 200.0 };
        out.push(e.min(end));
    }
    out
}

/// The material point of `params` at size `h` along `path`, to an axial strain of `end` (or until
/// `sigma_xx` falls below 1e-3 of its peak on the uniaxial paths).
pub fn point_curve(
    params: &MicroplaneParameters,
    h: f64,
    path: PointPath,
    end: f64,
) -> Result<PointCurve, BandError> {
    let mut params = *params;
    params.rate_effect = None;
    let model = MicroplaneConcrete::new(params)?;
    let mut point = MaterialPoint::new(&model, h)?;
    let mut pts = vec![([0.0; 6], [0.0; 6])];
    let mut peak: f64 = 0.0;
    let mut shear_from: Option<(f64, [f64; 6])> = None;
    let mut previous = 0.0;
    for e in strains(end) {
        let dt = (e - previous) / QUASI_STATIC_RATE;
        previous = e;
        let p = match path {
            PointPath::UniaxialStress => point.mixed_step_subdivided(&uniaxial_controls(e), dt)?,
            PointPath::UniaxialStrain => point.strain_step([e, 0.0, 0.0, 0.0, 0.0, 0.0], dt),
            PointPath::Bonded | PointPath::TensionShear { .. } => match shear_from {
                None => {
                    let p = point.mixed_step_subdivided(&uniaxial_controls(e), dt)?;
                    if p.stress[0] < peak && e > 4e-5 {
                        shear_from = Some((e, p.strain));
                    }
                    p
                }
                Some((e0, s0)) => {
                    let ratio = match path {
                        PointPath::TensionShear { ratio } => ratio,
                        _ => 0.0,
                    };
                    // Sym holds tensor shears: gamma_xy = 2 E_12.
                    let mut s = s0;
                    s[0] = e;
                    s[3] = 0.5 * ratio * (e - e0);
                    point.strain_step(s, dt)
                }
            },
        };
        peak = peak.max(p.stress[0]);
        pts.push((p.strain, p.stress));
        if !matches!(path, PointPath::TensionShear { .. }) && e > 4e-4 && p.stress[0] < 1e-3 * peak
        {
            break;
        }
    }
    let slope = pts[1].1[0] / pts[1].0[0];
    let work: f64 = pts
        .windows(2)
        .map(|w| {
            (0..6)
                .map(|i| {
                    let f = if i < 3 { 1.0 } else { 2.0 };
                    f * 0.5 * (w[0].1[i] + w[1].1[i]) * (w[1].0[i] - w[0].0[i])
                })
                .sum::<f64>()
        })
        .sum();
    let last_e = pts.last().map_or(0.0, |p| p.0[0]);
    let tail = pts
        .iter()
        .filter(|p| p.0[0] >= 0.9 * last_e)
        .flat_map(|p| p.1.iter().map(|s| s.abs()))
        .fold(0.0, f64::max);
    Ok(PointCurve {
        w: pts.iter().map(|(e, s)| h * (e[0] - s[0] / slope)).collect(),
        sigma: pts.iter().map(|p| p.1[0]).collect(),
        shear: pts.iter().map(|p| p.1[3]).collect(),
        peak,
        fracture_energy: h * work,
        residual_ratio: pts.last().map_or(0.0, |p| p.1[0]) / peak,
        residual_any_ratio: tail / peak,
        final_lateral_strain: pts.last().map_or(0.0, |p| p.0[1]),
        final_axial_strain: last_e,
    })
}

/// Microplane parameters of the body or material region `name` of `scene`.
pub fn region_parameters(scene: &Scene, name: &str) -> Result<MicroplaneParameters, BandError> {
    let spec = scene
        .bodies
        .iter()
        .flat_map(|b| {
            std::iter::once((b.name.as_str(), &b.material))
                .chain(b.regions.iter().map(|r| (r.name.as_str(), &r.material)))
        })
        .find(|(n, _)| *n == name)
        .map(|(_, m)| m)
        .ok_or_else(|| BandError::NoRegion { name: name.into() })?;
    match spec.model(name).map_err(BandError::Material)? {
        MaterialModel::Microplane(p) => Ok(p),
        _ => Err(BandError::NotMicroplane { name: name.into() }),
    }
}

/// Microplane parameters of the body or material region `name` of a built model.
pub fn model_parameters(
    model: &impact_solver::model::Model,
    name: &str,
) -> Result<MicroplaneParameters, BandError> {
    let b = model
        .body_index(name)
        .ok_or_else(|| BandError::NoModelRegion { name: name.into() })?;
    match model.bodies[b].material.model() {
        Some(MaterialModel::Microplane(p)) => Ok(p),
        _ => Err(BandError::NotMicroplane { name: name.into() }),
    }
}

/// The band of a prism run: which columns and sizes (see the module doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BandSpec {
    /// The material region (or body) of microplane concrete that forms the band.
    pub band: String,
    /// Reaction column of the pulled end (N).
    pub force: String,
    /// Displacement column of the pulled end (m).
    pub end_displacement: String,
    /// Mean displacement columns of the band's two faces (m).
    pub band_left: String,
    /// Mean displacement column of the band's right face (m); see `band_left`.
    pub band_right: String,
    /// Cross-section (m^2).
    pub area: f64,
    /// Band width = element size `h` (m).
    pub element_size: f64,
    /// The material-point path of the comparison.
    #[serde(default)]
    pub path: PointPath,
    /// Further material-point paths to draw in the plot (not measured).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub also_plot: Vec<PointPath>,
}

/// What a band measure returns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BandQuantity {
    /// Dissipated energy per crack area (N/mm).
    FractureEnergy,
    /// RMS of `t(w) - sigma_point(w)` over the softening records of the run, over the point's
    /// peak (`-`).
    TractionOpeningRms,
    /// Largest `|t(w) - sigma_point(w)|` over the same records, over the point's peak.
    TractionOpeningMax,
    /// |Mean traction| over the last tenth of the records (the ringing of the unloaded halves
    /// averages out) over the peak traction.
    FinalTractionRatio,
    /// Peak traction over the material point's peak stress.
    PeakRatio,
}

/// A band measure: `{ crack_band: { quantity, spec: {...} } }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BandMeasure {
    /// What the measure returns.
    pub quantity: BandQuantity,
    /// Where the band and its history columns are.
    pub spec: BandSpec,
}

/// The traction-opening curve of a run.
#[derive(Debug, Clone)]
pub struct RunCurve {
    /// Band opening `w = (u_right - u_left) - t h / K_b` at each history row (m).
    pub w: Vec<f64>,
    /// Traction `t = F / A` at each history row (Pa).
    pub t: Vec<f64>,
    /// Index of the peak traction.
    pub peak: usize,
    /// Dissipated energy per crack area `G` (N/m = J/m^2): external work less the elastic
    /// energy still stored, over the cross-section.
    pub fracture_energy: f64,
}

/// `column(name)` gives a history column.
pub fn run_curve(
    spec: &BandSpec,
    column: &dyn Fn(&str) -> Result<Vec<f64>, CurveError>,
) -> Result<RunCurve, BandError> {
    let force = column(&spec.force)?;
    let end = column(&spec.end_displacement)?;
    let (left, right) = (column(&spec.band_left)?, column(&spec.band_right)?);
    let t: Vec<f64> = force.iter().map(|f| f / spec.area).collect();
    let strain: Vec<f64> = left
        .iter()
        .zip(&right)
        .map(|(l, r)| (r - l) / spec.element_size)
        .collect();
    let k_band = crate::beam::history::secant_stiffness(&t, &strain, 0.3)?;
    let k = crate::beam::history::secant_stiffness(&force, &end, 0.3)?;
    let w = strain
        .iter()
        .zip(&t)
        .map(|(e, t)| spec.element_size * (e - t / k_band))
        .collect();
    let work: f64 = force
        .windows(2)
        .zip(end.windows(2))
        .map(|(f, u)| 0.5 * (f[0] + f[1]) * (u[1] - u[0]))
        .sum();
    let last = *force.last().ok_or(BandError::Empty)?;
    let peak = (0..t.len())
        .max_by(|&a, &b| t[a].total_cmp(&t[b]))
        .ok_or(BandError::Empty)?;
    Ok(RunCurve {
        w,
        t,
        peak,
        fracture_energy: (work - last * last / (2.0 * k)) / spec.area,
    })
}

/// Linear interpolation of `(x, y)` at `x0` (x increasing at first; the first crossing counts).
fn interpolate(x: &[f64], y: &[f64], x0: f64) -> Option<f64> {
    x.windows(2)
        .zip(y.windows(2))
        .find(|(x, _)| x[0] <= x0 && x0 <= x[1] && x[1] > x[0])
        .map(|(x, y)| y[0] + (y[1] - y[0]) * (x0 - x[0]) / (x[1] - x[0]))
}

/// The run's softening records `(w, t)` with the point's `sigma(w)` there: from the run's peak on,
/// while `w` lies within the point's curve.
fn softening_pairs(run: &RunCurve, point: &PointCurve) -> Vec<(f64, f64, f64)> {
    let start = point
        .sigma
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |p| p.0);
    let (pw, ps) = (&point.w[start..], &point.sigma[start..]);
    run.w[run.peak..]
        .iter()
        .zip(&run.t[run.peak..])
        .filter_map(|(&w, &t)| interpolate(pw, ps, w).map(|s| (w, t, s)))
        .collect()
}

impl BandMeasure {
    /// The measure's value from the run's history columns (`column(name)`), with the band's
    /// material taken from `model`; the error says which column or curve is missing.
    pub fn evaluate(
        &self,
        model: &impact_solver::model::Model,
        column: &dyn Fn(&str) -> Result<Vec<f64>, CurveError>,
    ) -> Result<f64, BandError> {
        let spec = &self.spec;
        let run = run_curve(spec, column)?;
        let point = || -> Result<PointCurve, BandError> {
            point_curve(
                &model_parameters(model, &spec.band)?,
                spec.element_size,
                spec.path,
                0.05,
            )
        };
        Ok(match self.quantity {
            BandQuantity::FractureEnergy => run.fracture_energy * 1e-3,
            BandQuantity::FinalTractionRatio => {
                let tail = &run.t[run.t.len() - (run.t.len() / 10).max(1)..];
                (tail.iter().sum::<f64>() / tail.len() as f64).abs() / run.t[run.peak]
            }
            BandQuantity::PeakRatio => run.t[run.peak] / point()?.peak,
            BandQuantity::TractionOpeningRms | BandQuantity::TractionOpeningMax => {
                let point = point()?;
                let pairs = softening_pairs(&run, &point);
                if pairs.is_empty() {
                    return Err(BandError::NoSoftening);
                }
                let d = pairs.iter().map(|(_, t, s)| (t - s) / point.peak);
                if self.quantity == BandQuantity::TractionOpeningMax {
                    d.fold(0.0, |a: f64, x| a.max(x.abs()))
                } else {
                    (d.map(|x| x * x).sum::<f64>() / pairs.len() as f64).sqrt()
                }
            }
        })
    }
}

/// A material-point diagnostic that needs no run: `{ crack_band_point: { band, element_size,
/// path, quantity } }`, the parameters taken from the scene's body or region `band`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointMeasure {
    /// The scene's body or region of microplane concrete whose parameters are used.
    pub band: String,
    /// Element size `h` of the point (m), the band width.
    pub element_size: f64,
    /// The path the point is driven along.
    pub path: PointPath,
    /// Axial strain at the end of the path (default 0.05; the uniaxial paths stop earlier once
    /// the stress has fallen below 1e-3 of its peak).
    #[serde(default = "default_end")]
    pub end_strain: f64,
    /// What the measure returns.
    pub quantity: PointQuantity,
}

fn default_end() -> f64 {
    0.05
}

/// What a material-point diagnostic returns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PointQuantity {
    /// `h int sigma : d eps` over the path (N/mm).
    FractureEnergy,
    /// `sigma_xx / peak` at the end of the path: 0 without stress locking.
    ResidualRatio,
    /// Largest `|sigma_ij| / peak` over the last tenth of the path.
    ResidualAnyRatio,
    /// `-E_yy / E_xx` at the end of the path: how much the point contracts laterally once the
    /// crack is open (0 where the lateral strains are held).
    FinalLateralContraction,
}

impl PointMeasure {
    /// Drives the point with the band's parameters from `model` and returns the quantity.
    pub fn evaluate(&self, model: &impact_solver::model::Model) -> Result<f64, BandError> {
        let c = point_curve(
            &model_parameters(model, &self.band)?,
            self.element_size,
            self.path,
            self.end_strain,
        )?;
        Ok(match self.quantity {
            PointQuantity::FractureEnergy => c.fracture_energy * 1e-3,
            PointQuantity::ResidualRatio => c.residual_ratio,
            PointQuantity::ResidualAnyRatio => c.residual_any_ratio,
            PointQuantity::FinalLateralContraction => {
                -c.final_lateral_strain / c.final_axial_strain
            }
        })
    }
}

/// The plot of a band case: the run's traction-opening curve beside the material point's.
pub fn plot_series(
    spec: &BandSpec,
    scene: &Scene,
    column: &dyn Fn(&str) -> Result<Vec<f64>, CurveError>,
) -> Result<Vec<crate::results::Series>, BandError> {
    let run = run_curve(spec, column)?;
    let point = point_curve(
        &region_parameters(scene, &spec.band)?,
        spec.element_size,
        spec.path,
        0.05,
    )?;
    let mm = |w: &[f64]| w.iter().map(|w| w * 1e3).collect::<Vec<_>>();
    let mpa = |s: &[f64]| s.iter().map(|s| s * 1e-6).collect::<Vec<_>>();
    // The run goes on far past the opening where the point's stress is gone; draw it up to 1.5
    // times the point's last opening so that the softening branches fill the plot.
    let w_max = 1.5 * point.w.last().copied().unwrap_or(f64::INFINITY);
    let n = run.w.iter().position(|&w| w > w_max).unwrap_or(run.w.len());
    let name = |path: &PointPath| {
        let path = match path {
            PointPath::UniaxialStress => "uniaxial stress".to_string(),
            PointPath::UniaxialStrain => "uniaxial strain".to_string(),
            PointPath::Bonded => "lateral strains held after the peak".to_string(),
            PointPath::TensionShear { ratio } => format!("tension, then shear 1 : {ratio}"),
        };
        format!("material point, h = {} mm, {path}", spec.element_size * 1e3)
    };
    let mut series = vec![
        crate::results::Series {
            name: "prism: end reaction / area".into(),
            x: mm(&run.w[..n]),
            y: mpa(&run.t[..n]),
        },
        crate::results::Series {
            name: name(&spec.path),
            x: mm(&point.w),
            y: mpa(&point.sigma),
        },
    ];
    for path in &spec.also_plot {
        let c = point_curve(
            &region_parameters(scene, &spec.band)?,
            spec.element_size,
            *path,
            0.05,
        )?;
        let n = c.w.iter().position(|&w| w > w_max).unwrap_or(c.w.len());
        series.push(crate::results::Series {
            name: name(path),
            x: mm(&c.w[..n]),
            y: mpa(&c.sigma[..n]),
        });
    }
    Ok(series)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn thesis() -> MicroplaneParameters {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("cases/materials/thesis-concrete.yaml");
        impact_solver::material::read_microplane_file(&path).unwrap()
    }

    /// The crack band's path (uniaxial stress to the peak, lateral strains held after it)
    /// reproduces the GF the thesis concrete is calibrated to on it (0.10 N/mm).
    #[test]
    fn bonded_point_dissipates_gf() {
        let c = point_curve(&thesis(), 0.05, PointPath::Bonded, 0.05).unwrap();
        assert!(
            (c.fracture_energy - 100.0).abs() < 10.0,
            "{}",
            c.fracture_energy
        );
        assert!(c.residual_ratio < 2e-3);
        assert!(c.w[0] == 0.0 && c.w.last().unwrap() > &0.0);
    }
}
#[cfg(test)]
mod print {
    #[test]
    #[ignore]
    fn print_point_curves() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("cases/materials/thesis-concrete.yaml");
        let p = impact_solver::material::read_microplane_file(&path).unwrap();
        for (h, path) in [
            (0.05, super::PointPath::UniaxialStress),
            (0.05, super::PointPath::UniaxialStrain),
            (0.05, super::PointPath::TensionShear { ratio: 1.0 }),
            (0.05, super::PointPath::TensionShear { ratio: 0.5 }),
            (0.025, super::PointPath::UniaxialStress),
            (0.025, super::PointPath::UniaxialStrain),
        ] {
            let c = super::point_curve(&p, h, path, 0.05).unwrap();
            println!(
                "h {h} {path:?}: peak {:.4e} G {:.4} N/m residual {:.3e} any {:.3e} points {}",
                c.peak,
                c.fracture_energy,
                c.residual_ratio,
                c.residual_any_ratio,
                c.w.len()
            );
            let mut next = 0.0;
            for i in 0..c.w.len() {
                if c.w[i] >= next {
                    println!(
                        "  w {:.4e} sigma {:.4e} shear {:.4e}",
                        c.w[i], c.sigma[i], c.shear[i]
                    );
                    next = c.w[i] + 0.01e-3;
                    if next > 0.3e-3 {
                        next = c.w[i] * 1.5;
                    }
                }
            }
        }
    }
}
