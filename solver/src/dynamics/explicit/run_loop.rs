//! The step loop of a run with output: history rows, field frames and snapshots as they fall
//! due, the energy-balance stop, progress and halts. A run from start to end is one segment; a
//! run that remeshes ([`crate::remesh::run_remeshing`]) is several, one per mesh, over one set
//! of observers and one [`OutputSchedule`], so its output reads as one run.

use std::time::Instant;

use super::ExplicitSolver;
use crate::dynamics::{RunSummary, StopProgress};
use crate::error::Result;
use crate::output::{HistoryTable, ObserverSet, Recorder, RunObserver, SnapshotView};

/// How a segment of a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentEnd {
    /// The end time (or the step limit) was reached.
    Finished,
    /// The caller's pause condition held after a step: the state is between two steps.
    Paused,
}

/// Where a run's output stands: the next times a history row, a field frame and a snapshot
/// fall due, the energy scale and largest balance error so far, the steps flagged by the mesh
/// stability check, and the steps taken (over every segment).
#[derive(Debug, Clone, Default)]
pub struct OutputSchedule {
    pub(super) next_history: f64,
    pub(super) next_field: f64,
    pub(super) next_snapshot: f64,
    pub(super) max_scale: f64,
    pub(super) max_abs_error: f64,
    pub(super) flags: usize,
    pub(super) steps: usize,
    pub(super) stop: StopProgress,
}

impl OutputSchedule {
    /// The largest balance error over the energy scale so far.
    pub fn max_relative_energy_error(&self) -> f64 {
        if self.max_scale > 0.0 {
            self.max_abs_error / self.max_scale
        } else {
            0.0
        }
    }
}

impl<'p> ExplicitSolver<'p> {
    /// Runs to the end time, showing the history rows, field frames, snapshots and progress to
    /// `observers` as they fall due (the integrator writes nothing itself), and stopping at the
    /// end of a step where one of them asks to halt. The summary holds the history and the
    /// snapshots, and the files the observers wrote.
    pub fn run_with(&mut self, observers: &mut [&mut dyn RunObserver]) -> Result<RunSummary> {
        let started = Instant::now();
        let mut recorder = Recorder::default();
        let mut all: Vec<&mut dyn RunObserver> = observers.iter_mut().map(|o| &mut **o).collect();
        all.push(&mut recorder);
        let mut set = ObserverSet::new(all);
        set.history_columns(&self.history_columns())?;
        let mut schedule = OutputSchedule::default();
        self.run_segment(&mut set, &mut schedule, &mut |_| false)?;
        set.finish()?;
        let written = std::mem::take(&mut set.written);
        drop(set);
        Ok(self.summary(&schedule, started, recorder, written))
    }

    /// The summary of a run that ended with this solver's state.
    pub fn summary(
        &self,
        schedule: &OutputSchedule,
        started: Instant,
        recorder: Recorder,
        written: Vec<std::path::PathBuf>,
    ) -> RunSummary {
        RunSummary {
            steps: schedule.steps.saturating_sub(1),
            time: self.time,
            time_step: self.dt,
            critical_time_step: self.dt_critical,
            critical_element: self.critical_element,
            wall_seconds: started.elapsed().as_secs_f64(),
            contact_seconds: self.phases.contact,
            phase_seconds: self.phases,
            contact_totals: self.contact_totals,
            energies: self.energies,
            max_relative_energy_error: schedule.max_relative_energy_error(),
            mesh_stability_flags: schedule.flags,
            history: recorder
                .history
                .unwrap_or_else(|| HistoryTable::new(Vec::new())),
            snapshots: recorder.snapshots,
            written,
            stopped_when_at: schedule.stop.reached_at(),
        }
    }

