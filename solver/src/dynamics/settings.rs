//! What an explicit run is given and what it reports: its settings (FORMULATION section 2),
//! output settings, and the summary with the contact totals and the time of each phase.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::EnergyLedger;
use crate::output::history::HistoryTable;
use crate::output::Snapshot;

/// Settings of an explicit run. Defaults follow FORMULATION section 2.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExplicitSettings {
    /// Simulated time (s).
    pub end_time: f64,
    /// Fixed time step (s); `None` takes `safety * dt_cr`.
    #[serde(default)]
    pub time_step: Option<f64>,
    /// Fraction of the critical step used when `time_step` is not given (default 0.8: see
    /// the doc comment of `default_safety` in this file).
    #[serde(default = "default_safety")]
    pub safety: f64,
    /// Run even if `time_step` exceeds the stable estimate (stability sweeps do).
    #[serde(default)]
    pub allow_unstable_time_step: bool,
    /// Mass-proportional damping coefficient `a` of `C = a M` (1/s).
    #[serde(default)]
    pub damping: f64,
    /// Stop after this many steps even if `end_time` is not reached.
    #[serde(default)]
    pub max_steps: Option<usize>,
    /// End the run, before `end_time`, at the first history row where a column reaches a level
    /// (the nail's velocity reaching zero: it has stopped); `None` runs to `end_time`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop_when: Option<super::StopWhen>,
    /// Time between history records (s); `None` records about 500 instants.
    #[serde(default)]
    pub history_interval: Option<f64>,
    /// Time between field frames (s); `None` writes the first and the last state only.
    #[serde(default)]
    pub field_interval: Option<f64>,
    /// Time between displacement snapshots kept in memory for the caller (crack growth, failure
    /// modes); `None` keeps none. Cheaper than field frames: nothing is written or derived.
    #[serde(default)]
    pub snapshot_interval: Option<f64>,
    /// A shorter time between snapshots up to a time (s), for what changes fast early in a run
    /// (a crack's initiation and first growth in a drop test); after `until`, and without it,
    /// `snapshot_interval`. Needs `snapshot_interval`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub snapshot_refined: Option<RefinedSnapshots>,
    /// The run is declared unstable when the energy balance error exceeds this fraction of the
    /// largest energy scale seen so far.
    #[serde(default = "default_energy_tolerance")]
    pub instability_energy_tolerance: f64,
    /// Mesh stability check (4.35): steps where a node moves more than `eta` times the smallest
    /// altitude of its elements are counted.
    #[serde(default = "default_eta")]
    pub mesh_stability_eta: f64,
    /// How often the run writes a checkpoint to resume from (`impact-vv scene --resume`);
    /// `None`: never (the command line's `--checkpoint-every` may still ask for them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checkpoint: Option<super::CheckpointEvery>,
}

/// The default safety, 0.8. The estimate `dt_cr` (smallest altitude over the wave speed,
/// thesis (4.33)) is not a bound: the exact limit of Kuhn meshes of box cells up to 10:1 is
/// 0.868 of it on flat cells, 0.93 to 0.95 on cubic and long ones (docs/stable-time-step.md,
/// `solver/tests/stable_step_aspect.rs`), so the 0.9 of explicit codes' habit is unstable on
/// flat cells, and 0.8 keeps 8 % of margin on all of them. Meshes of near-cubic cells may set
/// 0.9 (the catalogue's beams do, each measured stable).
fn default_safety() -> f64 {
    0.8
}
fn default_energy_tolerance() -> f64 {
    0.05
}
fn default_eta() -> f64 {
    0.1
}

impl ExplicitSettings {
    /// Settings for a run to `end_time` (s) with every other setting at its default.
    pub fn new(end_time: f64) -> Self {
        Self {
            end_time,
            time_step: None,
            safety: default_safety(),
            allow_unstable_time_step: false,
            damping: 0.0,
            max_steps: None,
            stop_when: None,
            history_interval: None,
            field_interval: None,
            snapshot_interval: None,
            snapshot_refined: None,
            instability_energy_tolerance: default_energy_tolerance(),
            mesh_stability_eta: default_eta(),
            checkpoint: None,
        }
    }
}

