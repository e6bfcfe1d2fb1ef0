//! The command line stopped from outside: a scene or a catalogue run interrupted by SIGINT
//! writes what it has, and one killed outright leaves what it had streamed.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod cli_common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use cli_common::*;

/// The confined column of `cases/examples/` run for 10 s of simulated time (millions of steps:
/// it runs until stopped), written into `dir`.
fn endless_column(dir: &Path) -> PathBuf {
    let scene = std::fs::read_to_string(repo().join("cases/examples/confined-column.yaml"))
        .unwrap()
        .replace("end_time: 3.0e-4", "end_time: 10.0");
    assert!(scene.contains("end_time: 10.0"));
    let file = dir.join("long-column.yaml");
    std::fs::write(&file, scene).unwrap();
    file
}

/// A catalogue folder in `dir` of the confined-wave case under each id, in order; the case
/// marked `endless` runs 40 s of simulated time (hours of steps).
fn catalogue_of(dir: &Path, cases: &[(&str, bool)]) -> PathBuf {
    let folder = dir.join("cases");
    let wave = confined_wave();
    for (id, endless) in cases {
        let text = if *endless {
            wave.replace("end_time: 2.36e-4", "end_time: 40.0")
        } else {
            wave.clone()
        };
        let sub = folder.join(id.replace('/', "_"));
        std::fs::create_dir_all(&sub).unwrap();
        std::fs::write(
            sub.join("case.yaml"),
            text.replace("id: elastic/confined-wave", &format!("id: {id}")),
        )
        .unwrap();
    }
    folder
}

/// `impact-vv` with `args` started in the background, its output captured.
fn spawn_impact_vv(args: &[&str]) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_impact-vv"))
        .args(args)
        .current_dir(repo())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap()
}

/// A serial run of the quick tier of `cases`, reporting into `reports`, started in the
/// background.
fn spawn_serial_run(cases: &Path, reports: &Path) -> std::process::Child {
    spawn_impact_vv(&[
        "run",
        "--tier",
        "quick",
        "--serial",
        "--catalogue",
        cases.to_str().unwrap(),
        "--reports",
        reports.to_str().unwrap(),
    ])
}

/// Sends SIGINT to `child` after `seconds` and waits for it.
/// `impact-vv scene FILE --out OUT`, started in the background.
fn spawn_scene(file: &Path, out: &Path) -> std::process::Child {
    spawn_impact_vv(&[
        "scene",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
}

fn interrupt_after(child: std::process::Child, seconds: u64) -> Output {
    std::thread::sleep(std::time::Duration::from_secs(seconds));
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    child.wait_with_output().unwrap()
}

/// Kills `child` outright (SIGKILL: no handler runs) after `seconds`.
fn kill_after(mut child: std::process::Child, seconds: u64) {
    std::thread::sleep(std::time::Duration::from_secs(seconds));
    child.kill().unwrap();
    child.wait().unwrap();
}

/// The data rows of a history CSV, each checked to be whole; column 1 is the step.
fn history_rows(path: &Path) -> Vec<Vec<f64>> {
    let history = std::fs::read_to_string(path).unwrap();
    let mut lines = history.lines();
    let width = lines.next().expect("a header").split(',').count();
    lines
        .enumerate()
        .map(|(k, l)| {
            let row: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            assert_eq!(row.len(), width, "row {k} is cut");
            row
        })
        .collect()
}

/// A scene run stopped by SIGINT after a few seconds exits with status 130 and leaves the history
/// CSV with every record up to the stop (consecutive steps, nothing after the last) and a PVD
/// collection whose every frame file exists.
#[test]
fn a_scene_run_interrupted_by_sigint_writes_what_it_has() {
    let dir = temp_dir("sigint");
    let file = endless_column(&dir);
    let out = dir.join("out");
    let child = spawn_scene(&file, &out);
    let output = interrupt_after(child, 3);
    assert_eq!(output.status.code(), Some(130), "{}", text(&output));
    assert!(text(&output).contains("interrupted"), "{}", text(&output));
    let rows = history_rows(&out.join("confined-column_history.csv"));
    assert!(rows.len() > 10, "{} rows", rows.len());
    // Every record from the start, one per step (history_interval 1e-6 s is below the time step
    // here), none missing.
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(r[1], k as f64, "row {k}");
    }
    let pvd = std::fs::read_to_string(out.join("confined-column.pvd")).unwrap();
    let frames: Vec<&str> = pvd
        .split("file=\"")
        .skip(1)
        .map(|s| s.split('"').next().unwrap())
        .collect();
    assert!(!frames.is_empty(), "{pvd}");
    for f in frames {
        assert!(out.join(f).is_file(), "{f} listed in the PVD is missing");
    }
}

/// A catalogue run sent SIGINT while its second case runs: exit status 130; `results.json` and
/// `index.html` are written; the first case is judged and is the only one in the history; the
/// second (stopped mid-run) and the third (never started) are `interrupted`.
#[test]
fn a_catalogue_run_interrupted_by_sigint_reports_the_finished_cases() {
    let dir = temp_dir("sigint-run");
    let cases = catalogue_of(
        &dir,
        &[("a/first", false), ("b/second", true), ("c/third", false)],
    );
    let reports = dir.join("reports");
    let output = interrupt_after(spawn_serial_run(&cases, &reports), 4);
    assert_eq!(output.status.code(), Some(130), "{}", text(&output));
    let json = results(&reports);
    assert!(only_run_dir(&reports).join("index.html").is_file());
    for case in json["cases"].as_array().unwrap() {
        let expected = if case["id"] == "a/first" {
            "pass"
        } else {
            "interrupted"
        };
        assert_eq!(
            case["status"], expected,
            "{}: {}",
            case["id"], case["message"]
        );
    }
    let history = std::fs::read_to_string(reports.join("history.jsonl")).unwrap();
    let lines: Vec<&str> = history.lines().collect();
    assert!(!lines.is_empty());
    assert!(
        lines.iter().all(|l| l.contains("\"case\":\"a/first\"")),
        "{history}"
    );
}

/// A scene run killed outright (SIGKILL: no handler runs) still leaves its history CSV up to the
/// last flush: the header, and whole rows of consecutive steps from the start.
#[test]
fn a_scene_run_killed_outright_leaves_the_history_written_so_far() {
    let dir = temp_dir("sigkill");
    let file = endless_column(&dir);
    let out = dir.join("out");
    let child = spawn_scene(&file, &out);
    // Past two flush intervals.
    kill_after(child, 5);
    let rows = history_rows(&out.join("confined-column_history.csv"));
    assert!(rows.len() > 10, "{} rows", rows.len());
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(r[1], k as f64, "row {k}");
    }
}

