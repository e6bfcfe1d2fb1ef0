//! A material-point driver: one homogeneous element of the microplane model under strain- or
//! stress-controlled paths, for calibration and for the catalogue's material cases.
//!
//! Every path is a sequence of increments of a time `dt`; the equivalent rate of each increment is
//! `gamma_dot = sqrt(1/2 dE:dE) / dt` (5.111). Components are either prescribed strains or
//! prescribed stresses; the free strains are found by Newton's method on the stress residual with a
//! finite-difference tangent, evaluated on copies of the history so that only the converged
//! increment is committed. At the strains of these tests (1e-2 at most) the Green-Lagrange strain
//! and the back-rotated Cauchy stress are the small-strain pair, so no kinematics is needed here.

use super::{CrackBand, MicroplaneConcrete, MicroplaneState, Sym};

/// What a component of an increment prescribes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Control {
    /// The strain component at the end of the increment.
    Strain(f64),
    /// The stress component at the end of the increment (Pa).
    Stress(f64),
}

/// One point of a path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathPoint {
    /// Time at the end of the increment (s).
    pub time: f64,
    /// Green-Lagrange strain `[11, 22, 33, 23, 13, 12]`, tensor shears (dimensionless).
    pub strain: Sym,
    /// Second Piola-Kirchhoff stress `[11, 22, 33, 23, 13, 12]` (Pa), tension positive.
    pub stress: Sym,
    /// Rate factor `F` of the strength (thesis (5.110)); 1 at static rates.
    pub rate_factor: f64,
}

/// Why an increment failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DriverError {
    /// The point's size `h` does not fit the model's crack band (the regularised softening
    /// would snap back); holds the model's explanation.
    #[error(transparent)]
    CrackBand(#[from] super::CrackBandError),
    /// Newton's method on the stress-controlled components did not converge.
    #[error(
        "stress control did not converge at t = {time:e} s: residual {residual:e} Pa after \
         {iterations} Newton iterations"
    )]
    NotConverged {
        /// Time at the end of the failed increment (s).
        time: f64,
        /// Euclidean norm of the stress misfit of the controlled components at the last
        /// iteration (Pa).
        residual: f64,
        /// Newton iterations spent.
        iterations: usize,
    },
}

/// One material point of size `h` (the crack band) with its history.
#[derive(Debug, Clone)]
pub struct MaterialPoint<'a> {
    model: &'a MicroplaneConcrete,
    band: CrackBand,
    /// The history variables of every microplane at the last committed increment.
    pub state: MicroplaneState,
    /// Green-Lagrange strain `[11, 22, 33, 23, 13, 12]` at the last committed increment.
    pub strain: Sym,
    /// Second Piola-Kirchhoff stress `[11, 22, 33, 23, 13, 12]` (Pa) at that increment.
    pub stress: Sym,
    /// Time of the last committed increment (s), from 0.
    pub time: f64,
}

