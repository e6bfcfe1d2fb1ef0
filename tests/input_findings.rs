//! Every reproducer of the fuzz campaign's findings (the fuzz campaign's findings) as a
//! regression test: out-of-range numbers, names and sizes stop with exit status 2 and a message
//! that names the key, where they used to panic, run away or give a wrong answer with status 0.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod cli_common;

use std::process::Output;

use cli_common::*;

/// The bar of the findings, pushed at one end: 10 cells of 0.1 x 0.1 x 0.1 m.
const BAR: &str = r#"name: s
bodies:
  - name: bar
    mesh: { box: { origin: [0, 0, 0], size: [1.0, 0.1, 0.1], divisions: [10, 1, 1] } }
    material: { linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 } }
boundary_conditions:
  - { name: push, body: bar, nodes: { plane: { point: [0, 0, 0], normal: [1, 0, 0] } }, motion: { velocity: { components: [x], value: { constant: 1.0 } } } }
analysis:
  explicit: { end_time: 1.0e-4 }
"#;

/// The case of finding P1 without its time limit: a bar of two cells run for 0.1 ms.
const CASE: &str = r#"id: t/limit
description: time limit
tier: quick
scene:
  name: bar
  bodies:
    - name: bar
      mesh: { box: { origin: [0, 0, 0], size: [1, 0.1, 0.1], divisions: [2, 1, 1] } }
      material: { linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 } }
  analysis: { explicit: { end_time: 1.0e-4 } }
metrics:
  - { name: energy_balance_error, measure: energy_balance_error, reference: { analytic: zero }, tolerance: { at_most: 0.5 } }
"#;

/// `impact-vv scene` on `text` written to a scratch folder, with `--out` in it.
fn scene(text: &str) -> (Output, TestDir) {
    let dir = temp_dir("finding");
    let file = dir.join("scene.yaml");
    std::fs::write(&file, text).unwrap();
    let out = dir.join("out");
    let o = impact_vv(
        &[
            "scene",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--no-fields",
        ],
        &[],
    );
    (o, dir)
}

/// `impact-vv run` on the case `text` written to a scratch folder, with `extra` arguments.
fn case(text: &str, extra: &[&str]) -> Output {
    let dir = temp_dir("finding-case");
    let file = dir.join("case.yaml");
    std::fs::write(&file, text).unwrap();
    let reports = dir.join("reports");
    let mut args = vec![
        "run",
        file.to_str().unwrap(),
        "--reports",
        reports.to_str().unwrap(),
    ];
    args.extend(extra);
    impact_vv(&args, &[])
}

/// Exit status 2 (bad input), no panic, and every one of `words` in what was printed.
fn assert_input_error(o: &Output, words: &[&str]) {
    let t = text(o);
    assert!(!t.contains("panicked"), "{t}");
    assert_eq!(o.status.code(), Some(2), "{t}");
    for w in words {
        assert!(t.contains(w), "`{w}` missing from: {t}");
    }
}

/// P1: a time limit that is not a positive finite number is refused where it is read, in a
/// case file and on the command line; a huge one is no limit (it used to panic).
#[test]
fn p1_time_limits_out_of_range_are_refused() {
    for value in ["-1", ".nan", ".inf"] {
        let o = case(&format!("{CASE}time_limit_s: {value}\n"), &[]);
        assert_input_error(&o, &["time_limit_s", "positive, finite"]);
    }
    for value in ["-1", "nan", "inf"] {
        let o = case(CASE, &[&format!("--time-limit={value}")]);
        assert_input_error(&o, &["--time-limit", "positive, finite"]);
    }
    for o in [
        case(&format!("{CASE}time_limit_s: 1e300\n"), &[]),
        case(CASE, &["--time-limit=1e300"]),
    ] {
        assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    }
}

