//! The targets only a tensile boundary is held to (docs/MICROPLANE.md "Tensile boundary"):
//! Kupfer & Gerstle's (1973) tension under lateral compression, within 10 % at `-0.5`, `-1`
//! and `-2 ft` and 15 % at `-0.3 fc`, and a crack opened to `w_cr` in x that still carries at
//! least 0.8 of the uncracked point's compression along y.

use super::super::crack_compression::{
    compression_along_crack, kupfer_gerstle, lateral_tension_ratio, CrackCompression,
};
use super::super::driver::DriverError;
use super::super::MicroplaneConcrete;
use super::{Outcome, Targets};

/// The lateral stresses of Kupfer's tension-compression targets, in units of `ft` (the last is
/// `-0.3 fc` for the thesis concrete's `fc / ft = 16.7`, given in units of `fc`: see
/// [`BoundaryChecks::lateral`]).
pub const KUPFER_LATERAL: [(f64, &str); 4] = [(0.5, "ft"), (1.0, "ft"), (2.0, "ft"), (0.3, "fc")];

/// The crack opening of the compression along a crack (m): the crack indicator's `w_cr`.
pub const CRACK_OPENING: f64 = 2.0e-4;

/// The targets that only a tensile boundary is held to (docs/MICROPLANE.md "Tensile boundary").
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryChecks {
    /// Tensile peak under each lateral stress of [`KUPFER_LATERAL`] over the uniaxial one, and
    /// whether the path passed its peak (else a lower bound).
    pub lateral: [(f64, bool); 4],
    /// A crack opened to [`CRACK_OPENING`] in x, compressed along y.
    pub crack: Result<CrackCompression, DriverError>,
}

impl BoundaryChecks {
    /// The lateral stresses (Pa) of [`KUPFER_LATERAL`] for targets `t`.
    pub fn lateral_stresses(t: &Targets) -> [f64; 4] {
        KUPFER_LATERAL.map(|(k, unit)| -k * if unit == "ft" { t.ft } else { t.fc })
    }

    pub(super) fn of(model: &MicroplaneConcrete, t: &Targets, uniaxial: f64) -> Self {
        let h = t.element_size;
        let lateral = Self::lateral_stresses(t).map(|s| {
            lateral_tension_ratio(model, h, s, uniaxial, 8e-4).unwrap_or((f64::NAN, false))
        });
        let crack = compression_along_crack(model, h, CRACK_OPENING, 3.0 * t.fc_strain[1]);
        Self { lateral, crack }
    }
}

impl BoundaryChecks {
    /// The band of each lateral stress of [`KUPFER_LATERAL`]: relative tolerance.
    pub const TOLERANCE: [f64; 4] = [0.10, 0.10, 0.10, 0.15];

    /// The least ratio of compression along a crack to the uncracked point's.
    pub const CRACK_RATIO: f64 = 0.8;

    /// The outcomes of the checks against targets `t`: a lateral ratio counts as met only where
    /// the path passed its peak (a lower bound within the band proves nothing).
    pub fn outcomes(&self, t: &Targets) -> Vec<Outcome> {
        let mut out: Vec<Outcome> = Self::lateral_stresses(t)
            .iter()
            .zip(&KUPFER_LATERAL)
            .zip(self.lateral.iter().zip(Self::TOLERANCE))
            .map(|((&s, (k, unit)), (&(ratio, passed), tolerance))| {
                let reference = kupfer_gerstle(s, t.fc);
                Outcome {
                    name: format!("tensile peak under a lateral stress of -{k} {unit}, over ft"),
                    target: format!(
                        "{reference:.3} +- {} % (Kupfer & Gerstle 1973){}",
                        tolerance * 100.0,
                        if passed {
                            ""
                        } else {
                            "; path ended before the peak"
                        }
                    ),
                    achieved: ratio,
                    unit: "-".into(),
                    met: passed && (ratio / reference - 1.0).abs() <= tolerance,
                }
            })
            .collect();
        let (achieved, met) = match &self.crack {
            Ok(c) => (c.ratio(), c.ratio() >= Self::CRACK_RATIO),
            Err(_) => (f64::NAN, false),
        };
        out.push(Outcome {
            name: format!(
                "compression along y of a point cracked in x to w = {} mm, over the uncracked",
                CRACK_OPENING * 1e3
            ),
            target: format!("at least {}", Self::CRACK_RATIO),
            achieved,
            unit: "-".into(),
            met,
        });
        out
    }
}
