//! Failure handling: bad input and unstable runs stop with a report that names the entity and
//! the numbers, never with NaN, and the output computed before the stop is on disk.

mod common;

use common::*;
use impact_solver::dynamics::{ExplicitSettings, ExplicitSolver, OutputSettings};
use impact_solver::material::MaterialModel;
use impact_solver::model::Model;
use impact_solver::output::HistoryTable;
use impact_solver::SolverError;

#[test]
fn a_time_step_above_the_stable_limit_is_refused_with_both_numbers() {
    let p = pushed_column();
    let (dt_cr, _) = p.model.critical_time_step();
    let mut settings = ExplicitSettings::new(1e-3);
    settings.time_step = Some(1.2 * dt_cr);
    let err = ExplicitSolver::new(&p, settings, OutputSettings::default())
        .err()
        .expect("must refuse");
    let msg = err.to_string();
    assert!(matches!(err, SolverError::TimeStepAboveStable { .. }));
    assert!(msg.contains(&format!("{:.6e}", 1.2 * dt_cr)), "{msg}");
    assert!(msg.contains(&format!("{dt_cr:.6e}")), "{msg}");
    assert!(
        msg.contains("allow_unstable_time_step"),
        "the message names the fix: {msg}"
    );
}

#[test]
fn an_unstable_run_stops_with_a_report_and_writes_its_output() {
    let p = pushed_column();
    let (dt_cr, _) = p.model.critical_time_step();
    let mut settings = ExplicitSettings::new(2e-3);
    settings.time_step = Some(2.0 * dt_cr);
    settings.allow_unstable_time_step = true;
    settings.history_interval = Some(0.0);
    let dir = std::env::temp_dir().join(format!("impact-unstable-{}", std::process::id()));
    let output = OutputSettings {
        dir: Some(dir.clone()),
        stem: "column".into(),
        fields: true,
    };
    let mut solver = ExplicitSolver::new(&p, settings, output).unwrap();
    let err = solver
        .run(&mut |_| {})
        .expect_err("a step of twice the limit must blow up");
    let SolverError::Unstable(report) = &err else {
        panic!("expected an instability report, got {err}")
    };
    assert!(report.step > 0 && report.time > 0.0);
    assert!(report.element.is_some());
    for x in [
        report.kinetic,
        report.internal_work,
        report.external_work,
        report.energy_error,
    ] {
        assert!(
            x.is_finite(),
            "the report holds a non-finite energy: {report:?}"
        );
    }
    let msg = err.to_string();
    assert!(msg.contains("step") && msg.contains("element"), "{msg}");
    // The history up to the stop is written and free of NaN.
    let history_path = dir.join("column_history.csv");
    assert!(report.written.contains(&history_path));
    let history = HistoryTable::read_csv(&history_path).unwrap();
    assert!(history.rows().len() >= report.step.min(10));
    assert!(
        history.rows().iter().flatten().all(|x| x.is_finite()),
        "NaN in the written history"
    );
    assert!(dir.join("column.pvd").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_inverted_element_in_the_input_mesh_is_refused_with_its_id() {
    let mut mesh = box_body([1.0, 1.0, 1.0], [2, 2, 2], 0.0, 0);
    mesh.tets[13].swap(0, 1);
    let err = Model::new(vec![(
        "slab".into(),
        mesh,
        MaterialModel::LinearElastic(STEEL),
    )])
    .unwrap_err();
    match &err {
        SolverError::InvertedElement {
            mesh,
            element,
            volume,
            ..
        } => {
            assert_eq!(mesh, "slab");
            assert_eq!(*element, 13);
            assert!(*volume < 0.0);
        }
        other => panic!("expected InvertedElement, got {other}"),
    }
    assert!(err.to_string().contains("element 13"));
}

#[test]
fn a_degenerate_element_is_refused_with_its_id() {
    let mut mesh = box_body([1.0, 1.0, 1.0], [1, 1, 1], 0.0, 0);
    // Flatten node 7 (the far corner) almost onto the plane of three others of element 0.
    let t = mesh.tets[0];
    let (a, b, c) = (
        mesh.nodes[t[0] as usize],
        mesh.nodes[t[1] as usize],
        mesh.nodes[t[2] as usize],
    );
    mesh.nodes[t[3] as usize] = (a + b + c) / 3.0 + (b - a).cross(&(c - a)).normalize() * 1e-9;
    let err = Model::new(vec![(
        "sliver".into(),
        mesh,
        MaterialModel::LinearElastic(STEEL),
    )])
    .unwrap_err();
    assert!(
        matches!(
            err,
            SolverError::DegenerateElement { element: 0, .. } | SolverError::InvertedElement { .. }
        ),
        "{err}"
    );
}

#[test]
fn invalid_material_constants_are_refused() {
    let mut bad = STEEL;
    bad.density = -1.0;
    let err = Model::new(vec![(
        "b".into(),
        box_body([1.0; 3], [1, 1, 1], 0.0, 0),
        MaterialModel::LinearElastic(bad),
    )])
    .unwrap_err();
    assert!(
        err.to_string().contains("density must be positive"),
        "{err}"
    );
}

/// The unstable run above on ranks that keep their own elements' connectivity only: each looks
/// for the most strained element among its own, and together they name the one-process run's.
#[test]
fn ranks_keeping_their_own_elements_name_the_one_process_runs_most_strained_element() {
    use impact_solver::distributed::ThreadGroup;
    let unstable = || {
        let p = pushed_column();
        let (dt_cr, _) = p.model.critical_time_step();
        let mut settings = ExplicitSettings::new(2e-3);
        settings.time_step = Some(2.0 * dt_cr);
        settings.allow_unstable_time_step = true;
        (p, settings)
    };
    let element = |err: SolverError| match err {
        SolverError::Unstable(report) => report.element,
        other => panic!("expected an instability report, got {other}"),
    };
    let (p, settings) = unstable();
    let mut solver = ExplicitSolver::new(&p, settings, OutputSettings::default()).unwrap();
    let alone = element(solver.run(&mut |_| {}).expect_err("it blows up"));
    assert!(alone.is_some());
    for ranks in [2, 3] {
        let group = ThreadGroup::new(ranks);
        let named: Vec<Option<usize>> = std::thread::scope(|s| {
            let handles: Vec<_> = group
                .iter()
                .map(|comm| {
                    s.spawn(move || {
                        let (mut p, settings) = unstable();
                        let mut solver = ExplicitSolver::new_rank_keeping_own_elements(
                            &mut p,
                            settings,
                            OutputSettings::default(),
                            comm,
                        )
                        .unwrap();
                        assert_eq!(
                            Some(solver.problem().model.tets.stored_range()),
                            solver.rank_elements(),
                            "a rank keeps its own elements' connectivity"
                        );
                        element(solver.run(&mut |_| {}).expect_err("it blows up"))
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        assert_eq!(named, vec![alone; ranks], "{ranks} ranks");
    }
}
