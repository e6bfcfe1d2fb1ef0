//! The hinge as a harness reference: the case's [`HingeSpec`] (which law, which material, how
//! the pre-peak is modelled) and [`hinge_reference`], which builds the law from the scene and
//! evaluates the hinge's peak load.

use crate::error::ReferenceError;
use impact_solver::material::microplane::experiments::{tension_branches, TensionBranches};
use impact_solver::material::microplane::MicroplaneConcrete;
use impact_solver::material::MaterialModel;
use impact_solver::scene::Scene;
use serde::{Deserialize, Serialize};

use super::*;

/// The law a hinge reference feeds the hinge with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HingeLaw {
    /// The crack-opening curve of the case's own microplane material at `element_size`.
    Own,
    /// fib MC2010 bilinear at that material's `f_t` and `G_F` (from the same curve).
    Mc2010,
    /// Hordijk (1991) at that material's `f_t` and `G_F`.
    Hordijk,
}

/// The layers' law before the crack opens.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HingePrePeak {
    /// Linear elastic up to `f_t` (Olesen's hinge, the cohesive-crack idealisation).
    #[default]
    Linear,
    /// The material's own rising branch from the same tension test (`law: own` only): the
    /// bulk of a smeared-crack beam is not linear up to `f_t`, and its pre-peak inelastic
    /// strain, spread over the hinge, carries moment ([`PrePeak`]).
    Own,
}

/// What a hinge reference gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HingeQuantity {
    /// Peak mid-span bending moment (N m).
    PeakBendingMoment,
    /// Peak mid-span load `4 M / L` (N).
    PeakLoad,
}

/// `reference: { hinge: { depth: 0.6, width: 0.3, span: 2.8, law: own, element_size: 0.05,
/// quantity: peak_bending_moment } }`; `body` names the microplane body whose material is used
/// (default: the first microplane body of the scene).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HingeSpec {
    /// Beam depth `h` (m).
    pub depth: f64,
    /// Beam width `b` (m).
    pub width: f64,
    /// Span `L` between the supports (m).
    pub span: f64,
    /// The softening law the hinge's layers follow.
    pub law: HingeLaw,
    /// Element size (m) at which the material's own crack-opening curve is taken (the crack
    /// band of the case's mesh).
    pub element_size: f64,
    /// What the reference gives: the peak moment or the peak load.
    pub quantity: HingeQuantity,
    /// The microplane body whose material is used; the first one of the scene when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body: Option<String>,
    /// The layers' law before the crack opens (default linear).
    #[serde(default)]
    pub pre_peak: HingePrePeak,
    /// Depth of a notch at mid-span (m; default none): the hinge spans the ligament.
    #[serde(default)]
    pub notch: f64,
}

/// Both branches of a microplane material's own law at `element_size`, from the tension test
/// the calibration defines GF on (one run): the rising branch, and the crack-opening law with its
/// opening counted from the peak.
pub fn own_law_with_pre_peak(
    model: &MicroplaneConcrete,
    element_size: f64,
) -> (SofteningLaw, PrePeak) {
    counted_from_peak(
        tension_branches(model, element_size),
        element_size,
        model.parameters.youngs_modulus,
    )
}

/// The crack-opening law with its opening counted from the peak, and the rising branch: the bulk
/// of a hinge with that branch holds the pre-peak inelastic strain `eps_p - f_t / E`, which the
/// crack band's reading (`crack_opening_curve`) lumps into the opening at `f_t`.
fn counted_from_peak(
    branches: TensionBranches,
    element_size: f64,
    youngs_modulus: f64,
) -> (SofteningLaw, PrePeak) {
    let ((strain, stress), (w, sigma)) = (branches.rising, branches.opening);
    let pre = PrePeak { strain, stress };
    let ft = sigma.first().copied().unwrap_or(0.0);
    let w_peak = element_size * (pre.peak_strain() - ft / youngs_modulus);
    let (mut ws, mut ss) = (vec![0.0], vec![ft]);
    for (wi, si) in w.iter().zip(&sigma) {
        if *wi > w_peak {
            ws.push(wi - w_peak);
            ss.push(*si);
        }
    }
    (SofteningLaw::Tabulated { w: ws, sigma: ss }, pre)
}

/// The hinge a [`HingeSpec`] describes, built from the scene's microplane material.
pub struct SceneHinge {
    /// The hinge.
    pub hinge: Hinge,
    /// The body (or `body/region`) whose material feeds it.
    pub body: String,
    /// The law in words.
    pub law_name: &'static str,
    /// Tensile strength of the law (Pa).
    pub ft: f64,
    /// Fracture energy of the law (N/m).
    pub gf: f64,
}