    /// Steps to the end time with output through `set` as `schedule` says, and pauses between
    /// two steps where `pause(self)` holds after a step that was not the last. An instability
    /// or a halt writes what the observers hold and returns the error.
    pub fn run_segment(
        &mut self,
        set: &mut ObserverSet,
        schedule: &mut OutputSchedule,
        pause: &mut dyn FnMut(&Self) -> bool,
    ) -> Result<SegmentEnd> {
        let steps = self.planned_steps();
        let history_interval = self
            .settings
            .history_interval
            .unwrap_or(self.settings.end_time / 500.0)
            .max(0.0);
        // Collective output (frames gather the history) needs the same answer on every rank.
        let wants_fields = self.on_any_rank(set.wants_fields());
        let progress_every = (steps / 100).max(1);
        let resumed = self.step_origin > 0;
        let stop_when = match &self.settings.stop_when {
            Some(stop) => Some((stop.clone(), stop.column_index(&self.history_columns())?)),
            None => None,
        };

        // A segment goes on from the step its solver took over at (`restart.rs` restores a
        // solver mid-segment; every other solver starts at its origin, `n = 0`).
        for n in (self.step - self.step_origin)..=steps {
            let mut last = n == steps;
            let first = schedule.steps == 0;
            match self.advance() {
                Ok(moved_too_far) => schedule.flags += moved_too_far as usize,
                Err(reason_element) => return Err(self.stop(reason_element, set)),
            }
            schedule.steps += 1;
            // Energies now describe t_n; check the balance before recording.
            let mut clock = super::Lap::start();
            let e = self.energies;
            schedule.max_scale = schedule.max_scale.max(e.scale());
            let error = e.balance_error();
            schedule.max_abs_error = schedule.max_abs_error.max(error.abs());
            if schedule.steps > 11
                && error.abs() > self.settings.instability_energy_tolerance * schedule.max_scale
            {
                let reason = format!(
                    "energy balance error {:.3e} J exceeds {} of the energy scale {:.3e} J",
                    error, self.settings.instability_energy_tolerance, schedule.max_scale
                );
                let element = self.most_strained_element();
                return Err(self.stop((reason, element), set));
            }
            if first || n == 0 || last || self.time >= schedule.next_history - 1e-9 * self.dt {
                let row = self.history_row(&e);
                set.history_row(&row)?;
                schedule.next_history += history_interval;
                // A row that reaches the stop level makes this step the run's last: its field
                // frame and snapshot are written as at the end time.
                // Rank 0's row is the one written: its answer ends the run on every rank.
                if let Some((stop, column)) = &stop_when {
                    let mine = schedule.stop.reached(stop, row[*column]) && self.rank().0 == 0;
                    if self.on_any_rank(mine) {
                        schedule.stop.end(self.time);
                        last = true;
                    }
                }
            }
            if wants_fields {
                let due = match self.settings.field_interval {
                    Some(_) => self.time >= schedule.next_field - 1e-9 * self.dt,
                    None => first,
                };
                if due || last {
                    self.field_frame(set)?;
                    if let Some(interval) = self.settings.field_interval {
                        schedule.next_field += interval;
                    }
                }
            }
            if let Some(interval) = self.settings.snapshot_interval_at(self.time) {
                if last || self.time >= schedule.next_snapshot - 1e-9 * self.dt {
                    let u = self.whole(&self.u);
                    let crack_opening = self.crack_openings();
                    set.snapshot(&SnapshotView {
                        time: self.time,
                        u: &u,
                        crack_opening: &crack_opening,
                    });
                    schedule.next_snapshot += interval;
                }
            }
            self.phases.output += clock.lap();
            let fraction = (n % progress_every == 0).then(|| {
                if resumed {
                    (self.time / self.settings.end_time).clamp(0.0, 1.0)
                } else {
                    n as f64 / steps.max(1) as f64
                }
            });
            // Every observer sees the last step's progress, but a run whose last step is done
            // completes: there is nothing left to halt (before the observers, a stop flag was
            // not read after the last step either).
            // A halt on one rank (its deadline, a signal) halts them all at this step.
            let halt = set.poll(fraction);
            let halt = if self.on_any_rank(halt.is_some()) {
                Some(halt.unwrap_or(crate::output::Halt::Interrupted))
            } else {
                None
            };
            match halt {
                Some(halt) if !last => return Err(self.halt(halt, set)),
                _ if last => break,
                _ => {}
            }
            self.finish_step();
            if pause(self) {
                return Ok(SegmentEnd::Paused);
            }
        }
        Ok(SegmentEnd::Finished)
    }
}