/// Equivalent rate `sqrt(1/2 dE_ij dE_ij) / dt` (5.111), tensor shears counted twice.
pub fn equivalent_rate(from: &Sym, to: &Sym, dt: f64) -> f64 {
    if dt <= 0.0 {
        return 0.0;
    }
    let d: [f64; 6] = std::array::from_fn(|i| to[i] - from[i]);
    let sq =
        d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 2.0 * (d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
    (0.5 * sq).sqrt() / dt
}

impl<'a> MaterialPoint<'a> {
    /// A virgin point of size `h` (m).
    pub fn new(model: &'a MicroplaneConcrete, h: f64) -> Result<Self, DriverError> {
        Self::with_strength(model, h, 1.0)
    }

    /// A virgin point of size `h` (m) whose tensile strength is `strength` times the material's
    /// ([`MicroplaneConcrete::crack_band_with_strength`]).
    pub fn with_strength(
        model: &'a MicroplaneConcrete,
        h: f64,
        strength: f64,
    ) -> Result<Self, DriverError> {
        let band = model
            .crack_band_with_strength(h, strength)
            .map_err(DriverError::CrackBand)?;
        Ok(Self {
            model,
            band,
            state: model.initial_state(),
            strain: [0.0; 6],
            stress: [0.0; 6],
            time: 0.0,
        })
    }

    /// The material model the point evaluates.
    pub fn model(&self) -> &MicroplaneConcrete {
        self.model
    }

    /// Stress for `strain` reached in `dt` from the current point, without committing it.
    fn trial(&self, strain: &Sym, dt: f64) -> (Sym, MicroplaneState, f64) {
        let mut state = self.state.clone();
        let rate = equivalent_rate(&self.strain, strain, dt);
        let (stress, info) = self
            .model
            .update(&mut state.values, strain, rate, &self.band);
        (stress, state, info.rate_factor)
    }

    fn commit(&mut self, strain: Sym, stress: Sym, state: MicroplaneState, dt: f64) {
        self.strain = strain;
        self.stress = stress;
        self.state = state;
        self.time += dt;
    }

    fn point(&self) -> PathPoint {
        PathPoint {
            time: self.time,
            strain: self.strain,
            stress: self.stress,
            rate_factor: self.state.rate_factor(),
        }
    }

    /// A strain-controlled increment to `strain` in `dt`.
    pub fn strain_step(&mut self, strain: Sym, dt: f64) -> PathPoint {
        let (stress, state, _) = self.trial(&strain, dt);
        self.commit(strain, stress, state, dt);
        self.point()
    }

    /// A mixed increment in `dt`: prescribed strains where `controls` says `Strain`, prescribed
    /// stresses elsewhere.
    pub fn mixed_step(
        &mut self,
        controls: &[Control; 6],
        dt: f64,
    ) -> Result<PathPoint, DriverError> {
        let free: Vec<usize> = (0..6)
            .filter(|&i| matches!(controls[i], Control::Stress(_)))
            .collect();
        let mut strain = self.strain;
        for i in 0..6 {
            if let Control::Strain(e) = controls[i] {
                strain[i] = e;
            }
        }
        if free.is_empty() {
            return Ok(self.strain_step(strain, dt));
        }
        let target = |i: usize| match controls[i] {
            Control::Stress(s) => s,
            Control::Strain(_) => unreachable!(),
        };
        // Elastic predictor for the free strains: the elastic compliance applied to the change of
        // the prescribed strains keeps the first trial close.
        let elastic = self.model.elastic_stiffness();
        let residual_of =
            |stress: &Sym| -> Vec<f64> { free.iter().map(|&i| stress[i] - target(i)).collect() };
        // 1 Pa, or 1e-8 of the stress: far below anything a test compares.
        let tolerance = 1.0 + 1e-8 * norm(&self.stress);
        let mut trial = self.trial(&strain, dt);
        let mut residual = residual_of(&trial.0);
        let n = free.len();
        let mut iterations = 0;
        while norm(&residual) > tolerance && iterations < 60 {
            iterations += 1;
            // Finite-difference tangent of the free stresses with respect to the free strains,
            // falling back to the elastic one where the difference vanishes (fully open crack).
            let step = 1e-9;
            let mut jacobian = vec![vec![0.0; n]; n];
            for (c, &j) in free.iter().enumerate() {
                let mut perturbed = strain;
                perturbed[j] += step;
                let (s, _, _) = self.trial(&perturbed, dt);
                for (r, &i) in free.iter().enumerate() {
                    jacobian[r][c] = (s[i] - trial.0[i]) / step;
                }
                if jacobian[c][c].abs() < 1e-6 * elastic[j][j] {
                    jacobian[c][c] = 1e-6 * elastic[j][j];
                }
            }
            let delta = solve(jacobian, residual.iter().map(|r| -r).collect());
            // Backtracking: halve the step until the residual falls.
            let mut lambda = 1.0;
            let current = norm(&residual);
            loop {
                let mut candidate = strain;
                for (c, &j) in free.iter().enumerate() {
                    candidate[j] += lambda * delta[c];
                }
                let t = self.trial(&candidate, dt);
                let r = residual_of(&t.0);
                if norm(&r) < current || lambda < 1e-4 {
                    strain = candidate;
                    trial = t;
                    residual = r;
                    break;
                }
                lambda *= 0.5;
            }
        }
        if norm(&residual) > tolerance {
            return Err(DriverError::NotConverged {
                time: self.time + dt,
                residual: norm(&residual),
                iterations,
            });
        }
        self.commit(strain, trial.0, trial.1, dt);
        Ok(self.point())
    }

    /// A mixed increment that, when Newton's method fails, is cut into halves (down to 1/64) with
    /// the prescribed strains interpolated linearly; the prescribed stresses stay as given.
    pub fn mixed_step_subdivided(
        &mut self,
        controls: &[Control; 6],
        dt: f64,
    ) -> Result<PathPoint, DriverError> {
        self.subdivide(controls, dt, 0)
    }

    fn subdivide(
        &mut self,
        controls: &[Control; 6],
        dt: f64,
        depth: u32,
    ) -> Result<PathPoint, DriverError> {
        let saved = self.clone();
        match self.mixed_step(controls, dt) {
            Ok(p) => Ok(p),
            Err(e) if depth >= 6 => {
                *self = saved;
                Err(e)
            }
            Err(_) => {
                *self = saved;
                let start = self.strain;
                let half: [Control; 6] = std::array::from_fn(|i| match controls[i] {
                    Control::Strain(e) => Control::Strain(0.5 * (start[i] + e)),
                    stress => stress,
                });
                self.subdivide(&half, 0.5 * dt, depth + 1)?;
                self.subdivide(controls, 0.5 * dt, depth + 1)
            }
        }
    }

    /// Runs `controls` in turn, each in its time; on failure returns the points computed so far
    /// with the error.
    pub fn run(
        &mut self,
        increments: impl IntoIterator<Item = ([Control; 6], f64)>,
    ) -> (Vec<PathPoint>, Option<DriverError>) {
        let mut out = vec![self.point()];
        for (controls, dt) in increments {
            match self.mixed_step_subdivided(&controls, dt) {
                Ok(p) => out.push(p),
                Err(e) => return (out, Some(e)),
            }
        }
        (out, None)
    }

    /// Uniaxial stress along `x`: `E_11` to each value of `axial` in turn at the strain rate
    /// `rate` (1/s), all other stresses zero.
    pub fn uniaxial_stress(
        &mut self,
        axial: &[f64],
        rate: f64,
    ) -> Result<Vec<PathPoint>, DriverError> {
        let mut previous = self.strain[0];
        let increments: Vec<_> = axial
            .iter()
            .map(|&e| {
                let dt = (e - previous).abs() / rate;
                previous = e;
                (uniaxial_controls(e), dt)
            })
            .collect();
        match self.run(increments) {
            (points, None) => Ok(points),
            (_, Some(e)) => Err(e),
        }
    }
}

/// Uniaxial stress: `E_11 = e`, lateral stresses zero, no shear strain.
pub fn uniaxial_controls(e: f64) -> [Control; 6] {
    [
        Control::Strain(e),
        Control::Stress(0.0),
        Control::Stress(0.0),
        Control::Strain(0.0),
        Control::Strain(0.0),
        Control::Strain(0.0),
    ]
}

impl MaterialPoint<'_> {}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Solves the small dense Newton system `a x = b` (LU with partial pivoting); a singular system
/// (a fully open crack in every free direction) gives no step.
fn solve(a: Vec<Vec<f64>>, b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    let matrix = nalgebra::DMatrix::from_fn(n, n, |i, j| a[i][j]);
    matrix
        .lu()
        .solve(&nalgebra::DVector::from_vec(b))
        .map_or_else(|| vec![0.0; n], |x| x.as_slice().to_vec())
}

/// A monotonic list of strains from `0` to `end` in `steps` equal increments (the first strain is
/// `end / steps`).
pub fn ramp(end: f64, steps: usize) -> Vec<f64> {
    (1..=steps).map(|i| end * i as f64 / steps as f64).collect()
}