/// The hinge of `spec` on the material of `scene` (see [`hinge_reference`]).
pub fn scene_hinge(scene: &Scene, spec: &HingeSpec) -> Result<SceneHinge, ReferenceError> {
    let (name, parameters) = scene
        .bodies
        .iter()
        .filter(|b| spec.body.as_ref().is_none_or(|n| n == &b.name))
        .find_map(|b| {
            // The body's own material first, then its regions (a band of concrete between
            // elastic neighbours).
            std::iter::once((b.name.clone(), &b.material))
                .chain(
                    b.regions
                        .iter()
                        .map(|r| (format!("{}/{}", b.name, r.name), &r.material)),
                )
                .find_map(|(name, m)| match m.model(&name) {
                    Ok(MaterialModel::Microplane(p)) => Some((name, p)),
                    _ => None,
                })
        })
        .ok_or_else(|| match &spec.body {
            Some(n) => ReferenceError::HingeBody { body: n.clone() },
            None => ReferenceError::HingeNeedsMicroplane,
        })?;
    let model = MicroplaneConcrete::new(parameters)?;
    let branches = tension_branches(&model, spec.element_size);
    let (w, sigma) = branches.opening.clone();
    if w.len() < 2 {
        return Err(ReferenceError::NoOpeningCurve {
            body: name,
            element_size: spec.element_size,
        });
    }
    // The curve starts at the test's peak stress: that is the material's f_t.
    let own = SofteningLaw::Tabulated { w, sigma };
    let (ft, gf) = (own.tensile_strength(), own.fracture_energy());
    let (law, name_of_law) = match spec.law {
        HingeLaw::Own => (own, "the material's own crack-opening curve"),
        HingeLaw::Mc2010 => (SofteningLaw::Mc2010 { ft, gf }, "MC2010 bilinear law"),
        HingeLaw::Hordijk => (SofteningLaw::Hordijk { ft, gf }, "Hordijk (1991) law"),
    };
    let e = parameters.youngs_modulus;
    if !(0.0..0.9 * spec.depth).contains(&spec.notch) {
        return Err(ReferenceError::Notch {
            notch: spec.notch,
            limit: 0.9 * spec.depth,
        });
    }
    let hinge = match spec.pre_peak {
        HingePrePeak::Linear => Hinge::new(spec.depth, spec.width, spec.span, e, law),
        HingePrePeak::Own => {
            if spec.law != HingeLaw::Own {
                return Err(ReferenceError::PrePeakNeedsOwnLaw);
            }
            let (law, pre) = counted_from_peak(branches, spec.element_size, e);
            Hinge::new(spec.depth, spec.width, spec.span, e, law).with_pre_peak(pre)
        }
    };
    let hinge = if spec.notch > 0.0 {
        hinge.with_notch(spec.notch)
    } else {
        hinge
    };
    Ok(SceneHinge {
        hinge,
        body: name,
        law_name: name_of_law,
        ft,
        gf,
    })
}

/// The reference value and a line saying how it was computed.
pub fn hinge_reference(scene: &Scene, spec: &HingeSpec) -> Result<(f64, String), ReferenceError> {
    let SceneHinge {
        hinge,
        body: name,
        law_name: name_of_law,
        ft,
        gf,
    } = scene_hinge(scene, spec)?;
    let peak = hinge.peak(1e4);
    let (value, what) = match spec.quantity {
        HingeQuantity::PeakBendingMoment => (peak.moment, "peak bending moment"),
        HingeQuantity::PeakLoad => (peak.load, "peak load 4 M / L"),
    };
    Ok((
        value,
        format!(
            "cohesive hinge (Olesen 2001, s = {} m, {} layers{}{}), {what} of a {} x {} m beam on \
             a {} m span, {name_of_law} of body `{name}` (f_t {:.3} MPa, G_F {:.1} N/m at {} m)",
            hinge.length,
            hinge.layers,
            if spec.notch > 0.0 {
                format!(", on the ligament above a {} m notch", spec.notch)
            } else {
                String::new()
            },
            match spec.pre_peak {
                HingePrePeak::Linear => "",
                HingePrePeak::Own => ", rising along the material's own pre-peak branch",
            },
            spec.depth,
            spec.width,
            spec.span,
            ft / 1e6,
            gf,
            spec.element_size
        ),
    ))
}