/// The most steps an explicit run may take without `max_steps`: at a microsecond a step on the
/// smallest mesh, some 20 minutes. More comes from an `end_time` or a mesh far off what the
/// scene meant (`end_time: 1e300`), and would run for ever.
pub const MAX_STEPS: f64 = 1.0e9;

impl ExplicitSettings {
    /// Checks every setting's range, naming it under `key` (`analysis.explicit` or
    /// `analysis.release.explicit`): times and intervals positive and finite, `safety` in
    /// `(0, 1]` unless `allow_unstable_time_step` (above 1 the step exceeds the stable estimate,
    /// which only a stability sweep asks for), intervals, damping and tolerances finite and not
    /// negative.
    pub fn validate(&self, key: &str) -> crate::error::Result<()> {
        let fail = |name: &str, message: String| crate::error::SolverError::InvalidScene {
            entity: format!("{key}.{name}"),
            message,
        };
        let positive = |name: &str, value: f64, unit: &str| {
            if value > 0.0 && value.is_finite() {
                Ok(())
            } else {
                Err(fail(
                    name,
                    format!("must be positive and finite ({unit}), got {value}"),
                ))
            }
        };
        if self.max_steps.is_none() || self.end_time != 0.0 {
            positive("end_time", self.end_time, "s")?;
        }
        if self.max_steps == Some(0) {
            return Err(fail("max_steps", "must be at least 1".into()));
        }
        if let Some(dt) = self.time_step {
            positive("time_step", dt, "s")?;
        }
        positive("safety", self.safety, "a fraction of the stable step")?;
        if self.safety > 1.0 && !self.allow_unstable_time_step {
            return Err(fail(
                "safety",
                format!(
                    "{} would take a step above the stable estimate, and the run would be                      unstable; use at most 1 (default 0.8), or set `allow_unstable_time_step:                      true` for a stability sweep",
                    self.safety
                ),
            ));
        }
        if !(self.damping >= 0.0 && self.damping.is_finite()) {
            return Err(fail(
                "damping",
                format!(
                    "must be zero or positive and finite (1/s; a negative one feeds energy in),                      got {}",
                    self.damping
                ),
            ));
        }
        for (name, value) in [
            ("history_interval", self.history_interval),
            ("field_interval", self.field_interval),
            ("snapshot_interval", self.snapshot_interval),
            (
                "snapshot_refined.interval",
                self.snapshot_refined.map(|r| r.interval),
            ),
            (
                "snapshot_refined.until",
                self.snapshot_refined.map(|r| r.until),
            ),
        ] {
            // Zero records at every step.
            if let Some(v) = value.filter(|v| !(*v >= 0.0 && v.is_finite())) {
                return Err(fail(
                    name,
                    format!("must be zero (every step) or positive and finite (s), got {v}"),
                ));
            }
        }
        if let Some(stop) = &self.stop_when {
            if !stop.level.is_finite() {
                return Err(fail(
                    "stop_when.level",
                    format!("must be finite, got {}", stop.level),
                ));
            }
        }
        positive(
            "instability_energy_tolerance",
            self.instability_energy_tolerance,
            "a fraction of the energy scale",
        )?;
        positive(
            "mesh_stability_eta",
            self.mesh_stability_eta,
            "a fraction of the altitude",
        )?;
        Ok(())
    }
}

/// Snapshots every `interval` (s) until `until` (s): [`ExplicitSettings::snapshot_refined`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefinedSnapshots {
    /// Time between snapshots before `until` (s).
    pub interval: f64,
    /// The time the refined snapshots end (s).
    pub until: f64,
}

impl ExplicitSettings {
    /// The time between snapshots at time `t`: the refined interval before its `until`,
    /// `snapshot_interval` after; `None` without snapshots.
    pub fn snapshot_interval_at(&self, t: f64) -> Option<f64> {
        let coarse = self.snapshot_interval?;
        Some(match self.snapshot_refined {
            Some(r) if t < r.until => r.interval.min(coarse),
            _ => coarse,
        })
    }
}

