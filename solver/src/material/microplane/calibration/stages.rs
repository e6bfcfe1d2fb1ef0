//! The three stages of the calibration (module documentation of `calibration`): tension,
//! the reference size that keeps the fracture energy, compression; twice, then tension again.

use super::super::experiments::QUASI_STATIC_RATE;
use super::super::{MicroplaneConcrete, MicroplaneParameters};
use super::{nelder_mead, CalibrationError, Evaluation, Free, Targets};

/// Progress of a calibration: a line per stage.
pub type Log<'a> = &'a mut dyn FnMut(&str);

/// Minimises `cost` over the `free` parameters; with `refit`, the fracture energy is fitted
/// (`fit_reference_size`) at every evaluation, so that shapes are compared at the target `GF`.
fn optimise(
    start: &MicroplaneParameters,
    free: &[Free],
    evaluations: usize,
    cost: &dyn Fn(&Evaluation) -> f64,
    targets: &Targets,
    refit: bool,
) -> MicroplaneParameters {
    let x0: Vec<f64> = free.iter().map(|v| v.get(start).ln()).collect();
    let step = vec![0.15; free.len()];
    let mut f = |x: &[f64]| {
        let mut p = *start;
        for (v, &xi) in free.iter().zip(x) {
            v.set(&mut p, xi.exp());
        }
        if refit && fit_reference_size(&mut p, targets).is_err() {
            return 1e6;
        }
        match Evaluation::of(&p, targets) {
            Ok(e) => cost(&e),
            Err(_) => 1e6,
        }
    };
    let (x, _) = nelder_mead(&mut f, &x0, &step, evaluations);
    let mut p = *start;
    for (v, &xi) in free.iter().zip(&x) {
        v.set(&mut p, xi.exp());
    }
    p
}

/// Fits `h_ref` so that `h int sigma d eps` at `element_size` equals `GF` (secant iterations:
/// the energy is close to proportional to `h_ref`). With a Hordijk tail, `h_ref` is the element
/// size of the strength tests and the tail length is fitted instead (the energy is affine in it;
/// only the product of `h_ref` and the tail, the opening where the law ends, matters).
fn fit_reference_size(p: &mut MicroplaneParameters, t: &Targets) -> Result<(), CalibrationError> {
    let (scaled, iterations): (fn(&mut MicroplaneParameters) -> &mut f64, usize) =
        if p.tension_boundary.is_some() {
            // The boundary's energy is its strength times its softening strain at h_ref.
            p.h_ref = t.element_size;
            (
                |p| match &mut p.tension_boundary {
                    Some(b) => &mut b.softening_strain,
                    None => unreachable!("checked above"),
                },
                30,
            )
        } else if p.hordijk_tail > 0.0 {
            p.h_ref = t.element_size;
            (|p| &mut p.hordijk_tail, 60)
        } else {
            (|p| &mut p.h_ref, 20)
        };
    for _ in 0..iterations {
        let model = MicroplaneConcrete::new(*p)?;
        let (_, r) = t
            .fracture_path
            .tension(&model, t.element_size, QUASI_STATIC_RATE)
            .map_err(|e| CalibrationError::experiment("tension", e))?;
        let ratio = t.gf / r.fracture_energy;
        if (ratio - 1.0).abs() < 1e-4 {
            break;
        }
        *scaled(p) *= ratio;
    }
    Ok(())
}

/// The three stages (module doc) from `start`, with `evaluations` per optimiser stage; returns
/// the parameters and their evaluation.
pub fn calibrate(
    start: &MicroplaneParameters,
    targets: &Targets,
    evaluations: usize,
    log: Log,
) -> Result<(MicroplaneParameters, Evaluation), CalibrationError> {
    let mut p = *start;
    p.rate_effect = None;
    p.tension_driver = targets.tension_driver;
    p.relaxation_driver = targets.relaxation_driver;
    p.dilatancy = targets.dilatancy;
    p.crack_friction = targets.crack_friction;
    p.tension_boundary = targets.tension_boundary;
    // With a tensile boundary the tension laws are elastic: its strength is fitted instead,
    // and its softening strain takes the fracture energy.
    let tension_parameters: &[Free] = if p.tension_boundary.is_some() {
        &[Free::BoundaryStrength]
    } else {
        &[Free::E1, Free::M]
    };
    let tension = |p: &mut MicroplaneParameters, stage: &str, log: &mut dyn FnMut(&str)| {
        *p = optimise(
            p,
            tension_parameters,
            evaluations,
            &|e| e.tension_cost(targets),
            targets,
            p.hordijk_tail > 0.0 || p.tension_boundary.is_some(),
        );
        fit_reference_size(p, targets)?;
        log(&format!(
            "{stage}, tension: e1 = {:.4e}, m = {:.3}, h_ref = {:.4} m, hordijk_tail = {:.3}, \
             tension_boundary = {:?}",
            p.e1, p.m, p.h_ref, p.hordijk_tail, p.tension_boundary
        ));
        Ok::<(), CalibrationError>(())
    };
    // The dilatancy is fitted with the compression only when the start has some (a start of 0
    // keeps the thesis' volumetric law, MICROPLANE "Dilatancy").
    let compression_parameters: &[Free] = if p.dilatancy > 0.0 {
        &[
            Free::E2,
            Free::N,
            Free::E3,
            Free::E4,
            Free::K,
            Free::Dilatancy,
        ]
    } else {
        &[Free::E2, Free::N, Free::E3, Free::E4, Free::K]
    };
    for round in 1..=2 {
        tension(&mut p, &format!("round {round}"), log)?;
        // Shear also carries some of the tension, so the tensile targets stay in the cost.
        p = optimise(
            &p,
            compression_parameters,
            evaluations,
            &|e| e.compression_cost(targets) + e.tension_cost(targets),
            targets,
            false,
        );
        log(&format!(
            "round {round}, compression: e2 = {:.4e}, n = {:.3}, e3 = {:.4e}, e4 = {:.3}, k = {:.3}, \
             dilatancy = {:.3}",
            p.e2, p.n, p.e3, p.e4, p.k, p.dilatancy
        ));
    }
    tension(&mut p, "final", log)?;
    p.rate_effect = start.rate_effect;
    let mut quasi_static = p;
    quasi_static.rate_effect = None;
    let evaluation = Evaluation::checked(&quasi_static, targets)?;
    Ok((p, evaluation))
}
