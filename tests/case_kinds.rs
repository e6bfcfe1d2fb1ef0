//! Reading case files of every kind through the registry: the two passes, the errors that name
//! the key to change, and a `contact_problems` case run and judged end to end.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

use impact_vv::case_file::load_case as load;
use impact_vv::case_kind::{LoadedCase, RunOptions};
use impact_vv::contact_compare::Comparison;
use impact_vv::registry::KINDS;
use impact_vv::results::Status;

fn load_case(path: &std::path::Path) -> Result<LoadedCase, impact_vv::case_file::CatalogueError> {
    load(path, &KINDS)
}

fn run(case: &LoadedCase) -> impact_vv::results::CaseResult {
    let options = RunOptions {
        output_dir: None,
        time_limit_s: 1.0,
        parallel: false,
        stop: None,
        verbose: false,
    };
    case.kind.run(case, None, &options)
}

/// A case file written into a scratch folder of its own, removed when the value is dropped; it
/// reads as the file's path.
struct CaseFile {
    _dir: tempfile::TempDir,
    path: std::path::PathBuf,
}

impl std::ops::Deref for CaseFile {
    type Target = std::path::Path;
    fn deref(&self) -> &std::path::Path {
        &self.path
    }
}

fn write_case(name: &str, body: &str) -> CaseFile {
    let dir = tempfile::Builder::new()
        .prefix(&format!("impact-vv-case-kinds-{name}-"))
        .tempdir()
        .unwrap();
    let path = dir.path().join("case.yaml");
    std::fs::write(&path, body).unwrap();
    CaseFile { _dir: dir, path }
}

const HEAD: &str = "id: x\ndescription: d\ntier: nightly\n";

const METRIC: &str = "metrics:
  - name: gs_error
    measure: { contact_problem_error: { solver: gauss-seidel/exact, problems: [a], tolerance: 1.0e-8 } }
    reference: { analytic: zero }
    tolerance: { at_most: 1.0e-8 }
";

/// Without a kind's key a case runs its scene, so it needs one; with `contact_problems` its
/// block is read strictly (paths from the case's folder, defaults, unknown fields named with
/// their line) and its metrics are checked against what the comparison runs.
#[test]
fn a_case_is_of_one_kind_and_each_kind_reads_its_block_strictly() {
    let none = write_case("none", &format!("{HEAD}{METRIC}"));
    let e = load_case(&none).unwrap_err().to_string();
    assert!(e.contains("case.yaml") && e.contains("no `scene`"), "{e}");

    let ok = write_case(
        "ok",
        &format!("{HEAD}contact_problems: {{ folder: data }}\n{METRIC}"),
    );
    let case = load_case(&ok).unwrap();
    assert_eq!(case.kind.name(), "contact_problems");
    let kind = format!("{:?}", case.kind);
    let folder = format!("{:?}", ok.parent().unwrap().join("data"));
    assert!(kind.contains(&folder), "relative to the case file: {kind}");
    assert!(kind.contains("tolerances: [0.0001, 1e-6, 1e-8]"), "{kind}");

    let bad_tol = write_case(
        "tol",
        &format!("{HEAD}contact_problems: {{ folder: d, tolerances: [1.0e-4] }}\n{METRIC}"),
    );
    let e = load_case(&bad_tol).unwrap_err().to_string();
    assert!(
        e.contains("tolerance 1e-8") && e.contains("gs_error"),
        "{e}"
    );

    let typo = write_case(
        "typo",
        &format!("{HEAD}contact_problems:\n  folder: d\n  time_limit: 3\n{METRIC}"),
    );
    let e = load_case(&typo).unwrap_err().to_string();
    assert!(
        e.contains("unknown field `time_limit`") && e.contains("line 6"),
        "the key and its line in the file: {e}"
    );

    let with_scene = write_case(
        "both",
        &format!(
            "{HEAD}contact_problems: {{ folder: d }}\n\
             scene: {{ name: s, bodies: [], analysis: {{ static: {{}} }} }}\n{METRIC}"
        ),
    );
    let e = load_case(&with_scene).unwrap_err().to_string();
    assert!(e.contains("remove `scene`"), "{e}");

    let two_kinds = write_case(
        "two",
        &format!(
            "{HEAD}contact_problems: {{ folder: d }}\n\
             material_point: {{ material: m.yaml, experiment: uniaxial_tension }}\n{METRIC}"
        ),
    );
    let e = load_case(&two_kinds).unwrap_err().to_string();
    assert!(
        e.contains("`material_point` and `contact_problems`") && e.contains("keep one"),
        "{e}"
    );

    let scene_measure = write_case(
        "measure",
        &format!(
            "{HEAD}contact_problems: {{ folder: d }}\nmetrics:\n  - name: k\n    \
             measure: {{ history_final: {{ column: kinetic }} }}\n    \
             reference: {{ analytic: zero }}\n    tolerance: {{ at_most: 1.0 }}\n"
        ),
    );
    let e = load_case(&scene_measure).unwrap_err().to_string();
    assert!(
        e.contains("metric `k`") && e.contains("contact_problems"),
        "{e}"
    );
}