/// A catalogue run killed outright (SIGKILL) while its second case runs leaves `run.json` and the
/// first case's lines in `cases.jsonl`; `impact-vv report` rebuilds `results.json`, the page and
/// the history lines from them, with exactly the cases that finished.
#[test]
fn a_catalogue_run_killed_outright_is_rebuilt_from_its_case_lines() {
    let dir = temp_dir("sigkill-run");
    let cases = catalogue_of(&dir, &[("a/first", false), ("b/second", true)]);
    let reports = dir.join("reports");
    kill_after(spawn_serial_run(&cases, &reports), 4);
    let run = only_run_dir(&reports);
    assert!(!run.join("results.json").exists());
    let out = impact_vv(
        &[
            "report",
            run.to_str().unwrap(),
            "--reports",
            reports.to_str().unwrap(),
        ],
        &[],
    );
    assert!(text(&out).contains("rebuilt"), "{}", text(&out));
    let json = results(&reports);
    let finished = json["cases"].as_array().unwrap();
    assert!(!finished.is_empty());
    assert!(finished
        .iter()
        .all(|c| c["id"] == "a/first" && c["status"] == "pass"));
    assert!(run.join("index.html").is_file());
    let history = std::fs::read_to_string(reports.join("history.jsonl")).unwrap();
    assert_eq!(history.lines().count(), finished.len(), "{history}");
}

/// `count` copies of a frictionless problem that Gauss-Seidel solves slowly, written into
/// `dir/problems`: 100 contacts whose normal components are coupled as a 1-D Laplacian
/// (`W_NN = tridiag(-1, 2, -1)`, condition number about 4e3; tangential diagonal 1),
/// `q_N = -1`. Gauss-Seidel needs tens of thousands of sweeps for 1e-8, so each solve and its
/// timing repeats take a good fraction of a second.
fn slow_contact_problems(dir: &Path, count: usize) -> PathBuf {
    let n = 100;
    let mut triplets = Vec::new();
    for a in 0..n {
        triplets.push(format!("[{0}, {0}, 2.0]", 3 * a));
        triplets.push(format!("[{0}, {0}, 1.0]", 3 * a + 1));
        triplets.push(format!("[{0}, {0}, 1.0]", 3 * a + 2));
        if a + 1 < n {
            triplets.push(format!("[{}, {}, -1.0]", 3 * a, 3 * a + 3));
            triplets.push(format!("[{}, {}, -1.0]", 3 * a + 3, 3 * a));
        }
    }
    let q: Vec<&str> = (0..n).flat_map(|_| ["-1.0", "0.0", "0.0"]).collect();
    let json = format!(
        "{{\"format\": \"contact-problem/1\", \"dimension\": 3, \"contacts\": {n}, \
         \"mu\": [{}], \"q\": [{}], \"W\": {{\"rows\": {m}, \"cols\": {m}, \"triplets\": [{}]}}}}",
        vec!["0.0"; n].join(", "),
        q.join(", "),
        triplets.join(", "),
        m = 3 * n
    );
    let folder = dir.join("problems");
    std::fs::create_dir_all(&folder).unwrap();
    for k in 0..count {
        std::fs::write(folder.join(format!("laplace-{k:03}.json")), &json).unwrap();
    }
    folder
}

