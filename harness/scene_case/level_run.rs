//! Running the levels of a scene case: each level's scene built and executed once, as one
//! process, as one rank of an `mpirun` world, or as `N` rank threads of this process.

use std::path::Path;
use std::time::Instant;

use impact_solver::analysis::{execute, ExecuteOptions, Execution};
use impact_solver::distributed::{Communicator, ThreadGroup};
use impact_solver::dynamics::restore_whole_problem;
use impact_solver::problem::Problem;
use impact_solver::scene::{build_problem_on_rank, Scene};
use impact_solver::SolverError;

use crate::case_kind::RunOptions;
use crate::catalogue::{CaseSpec, Variant};
use crate::results::file_safe;

/// What a level's run gives: its problem and run, or why it failed.
pub(super) type LevelOutcome = Result<(Problem, Execution), SolverError>;

/// One solver run of a case (one sweep level).
pub(super) struct LevelRun {
    /// The sweep's parameter at this level (1 without a sweep).
    pub(super) parameter: f64,
    /// Wall time of the level (s).
    pub(super) wall_s: f64,
    /// The problem and its run, or why it failed.
    pub(super) outcome: LevelOutcome,
}

/// What every level of one case under one variant runs with.
pub(super) struct LevelRunner<'a> {
    /// The case.
    pub(super) spec: &'a CaseSpec,
    /// The variant run, if any.
    pub(super) variant: Option<&'a Variant>,
    /// The run's options (time limit, stop flag).
    pub(super) options: &'a RunOptions,
    /// The `mpirun` world this process is a rank of, if any.
    pub(super) world: Option<&'a dyn Communicator>,
    /// Where the levels write their files (none: in memory).
    pub(super) case_dir: Option<&'a Path>,
    /// The case's log.
    pub(super) sink: &'a (dyn Fn(&str) + Sync),
    /// Number of levels (it names the files, [`stem_of`]).
    pub(super) levels: usize,
}

impl LevelRunner<'_> {
    /// Runs level `i`, whose scene is `scene` at the sweep's `parameter`: over the variant's
    /// ranks where it asks for more than one (the `mpirun` world this process belongs to, or
    /// rank threads of this process), once otherwise.
    pub(super) fn run(&self, i: usize, parameter: f64, scene: &Scene) -> LevelRun {
        let t0 = Instant::now();
        let stem = stem_of(self.variant, i, self.levels);
        let run_as = |ranks: Option<&dyn Communicator>| self.execute(scene, &stem, ranks);
        let world = self.world;
        let outcome = match self.variant.and_then(|v| v.ranks).filter(|&n| n > 1) {
            Some(n) if world.is_some_and(|w| w.size() != n) => Err(SolverError::InvalidScene {
                entity: "ranks".into(),
                message: format!(
                    "the variant asks for {n} ranks, but {} were started",
                    world.map_or(1, |w| w.size())
                ),
            }),
            Some(_) if world.is_some() => run_as(world),
            Some(n) => on_rank_threads(n, &run_as),
            None => run_as(None),
        };
        LevelRun {
            parameter,
            wall_s: t0.elapsed().as_secs_f64(),
            outcome,
        }
    }

    /// Builds the problem of `scene` and executes its analysis as one of `ranks` (or alone),
    /// writing files under `stem`.
    fn execute(&self, scene: &Scene, stem: &str, ranks: Option<&dyn Communicator>) -> LevelOutcome {
        build_problem_on_rank(scene, ranks.map(|c| (c.rank(), c.size()))).and_then(|mut problem| {
            let opts = ExecuteOptions {
                out: self.case_dir,
                stem,
                final_state: true,
                fields: false,
                time_limit_s: Some(self.spec.time_limit_s.unwrap_or(self.options.time_limit_s)),
                stop: self.options.stop.clone(),
                ranks,
                // Rank 0 of threaded ranks speaks for the run: every rank would log the
                // same lines.
                log: if ranks.is_none_or(|c| c.rank() == 0) {
                    self.sink
                } else {
                    &|_| {}
                },
            };
            // The measures read the whole problem: every rank gathers back what its run kept
            // to its own part (nothing where it kept all), whatever the run's outcome (the
            // gather is collective).
            let run = execute(&mut problem, &scene.analysis, &opts, &mut |_| {});
            if let Some(comm) = ranks {
                restore_whole_problem(&mut problem, comm);
            }
            run.map(|run| (problem, run))
        })
    }
}

