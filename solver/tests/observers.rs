//! A run shows its output to observers as it goes: a caller's own observer sees every history row
//! the moment it is due, every field frame it asks for, and can halt the run at the end of a step,
//! whose output is then on disk up to that step.

mod common;

use common::*;
use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::output::{FieldFrame, Halt, HistoryTable, RunObserver};
use impact_solver::SolverError;

type Result<T> = std::result::Result<T, SolverError>;

/// Counts what it is shown and halts the run after `halt_after` rows.
#[derive(Default)]
struct Watcher {
    columns: usize,
    rows: Vec<Vec<f64>>,
    frames: Vec<f64>,
    halt_after: Option<usize>,
    finished: bool,
}

impl RunObserver for Watcher {
    fn history_columns(&mut self, columns: &[String]) -> Result<()> {
        self.columns = columns.len();
        Ok(())
    }

    fn history_row(&mut self, row: &[f64]) -> Result<()> {
        self.rows.push(row.to_vec());
        Ok(())
    }

    fn wants_fields(&self) -> bool {
        true
    }

    fn field_frame(&mut self, frame: &FieldFrame) -> Result<Option<std::path::PathBuf>> {
        self.frames.push(frame.time);
        Ok(None)
    }

    fn poll(&mut self, _progress: Option<f64>) -> Option<Halt> {
        self.halt_after
            .filter(|&n| self.rows.len() >= n)
            .map(|_| Halt::Interrupted)
    }

    fn finish(&mut self) -> Result<Vec<std::path::PathBuf>> {
        self.finished = true;
        Ok(Vec::new())
    }
}

fn settings() -> ExplicitSettings {
    let mut settings = ExplicitSettings::new(1e-4);
    settings.history_interval = Some(1e-5);
    settings.field_interval = Some(2.5e-5);
    settings
}

#[test]
fn an_observer_sees_every_row_and_frame_of_the_run() {
    let p = pushed_column();
    let mut solver = ExplicitSolver::new(&p, settings(), OutputSettings::default()).unwrap();
    let mut watcher = Watcher::default();
    let summary = solver.run_with(&mut [&mut watcher]).unwrap();
    assert_eq!(watcher.columns, summary.history.columns().len());
    assert_eq!(watcher.rows, summary.history.rows());
    assert!(watcher.rows.len() >= 11, "{} rows", watcher.rows.len());
    // Frames at 0, 25, 50, 75 and 100 us.
    assert_eq!(watcher.frames.len(), 5, "{:?}", watcher.frames);
    assert_eq!(watcher.frames[0], 0.0);
    assert!((watcher.frames[4] - 1e-4).abs() < summary.time_step);
    assert!(watcher.finished);
}

#[test]
fn an_observer_halts_the_run_and_the_history_file_holds_every_row_so_far() {
    let p = pushed_column();
    let dir = std::env::temp_dir().join(format!("impact-observers-{}", std::process::id()));
    let output = OutputSettings {
        dir: Some(dir.clone()),
        stem: "bar".into(),
        fields: false,
    };
    let mut solver = ExplicitSolver::new(&p, settings(), output).unwrap();
    let mut files = solver.output_observers().unwrap();
    let mut watcher = Watcher {
        halt_after: Some(4),
        ..Watcher::default()
    };
    let mut observers: Vec<&mut dyn RunObserver> = files
        .iter_mut()
        .map(|o| &mut **o as &mut dyn RunObserver)
        .collect();
    observers.push(&mut watcher);
    let err = solver
        .run_with(&mut observers)
        .expect_err("the watcher halts the run");
    assert!(matches!(err, SolverError::Interrupted { .. }), "{err}");
    drop(observers);
    assert!(watcher.finished);
    let written = HistoryTable::read_csv(&dir.join("bar_history.csv")).unwrap();
    assert_eq!(written.rows(), &watcher.rows[..]);
    assert_eq!(written.rows().len(), 4);
    std::fs::remove_dir_all(&dir).unwrap();
}