/// P2: a region's name where a body is expected is refused with the advice to name its body.
#[test]
fn p2_a_region_named_as_a_body_is_refused_with_its_parent() {
    let region = r#"name: region-probe
bodies:
  - name: bar
    mesh: { box: { origin: [0, 0, 0], size: [0.2, 0.05, 0.05], divisions: [2, 1, 1] } }
    material: { linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 } }
    regions:
      - name: band
        centroid_box: { min: [0.1, 0, 0], max: [0.2, 0.05, 0.05] }
        material: { linear_elastic: { density: 2300, youngs_modulus: 10.0e9, poisson_ratio: 0.2 } }
analysis: { explicit: { end_time: 1.0e-6 } }
"#;
    for entry in [
        "probes:\n  - { name: p, body: band, nodes: all, quantity: displacement }\n",
        "boundary_conditions:\n  - { name: b, body: band, nodes: boundary, motion: { fixed: [x] } }\n",
        "loads:\n  - { name: l, body: band, nodes: { nodes: [0] }, force_per_node: [1, 0, 0] }\n",
    ] {
        let (o, _dir) = scene(&format!("{region}{entry}"));
        assert_input_error(&o, &["`band` is a material region of body `bar`", "body: bar"]);
    }
}

/// P3: a variant's `ranks` out of 1..=1024 is refused when the case is read, and ranks with an
/// analysis that runs on one rank name the key, not mpirun.
#[test]
fn p3_ranks_out_of_range_are_refused() {
    for n in ["9223372036854775808", "4294967296", "20000", "0"] {
        let o = case(
            &format!("{CASE}variants: [{{ name: r, ranks: {n} }}]\n"),
            &[],
        );
        assert_input_error(&o, &["variant `r` ranks", "1 to 1024"]);
    }
    let static_case = CASE.replace(
        "analysis: { explicit: { end_time: 1.0e-4 } }",
        "analysis: { static: { load_steps: 1 } }",
    );
    let o = case(
        &format!("{static_case}variants: [{{ name: r, ranks: 2 }}]\n"),
        &[],
    );
    assert_input_error(
        &o,
        &["variant `r` ranks", "explicit analysis without remeshing"],
    );
}

/// H1 and A1: `regrowth` below 1 (the runaway), and `min_edge`, `min_volume`, `check_every`
/// and `near_tip.steps` out of range, are refused naming the key.
#[test]
fn h1_remeshing_keys_out_of_range_are_refused() {
    for (line, key) in [
        ("      regrowth: 0\n", "remeshing.regrowth"),
        ("      regrowth: 0.5\n", "remeshing.regrowth"),
        ("      regrowth: -1\n", "remeshing.regrowth"),
        ("      regrowth: .nan\n", "remeshing.regrowth"),
        ("      min_edge: -1\n", "remeshing.min_edge"),
        ("      min_edge: .inf\n", "remeshing.min_edge"),
        ("      min_volume: .nan\n", "remeshing.min_volume"),
        ("      min_volume: .inf\n", "remeshing.min_volume"),
        ("      check_every: 0\n", "remeshing.check_every"),
        (
            "      near_tip: { probe: tip, radius: 0.03, steps: 1000000000 }\n",
            "remeshing.near_tip.steps",
        ),
    ] {
        // The keys the finding's scene sets, less the one under test.
        let others: String = ["      check_every: 2\n", "      collapse_limit: 2.5\n"]
            .into_iter()
            .filter(|l| l.split(':').next() != line.split(':').next())
            .collect();
        let text = remeshing_striker(&format!("{others}{line}"));
        let (o, _dir) = scene(&text);
        assert_input_error(&o, &[key]);
    }
}

/// A1: a box of more cells than the solver allocates is refused before it is made.
#[test]
fn a1_huge_meshes_are_refused_before_allocation() {
    for divisions in [
        "[400, 400, 400]",
        "[4294967296, 1, 1]",
        "[4294967296, 4294967296, 4294967296]",
    ] {
        let (o, _dir) = scene(&BAR.replace("[10, 1, 1]", divisions));
        assert_input_error(&o, &["mesh.box.divisions", "tetrahedra"]);
    }
}