#[test]
fn a_missing_folder_is_an_error_naming_the_folder_and_the_case_file() {
    let path = write_case(
        "missing",
        &format!("{HEAD}contact_problems: {{ folder: no/such/folder }}\n{METRIC}"),
    );
    let r = run(&load_case(&path).unwrap());
    assert_eq!(r.status, Status::Error);
    let m = r.message.unwrap();
    assert!(
        m.contains("no/such/folder")
            && m.contains(&path.display().to_string())
            && m.contains("references/contact-problems"),
        "{m}"
    );
}

#[test]
fn a_case_on_a_folder_is_judged_and_an_unreadable_file_fails_it() {
    let path = write_case(
        "folder",
        "id: x\ndescription: d\ntier: nightly\n\
         contact_problems: { folder: data, tolerances: [1.0e-8], time_limit_s: 5, solvers: [gauss-seidel/exact] }\n\
         metrics:\n  - name: e\n    measure: { contact_problem_error: { solver: gauss-seidel/exact, tolerance: 1.0e-8 } }\n\
         \x20   reference: { analytic: zero }\n    tolerance: { at_most: 1.0e-8 }\n",
    );
    let data = path.parent().unwrap().join("data");
    std::fs::create_dir_all(&data).unwrap();
    // W = 2 I, q = (-1, 0.1, 0), mu = 0.5: the contact sticks with r = (0.5, -0.05, 0).
    let problem = serde_json::json!({
        "format": "contact-problem/1",
        "dimension": 3,
        "contacts": 1,
        "mu": [0.5],
        "q": [-1.0, 0.1, 0.0],
        "W": { "rows": 3, "cols": 3, "triplets": [[0, 0, 2.0], [1, 1, 2.0], [2, 2, 2.0]] },
    });
    std::fs::write(data.join("one.json"), problem.to_string()).unwrap();
    let case = load_case(&path).unwrap();
    let r = run(&case);
    assert_eq!(r.status, Status::Pass, "{:?}", r.message);
    assert!(r.metrics[0].value <= 1e-8);
    let c: Comparison = r.record(Comparison::KEY).unwrap();
    assert_eq!((c.problems.len(), c.rows.len()), (1, 1));

    std::fs::write(data.join("zz-broken.json"), "[]").unwrap();
    let r = run(&case);
    assert_eq!(r.status, Status::Fail);
    assert!(r.message.unwrap().contains("zz-broken.json"));
    std::fs::remove_dir_all(data).ok();
}

/// A variant run as ranks in threads finishes while every worker of the shared pool is held by
/// other work: each rank computes in a pool of its own. (The ranks' parallel loops once went to
/// the shared pool, where a long case held the workers; the 2-rank run starved at step 0.)
#[test]
fn ranks_in_threads_do_not_wait_for_the_shared_pool() {
    let case = write_case(
        "ranks",
        &format!(
            "{HEAD}scene:
  name: bar
  bodies:
    - name: a
      mesh: {{ box: {{ origin: [0, 0, 0], size: [0.1, 0.1, 0.1], divisions: [2, 2, 2] }} }}
      material: {{ linear_elastic: {{ density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.2 }} }}
      initial_velocity: {{ translation: [1.0, 0, 0] }}
    - name: b
      mesh: {{ box: {{ origin: [0.2, 0, 0], size: [0.1, 0.1, 0.1], divisions: [2, 2, 2] }} }}
      material: {{ linear_elastic: {{ density: 2000, youngs_modulus: 1.0e7, poisson_ratio: 0.2 }} }}
  analysis:
    explicit: {{ end_time: 1.0e-3, history_interval: 1.0e-4 }}
variants:
  - {{ name: 2-ranks, ranks: 2 }}
metrics:
  - name: energy
    measure: energy_balance_error
    reference: {{ analytic: zero }}
    tolerance: {{ at_most: 1.0e-6 }}
"
        ),
    );
    let case = load_case(&case).unwrap();
    let variant = &case.spec.variants[0];

    // Hold every worker of the shared pool until the run is over (or a minute has passed, so
    // that a run that needs them still ends and the assertion below names the failure).
    let release = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let workers = rayon::current_num_threads();
    let held = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(0));
    for _ in 0..workers {
        let (release, held) = (release.clone(), held.clone());
        rayon::spawn(move || {
            held.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
            let t0 = std::time::Instant::now();
            while !release.load(std::sync::atomic::Ordering::SeqCst) && t0.elapsed().as_secs() < 60
            {
                std::thread::sleep(std::time::Duration::from_millis(5));
            }
        });
    }
    while held.load(std::sync::atomic::Ordering::SeqCst) < workers {
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    let options = RunOptions {
        output_dir: None,
        time_limit_s: 120.0,
        parallel: false,
        stop: None,
        verbose: false,
    };
    let t0 = std::time::Instant::now();
    let result = case.kind.run(&case, Some(variant), &options);
    let elapsed = t0.elapsed().as_secs_f64();
    release.store(true, std::sync::atomic::Ordering::SeqCst);
    assert_eq!(result.status, Status::Pass, "{:?}", result.message);
    assert!(
        elapsed < 30.0,
        "the 2-rank run took {elapsed:.1} s while the shared pool was busy: it waited for it"
    );
}
