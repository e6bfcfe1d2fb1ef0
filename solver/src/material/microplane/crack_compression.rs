//! Two single-point experiments of the tensile boundary's targets (docs/MICROPLANE.md "Tensile
//! boundary"): tension under a held lateral compression against Kupfer & Gerstle's (1973)
//! tension-compression line `sigma_1 / f_t = 1 + 0.8 sigma_2 / f_c`, and the compression a point
//! carries along a crack that is open across it.

use super::driver::{DriverError, MaterialPoint, PathPoint};
use super::experiments::{bonded_tension, tension_under_lateral_stress};
use super::MicroplaneConcrete;

/// Kupfer & Gerstle's tensile strength under the lateral stress `lateral` (Pa, negative in
/// compression), over the uniaxial one, for compressive strength `fc` (Pa, positive).
pub fn kupfer_gerstle(lateral: f64, fc: f64) -> f64 {
    1.0 + 0.8 * lateral / fc
}

/// The tensile peak under a held lateral stress over the uniaxial peak `uniaxial` (Pa), with
/// whether the path passed the peak (otherwise the ratio is a lower bound). `end`: axial strain
/// added after the preload, in 400 increments.
pub fn lateral_tension_ratio(
    model: &MicroplaneConcrete,
    h: f64,
    lateral: f64,
    uniaxial: f64,
    end: f64,
) -> Result<(f64, bool), DriverError> {
    let curve = tension_under_lateral_stress(model, h, lateral, end, 400)?;
    Ok((curve.peak().stress[0] / uniaxial, curve.peak_passed()))
}

/// What [`compression_along_crack`] measures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrackCompression {
    /// Largest compressive stress `-sigma_22` of the cracked point (Pa).
    pub cracked: f64,
    /// The same of the uncracked point on the same path (Pa).
    pub virgin: f64,
    /// The axial strain the crack was opened to before the compression, `w / h`.
    pub opening_strain: f64,
}

impl CrackCompression {
    /// `cracked / virgin`.
    pub fn ratio(&self) -> f64 {
        self.cracked / self.virgin
    }
}

/// A point cracked in x to the opening `w` (m) on the crack band's path (uniaxial tension to the
/// peak, lateral strains held after it: [`bonded_tension`], element size `h`), then compressed
/// along y by `end` in 600 strain increments with the other strains held, as a band bonded to
/// its neighbours holds them; against an uncracked point on the same path (the other strains
/// held at zero). A crack along the load should leave
/// the columns beside it their strength (the "compression along a crack").
pub fn compression_along_crack(
    model: &MicroplaneConcrete,
    h: f64,
    w: f64,
    end: f64,
) -> Result<CrackCompression, DriverError> {
    let opening_strain = w / h;
    let (curve, _) = bonded_tension(model, h, 1e-6)?;
    // The bonded path up to the first point past the opening (or its end, where the crack is
    // already traction-free).
    let reached = curve
        .points
        .iter()
        .position(|p| p.strain[0] >= opening_strain)
        .map_or(curve.points.len(), |i| i + 1);
    let opening = &curve.points[..reached];
    let crushing = |opening: &[PathPoint]| -> Result<f64, DriverError> {
        let mut point = MaterialPoint::new(model, h)?;
        // The opening replayed strain by strain, at the path's own times.
        let mut time = 0.0;
        for p in opening {
            point.strain_step(p.strain, (p.time - time).max(1e-12));
            time = p.time;
        }
        // Where the path ended traction-free before the opening: opened on with the lateral
        // strains held.
        if let Some(last) = opening.last().filter(|p| p.strain[0] < opening_strain) {
            for i in 1..=100 {
                let mut strain = last.strain;
                strain[0] += (opening_strain - last.strain[0]) * f64::from(i) / 100.0;
                point.strain_step(strain, 1.0);
            }
        }
        let start = point.strain;
        let mut peak: f64 = 0.0;
        for i in 1..=600 {
            let mut strain = start;
            strain[1] -= end * f64::from(i) / 600.0;
            peak = peak.max(-point.strain_step(strain, 1.0).stress[1]);
        }
        Ok(peak)
    };
    Ok(CrackCompression {
        cracked: crushing(opening)?,
        virgin: crushing(&[])?,
        opening_strain,
    })
}