/// `contact-compare` sent SIGINT mid-way stops after the solve under way (at most the time
/// limit), writes the solves that finished with a README that says it was interrupted, and
/// exits with status 130, as `scene` and `run` do (findings S6: it used to run to the end and
/// exit 0).
#[test]
fn a_contact_comparison_interrupted_by_sigint_writes_what_it_has() {
    let dir = temp_dir("sigint-compare");
    let problems = slow_contact_problems(&dir, 40);
    let out = dir.join("out");
    let child = spawn_impact_vv(&[
        "contact-compare",
        problems.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--solvers",
        "gauss-seidel/thesis,gauss-seidel/exact",
        "--tolerances",
        "1e-8",
        "--time-limit",
        "2",
    ]);
    let started = std::time::Instant::now();
    let output = interrupt_after(child, 3);
    let seconds = started.elapsed().as_secs_f64();
    assert_eq!(output.status.code(), Some(130), "{}", text(&output));
    assert!(text(&output).contains("interrupted"), "{}", text(&output));
    // The signal at 3 s; then at most one solve of at most 2 s, and the writing.
    assert!(seconds < 10.0, "stopped after {seconds} s");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let rows = json["rows"].as_array().unwrap();
    assert!(
        !rows.is_empty() && rows.len() < 80,
        "{} of 80 solves",
        rows.len()
    );
    // Only the problems that ran are described.
    let problems = json["problems"].as_array().unwrap();
    assert!(problems.len() < 40, "{} problems", problems.len());
    for r in rows {
        assert!(problems.iter().any(|p| p["name"] == r["problem"]), "{r}");
    }
    let readme = std::fs::read_to_string(out.join("README.md")).unwrap();
    assert!(
        readme.contains(&format!(
            "Interrupted by a signal: {} of the 80 solves",
            rows.len()
        )),
        "{readme}"
    );
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), rows.len() + 1);
}

/// A catalogue run that stopped after its first case, its case lines as a kill leaves them
/// (the first whole, the second cut, no `results.json`), is finished by `impact-vv run
/// --resume`: only the two cases that did not finish run, the first keeps its line as it was,
/// and the results, the page and the history hold all three in catalogue order.
#[test]
fn a_stopped_catalogue_run_is_finished_by_resume() {
    let dir = temp_dir("resume-run");
    let cases = catalogue_of(
        &dir,
        &[("a/first", false), ("b/second", false), ("c/third", false)],
    );
    let reports = dir.join("reports");
    let out = spawn_serial_run(&cases, &reports)
        .wait_with_output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out));
    let run = only_run_dir(&reports);
    let log = std::fs::read_to_string(run.join("cases.jsonl")).unwrap();
    let lines: Vec<&str> = log.lines().collect();
    // One line per case and variant (the confined wave has variants).
    let jobs = lines.len();
    assert!(jobs >= 3 && jobs % 3 == 0, "{log}");
    let first: serde_json::Value = serde_json::from_str(lines[0]).unwrap();
    assert_eq!(first["id"], "a/first");
    let cut = &lines[1][..lines[1].len() / 2];
    std::fs::write(run.join("cases.jsonl"), format!("{}\n{cut}", lines[0])).unwrap();
    for gone in ["results.json", "index.html"] {
        std::fs::remove_file(run.join(gone)).unwrap();
    }
    std::fs::remove_file(reports.join("history.jsonl")).unwrap();

    let out = impact_vv(
        &[
            "run",
            "--resume",
            run.to_str().unwrap(),
            "--reports",
            reports.to_str().unwrap(),
        ],
        &[],
    );
    assert!(out.status.success(), "{}", text(&out));
    let announced = format!("1 of {jobs} case runs finished, {} to run", jobs - 1);
    assert!(text(&out).contains(&announced), "{}", text(&out));
    let json = results(&reports);
    let all = json["cases"].as_array().unwrap();
    assert_eq!(all.len(), jobs);
    let ids: Vec<&str> = all.iter().map(|c| c["id"].as_str().unwrap()).collect();
    for (k, id) in ["a/first", "b/second", "c/third"].iter().enumerate() {
        let per_case = jobs / 3;
        assert!(
            ids[k * per_case..(k + 1) * per_case]
                .iter()
                .all(|i| i == id),
            "{ids:?}"
        );
    }
    assert!(all.iter().all(|c| c["status"] == "pass"), "{json}");
    assert_eq!(all[0], first, "the finished case is kept, not run again");
    assert!(run.join("index.html").is_file());
    let history = std::fs::read_to_string(reports.join("history.jsonl")).unwrap();
    assert_eq!(history.lines().count(), jobs, "{history}");
    let log = std::fs::read_to_string(run.join("cases.jsonl")).unwrap();
    assert_eq!(log.lines().count(), jobs, "{log}");
}