/// S1: a safety factor above 1 is refused unless the scene allows an unstable step; zero,
/// negative, NaN and infinite ones always.
#[test]
fn s1_safety_above_one_is_refused() {
    for safety in ["100.0", "1.5", "0", "-1", ".nan", ".inf"] {
        let (o, _dir) = scene(&BAR.replace(
            "end_time: 1.0e-4",
            &format!("end_time: 1.0e-4, safety: {safety}"),
        ));
        assert_input_error(&o, &["analysis.explicit.safety"]);
    }
}

/// S2: a scene's name cannot take its output out of `--out` or hide it.
#[test]
fn s2_scene_names_cannot_leave_the_output_folder() {
    for name in ["../escape", "/abs/escape", "\"\"", ".", "a/b", ".hidden"] {
        let (o, dir) = scene(&BAR.replace("name: s\n", &format!("name: {name}\n")));
        assert_input_error(&o, &["name"]);
        assert!(!dir.join("escape_history.csv").exists());
    }
}

/// S4: two probes, boundary conditions or contact pairs of one name are refused.
#[test]
fn s4_duplicate_names_are_refused() {
    let probes = "probes:\n  - { name: p, body: bar, nodes: all, quantity: velocity }\n  - { name: p, body: bar, nodes: all, quantity: velocity }\n";
    let (o, _dir) = scene(&format!("{BAR}{probes}"));
    assert_input_error(&o, &["probe `p`", "two probes"]);
    let bcs = BAR.replace(
        "boundary_conditions:\n",
        "boundary_conditions:\n  - { name: push, body: bar, nodes: { plane: { point: [1, 0, 0], normal: [1, 0, 0] } }, motion: { fixed: [x] } }\n",
    );
    let (o, _dir) = scene(&bcs);
    assert_input_error(&o, &["boundary condition `push`"]);
    let bodies = BAR.replace(
        "boundary_conditions:",
        "  - name: other\n    mesh: { box: { origin: [2, 0, 0], size: [0.1, 0.1, 0.1], divisions: [1, 1, 1] } }\n    material: { linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 } }\nboundary_conditions:",
    );
    let pairs =
        "contact:\n  - { name: c, bodies: [bar, other] }\n  - { name: c, bodies: [bar, other] }\n";
    let (o, _dir) = scene(&format!("{bodies}{pairs}"));
    assert_input_error(&o, &["contact pair `c`"]);
}

/// S5: two runs into one reports folder within a second keep both results.
#[test]
fn s5_two_runs_of_one_second_keep_their_own_folders() {
    let dir = temp_dir("finding-runs");
    let reports = dir.join("reports");
    let file = dir.join("case.yaml");
    std::fs::write(&file, CASE).unwrap();
    let run = || {
        impact_vv(
            &[
                "run",
                file.to_str().unwrap(),
                "--reports",
                reports.to_str().unwrap(),
            ],
            &[],
        )
    };
    let (a, b) = (run(), run());
    assert_eq!(a.status.code(), Some(0), "{}", text(&a));
    assert_eq!(b.status.code(), Some(0), "{}", text(&b));
    let runs: Vec<_> = std::fs::read_dir(&reports)
        .unwrap()
        .flatten()
        .filter(|e| e.path().join("results.json").is_file())
        .collect();
    assert_eq!(runs.len(), 2, "two run folders with results");
}

/// U1: an empty sweep and a factor that is not positive are refused naming the sweep's key.
#[test]
fn u1_empty_sweeps_are_refused_naming_the_key() {
    for (sweep, key) in [
        ("sweep: { mesh: [] }", "sweep.mesh"),
        ("sweep: { time_step_factor: [] }", "sweep.time_step_factor"),
        ("sweep: { mesh_files: [] }", "sweep.mesh_files"),
        (
            "sweep: { time_step_factor: [0.0] }",
            "sweep.time_step_factor[0]",
        ),
        (
            "sweep: { time_step_factor: [0.5, .nan] }",
            "sweep.time_step_factor[1]",
        ),
    ] {
        let o = case(&format!("{CASE}{sweep}\n"), &[]);
        assert_input_error(&o, &[key]);
    }
}