/// Runs `run_as` on `n` rank threads of this process; rank 0's outcome is the run's (every rank
/// holds the same nodal history, and rank 0 alone writes files).
///
/// Each rank thread gets a one-thread pool of its own: its parallel loops must not wait for the
/// catalogue's shared pool, whose workers another case may hold for its whole run while this
/// rank's partner waits at a barrier (the 2-rank solver-agreement case starved at step 0 behind
/// the nail run for 900 s).
fn on_rank_threads(
    n: usize,
    run_as: &(dyn Fn(Option<&dyn Communicator>) -> LevelOutcome + Sync),
) -> LevelOutcome {
    let group = ThreadGroup::new(n);
    std::thread::scope(|s| {
        let ranks: Vec<_> = group
            .iter()
            .map(|comm| {
                s.spawn(|| rank_pool()?.install(|| run_as(Some(comm as &dyn Communicator))))
            })
            .collect();
        let mut outcomes = ranks.into_iter().map(|h| {
            h.join().unwrap_or_else(|_| {
                Err(SolverError::InvalidScene {
                    entity: "ranks".into(),
                    message: "a rank of the distributed run panicked".into(),
                })
            })
        });
        let first = outcomes.next().expect("at least two ranks");
        // The others must end too; their outcome is rank 0's.
        outcomes.for_each(drop);
        first
    })
}

/// The pool a rank thread of a threaded distributed run computes in: one thread, its own, so that
/// no rank waits on workers that other cases hold.
fn rank_pool() -> Result<rayon::ThreadPool, SolverError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| SolverError::InvalidScene {
            entity: "ranks".into(),
            message: format!("cannot start a rank's thread pool: {e}"),
        })
}

/// The stem of the output files of level `i` of `levels` under `variant`
/// (`<stem>_history.csv`, ...): `run` for a case without a sweep, `level<i>` otherwise, each
/// after the variant's name ([`file_safe`]) when the case has variants. The variants of a case
/// share its folder and may run at the same time: without their names they wrote one file.
pub(super) fn stem_of(variant: Option<&Variant>, i: usize, levels: usize) -> String {
    let level = if levels > 1 {
        format!("level{i}")
    } else {
        "run".to_string()
    };
    match variant {
        Some(v) => format!("{}_{level}", file_safe(&v.name)),
        None => level,
    }
}

#[cfg(test)]
mod tests {
    use super::stem_of;
    use crate::catalogue::Variant;

    fn variant(name: &str) -> Variant {
        Variant {
            name: name.into(),
            analysis: None,
            contact_solver: None,
            ranks: None,
            strength_seed: None,
        }
    }

    /// Each variant of a case writes files of its own; a case without variants keeps `run` and
    /// `level<i>`.
    #[test]
    fn variants_of_a_case_write_files_of_their_own() {
        assert_eq!(stem_of(None, 0, 1), "run");
        assert_eq!(stem_of(None, 2, 3), "level2");
        let (a, b) = (variant("gauss-seidel/thesis"), variant("conic/coulomb"));
        assert_eq!(stem_of(Some(&a), 0, 1), "gauss-seidel_thesis_run");
        assert_eq!(stem_of(Some(&b), 1, 2), "conic_coulomb_level1");
        assert_ne!(stem_of(Some(&a), 0, 1), stem_of(Some(&b), 0, 1));
    }
}