/// Where a run writes its output; `dir: None` keeps everything in memory.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OutputSettings {
    /// Folder the files are written to (created if missing); `None` writes no files.
    pub dir: Option<PathBuf>,
    /// File stem: `<stem>_history.csv`, `<stem>.pvd`, `<stem>_00000.vtu`, ...
    pub stem: String,
    /// Write VTU field frames (histories are always kept).
    pub fields: bool,
}

/// The contact solver's record over a run, all pairs and passes together.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactTotals {
    /// Steps in which at least one contact problem was solved.
    pub steps_with_contact: usize,
    /// Contact problems solved (one per pair, pass and step with contacts).
    pub solves: usize,
    /// Solves that stopped at their iteration limit before meeting the tolerance.
    pub not_converged: usize,
    /// Contacts detected but not enforced: no face found for a crossing node, or a normal no
    /// free node can move along (all prescribed).
    pub unresolved: usize,
    /// Gauss-Seidel sweeps or interior-point iterations.
    pub iterations: usize,
}

/// Wall time spent in each phase of the time step over a run (s).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PhaseTimes {
    /// Internal forces and the material update.
    pub internal_forces: f64,
    /// Loads and the central-difference velocity update.
    pub predictor: f64,
    /// Velocities of prescribed components.
    pub prescribed_motion: f64,
    /// Contact detection and resolution.
    pub contact: f64,
    /// Full-step velocity, reactions, the stability check and the energy ledger.
    pub energy_ledger: f64,
    /// History rows, field frames, snapshots and the balance check.
    pub output: f64,
}

impl PhaseTimes {
    /// The phases by name, in step order.
    pub fn named(&self) -> [(&'static str, f64); 6] {
        [
            ("internal forces", self.internal_forces),
            ("predictor", self.predictor),
            ("prescribed motion", self.prescribed_motion),
            ("contact", self.contact),
            ("energy ledger", self.energy_ledger),
            ("output", self.output),
        ]
    }

    /// One line: each phase's time and share of their sum.
    pub fn line(&self) -> String {
        let total: f64 = self.named().iter().map(|(_, t)| t).sum();
        let parts: Vec<String> = self
            .named()
            .iter()
            .map(|(name, t)| {
                format!(
                    "{name} {t:.3} s ({:.0} %)",
                    if total > 0.0 { 100.0 * t / total } else { 0.0 }
                )
            })
            .collect();
        parts.join(", ")
    }
}

/// What a completed run reports.
#[derive(Debug, Clone)]
pub struct RunSummary {
    /// Time steps taken.
    pub steps: usize,
    /// Simulated time reached (s).
    pub time: f64,
    /// The time step used (s).
    pub time_step: f64,
    /// Stable limit of the central-difference scheme: smallest altitude over dilatational wave
    /// speed (s, FORMULATION section 2).
    pub critical_time_step: f64,
    /// Index (over the model's elements) of the element that sets `critical_time_step`.
    pub critical_element: usize,
    /// Wall-clock time of the run (s of real time).
    pub wall_seconds: f64,
    /// Wall time spent in the contact phase (detection and resolution), within `wall_seconds`.
    pub contact_seconds: f64,
    /// Wall time of each phase of the step, within `wall_seconds`.
    pub phase_seconds: PhaseTimes,
    /// How the contact solver fared, summed over the run.
    pub contact_totals: ContactTotals,
    /// The energy ledger at the end of the run (J): kinetic, internal, external work,
    /// dissipation.
    pub energies: EnergyLedger,
    /// Largest |balance error| over the run divided by the largest energy scale of the run.
    pub max_relative_energy_error: f64,
    /// Steps in which some node moved more than `eta` times its smallest element altitude.
    pub mesh_stability_flags: usize,
    /// The history rows kept in memory (time, energies, probes, reactions).
    pub history: HistoryTable,
    /// Displacements at every `snapshot_interval` (and at the end), when one is set.
    pub snapshots: Vec<Snapshot>,
    /// Every file the observers wrote, in the order written.
    pub written: Vec<PathBuf>,
    /// The time of the history row at which the run's `stop_when` column reached its level
    /// (the run ended there); `None` for a run to its end time.
    pub stopped_when_at: Option<f64>,
}