/// U2: a UTF-8 byte-order mark before a scene or a case is read past.
#[test]
fn u2_a_byte_order_mark_is_read_past() {
    let (o, _dir) = scene(&format!("\u{feff}{}", BAR.replace("1.0e-4", "1.0e-6")));
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let o = case(&format!("\u{feff}{CASE}"), &[]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
}

/// U3: non-finite gravity, damping, velocity and coordinates, and a damping that feeds energy
/// in, are refused naming the key (not reported as an inverted element).
#[test]
fn u3_non_finite_numbers_are_refused_naming_the_key() {
    let explicit = "explicit: { end_time: 1.0e-4 }";
    for (from, to, key) in [
        ("analysis:", "gravity: [0, 0, .nan]\nanalysis:", "gravity"),
        ("analysis:", "gravity: [0, 0, .inf]\nanalysis:", "gravity"),
        (
            explicit,
            "explicit: { end_time: 1.0e-4, damping: .nan }",
            "damping",
        ),
        (
            explicit,
            "explicit: { end_time: 1.0e-4, damping: -1.0e4 }",
            "damping",
        ),
        (
            "    material:",
            "    initial_velocity: { translation: [.nan, 0, 0] }\n    material:",
            "initial_velocity.translation",
        ),
        (
            "origin: [0, 0, 0]",
            "origin: [.nan, 0, 0]",
            "mesh.box.origin",
        ),
        (
            explicit,
            "explicit: { end_time: 1.0e-4, instability_energy_tolerance: -1.0e-9 }",
            "instability_energy_tolerance",
        ),
        (explicit, "explicit: { end_time: 1.0e300 }", "end_time"),
        ("density: 2300", "density: 1e300", "density"),
    ] {
        assert!(BAR.contains(from), "{from}");
        let (o, _dir) = scene(&BAR.replacen(from, to, 1));
        assert_input_error(&o, &[key]);
    }
}

/// S1 (the same mechanism): a stable step longer than the run is cut to the run's length, so
/// the history ends at `end_time`, not a step past it.
#[test]
fn a_run_shorter_than_one_step_ends_at_its_end_time() {
    let (o, dir) = scene(&BAR.replace("end_time: 1.0e-4", "end_time: 1.0e-6"));
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let history = std::fs::read_to_string(dir.join("out/s_history.csv")).unwrap();
    let last = history.lines().last().unwrap();
    let time: f64 = last.split(',').next().unwrap().parse().unwrap();
    assert!((time - 1.0e-6).abs() <= 1e-18, "{last}");
}

/// U6: a missing case file or catalogue, and a reports "folder" that is a file, say so.
#[test]
fn u6_missing_files_and_folders_are_named() {
    let o = impact_vv(&["run", "nope.yaml"], &[]);
    assert_input_error(&o, &["nope.yaml", "no such case file"]);
    let o = impact_vv(&["list", "--catalogue", "/nonexistent-catalogue"], &[]);
    assert_input_error(&o, &["/nonexistent-catalogue", "no such catalogue folder"]);
    let dir = temp_dir("finding-reports");
    let file = dir.join("case.yaml");
    std::fs::write(&file, CASE).unwrap();
    let not_a_folder = dir.join("reports");
    std::fs::write(&not_a_folder, "a file").unwrap();
    let o = impact_vv(
        &[
            "run",
            file.to_str().unwrap(),
            "--reports",
            not_a_folder.to_str().unwrap(),
        ],
        &[],
    );
    assert_input_error(&o, &["reports"]);
}

/// U6: the lines of a case's variants name the variant.
#[test]
fn u6_variant_lines_name_the_variant() {
    let o = case(
        &format!("{CASE}variants: [{{ name: first }}, {{ name: second }}]\n"),
        &["--serial"],
    );
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    assert!(
        t.contains("t/limit [first]") && t.contains("t/limit [second]"),
        "{t}"
    );
}

/// Every input scene and case of the repository passes the new range checks.
#[test]
fn the_catalogue_passes_the_range_checks() {
    let o = impact_vv(&["list"], &[]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
}
