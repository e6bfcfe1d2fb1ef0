//! A seeded mutation campaign over the inputs `impact-vv` reads: scenes, case files, Gmsh meshes
//! and contact problems, each mutated (a number made NaN, infinite, huge, negative or zero; a key
//! deleted or unknown; a list emptied or an item doubled; a type changed; the text truncated or a
//! byte flipped) and run through the release binary under a time limit. Whatever the input, the
//! program must not panic, abort, hang, or exit 0 having written a non-finite number; an input
//! error (status 2) must name a file or a key.
//!
//! `IMPACT_FUZZ_INPUTS` sets the number of inputs (default 600, a few seconds on two cores) and
//! `IMPACT_FUZZ_SEED` the seed (default 1): `IMPACT_FUZZ_INPUTS=1000 IMPACT_FUZZ_SEED=7 cargo
//! test --release --test fuzz_inputs` runs a campaign of its own. A finding prints the input that
//! made it.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod cli_common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use cli_common::*;
use impact_solver::rng::SplitMix64;
use serde_norway::Value;

/// How long an input runs before it is stopped by SIGTERM: the seeds run in a fraction of a
/// second.
const LIMIT: Duration = Duration::from_secs(10);

/// The seeds, each `(file name, command, text)`: small scenes of every analysis and feature
/// the catalogue uses, a case with a sweep and variants, a Gmsh mesh and a contact problem.
fn seeds() -> Vec<(&'static str, &'static str, String)> {
    let bar = r#"name: bar
bodies:
  - name: bar
    mesh: { box: { origin: [0, 0, 0], size: [0.4, 0.1, 0.1], divisions: [4, 1, 1], perturb: { fraction: 0.1, seed: 3 } } }
    material: { saint_venant_kirchhoff: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 } }
    initial_velocity: { translation: [0.1, 0, 0], angular_velocity: [0, 0, 1.0] }
boundary_conditions:
  - { name: push, body: bar, nodes: { plane: { point: [0, 0, 0], normal: [1, 0, 0] } }, motion: { velocity: { components: [x], value: { ramp: { t0: 0, t1: 1.0e-5, from: 0, to: 1.0 } } } } }
  - { name: side, body: bar, nodes: { box: { min: [0, 0, 0], max: [0.4, 0, 0.1] } }, motion: { fixed: [y] } }
loads:
  - { name: tip, body: bar, nodes: { plane: { point: [0.4, 0, 0], normal: [1, 0, 0] } }, force_per_node: [0, 10.0, 0] }
gravity: [0, -9.81, 0]
probes:
  - { name: end, body: bar, nodes: { plane: { point: [0.4, 0, 0], normal: [1, 0, 0] } }, quantity: displacement }
analysis:
  explicit: { end_time: 1.0e-4, safety: 0.8, damping: 10.0, history_interval: 1.0e-5, stop_when: { column: end_x, level: 1.0 } }
"#;
    let contact = r#"name: pair
bodies:
  - name: left
    mesh: { box: { origin: [0, 0, 0], size: [0.1, 0.1, 0.1], divisions: [1, 1, 1] } }
    material: { linear_elastic: { density: 7800, youngs_modulus: 200.0e9, poisson_ratio: 0.3 } }
    initial_velocity: { translation: [5.0, 0, 0] }
  - name: right
    mesh: { box: { origin: [0.1001, 0, 0], size: [0.1, 0.1, 0.1], divisions: [1, 1, 1] } }
    material: { linear_elastic: { density: 7800, youngs_modulus: 200.0e9, poisson_ratio: 0.3 } }
    transform: { rotation_axis: [1, 0, 0], rotation_angle: 0.0, translation: [0, 0, 0] }
probes:
  - { name: v, body: left, nodes: all, quantity: velocity }
contact:
  - { name: hit, bodies: [left, right], friction: 0.3, beta_0: 0.45, solver: { name: gauss-seidel/thesis, tolerance: 1.0e-8, max_iterations: 200 } }
analysis:
  explicit: { end_time: 6.0e-5 }
"#;
    let statics = r#"name: cantilever
bodies:
  - name: beam
    mesh: { box: { origin: [0, 0, 0], size: [0.5, 0.1, 0.1], divisions: [3, 1, 1] } }
    material: { linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 } }
    regions:
      - name: soft
        centroid_box: { min: [0.3, 0, 0], max: [0.5, 0.1, 0.1] }
        material: { linear_elastic: { density: 2300, youngs_modulus: 10.0e9, poisson_ratio: 0.2 } }
boundary_conditions:
  - { name: clamp, body: beam, nodes: { plane: { point: [0, 0, 0], normal: [1, 0, 0] } }, motion: { fixed: [x, y, z] } }
loads:
  - { name: tip, body: beam, nodes: { plane: { point: [0.5, 0, 0], normal: [1, 0, 0] } }, force_per_node: [0, -1.0e3, 0], function: { ramp: { t0: 0, t1: 1, from: 0, to: 1 } } }
probes:
  - { name: tip, body: beam, nodes: { plane: { point: [0.5, 0, 0], normal: [1, 0, 0] } }, quantity: displacement }
analysis:
  static: { load_steps: 4 }
"#;
    let release = statics.replace(
        "  static: { load_steps: 4 }",
        "  release:\n    preload: { load_steps: 2 }\n    explicit: { end_time: 5.0e-5 }",
    );
    let remesh = remeshing_striker(
        "      check_every: 2\n      collapse_limit: 2.5\n      min_edge: 1.0e-3\n      \
         regrowth: 1.25\n      near_tip: { probe: tip, radius: 3.0e-2, steps: 3 }\n",
    );
    let gmsh = format!(
        "name: cube\nbodies:\n  - name: cube\n    mesh: {{ gmsh: {} }}\n    material: {{ linear_elastic: {{ density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 }} }}\nboundary_conditions:\n  - {{ name: base, body: cube, nodes: {{ group: bottom }}, motion: {{ fixed: [x, y, z] }} }}\nanalysis: {{ explicit: {{ end_time: 1.0e-5 }} }}\n",
        "mesh.msh"
    );
    let case = r#"id: fuzz/case
description: a fuzzed case
tier: quick
time_limit_s: 10
scene:
  name: bar
  bodies:
    - name: bar
      mesh: { box: { origin: [0, 0, 0], size: [1, 0.1, 0.1], divisions: [2, 1, 1] } }
      material: { linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 } }
  boundary_conditions:
    - { name: push, body: bar, nodes: { plane: { point: [0, 0, 0], normal: [1, 0, 0] } }, motion: { velocity: { components: [x], value: { constant: 1.0 } } } }
  analysis: { explicit: { end_time: 1.0e-4 } }
sweep: { time_step_factor: [0.5, 0.9] }
variants:
  - { name: serial }
  - { name: two, ranks: 2 }
metrics:
  - { name: energy_balance_error, measure: energy_balance_error, reference: { analytic: zero }, tolerance: { at_most: 0.5 } }
"#;
    let problem = r#"{"format": "contact-problem/1", "dimension": 3, "contacts": 2, "mu": [0.3, 0.5], "q": [-1.0, 0.2, 0.1, -0.5, 0.0, 0.3], "W": {"rows": 6, "cols": 6, "triplets": [[0, 0, 2.0], [1, 1, 2.0], [2, 2, 2.0], [3, 3, 3.0], [4, 4, 3.0], [5, 5, 3.0], [0, 3, 0.5], [3, 0, 0.5]]}}"#;
    let msh = std::fs::read_to_string(repo().join("cases/meshes/test/cube_gmsh.msh")).unwrap();
    vec![
        ("bar.yaml", "scene", bar.to_string()),
        ("pair.yaml", "scene", contact.to_string()),
        ("cantilever.yaml", "scene", statics.to_string()),
        ("release.yaml", "scene", release),
        ("remesh.yaml", "scene", remesh),
        ("cube.yaml", "scene", gmsh),
        ("case.yaml", "run", case.to_string()),
        ("problem.json", "contact-compare", problem.to_string()),
        ("mesh.msh", "mesh", msh),
    ]
}

/// What replaces a number: the values the first campaign found to get through.
const NUMBERS: [&str; 12] = [
    ".nan",
    ".inf",
    "-.inf",
    "1e300",
    "-1e300",
    "0",
    "-1",
    "1e-300",
    "4294967296",
    "9223372036854775808",
    "0.5",
    "3",
];

/// Every path (keys and indices) to a node of `v`.
fn paths(v: &Value, here: &mut Vec<Value>, out: &mut Vec<Vec<Value>>) {
    out.push(here.clone());
    match v {
        Value::Mapping(m) => {
            for (k, child) in m {
                here.push(k.clone());
                paths(child, here, out);
                here.pop();
            }
        }
        Value::Sequence(s) => {
            for (i, child) in s.iter().enumerate() {
                here.push(Value::from(i as u64));
                paths(child, here, out);
                here.pop();
            }
        }
        _ => {}
    }
}

fn node_mut<'a>(v: &'a mut Value, path: &[Value]) -> &'a mut Value {
    path.iter().fold(v, |v, k| match v {
        Value::Mapping(m) => m.get_mut(k).unwrap(),
        Value::Sequence(s) => &mut s[k.as_u64().unwrap() as usize],
        _ => unreachable!("a path goes through maps and lists"),
    })
}

/// One structural mutation of a YAML or JSON document; `None` when the text does not parse.
fn mutate_tree(text: &str, rng: &mut SplitMix64) -> Option<String> {
    let mut doc: Value = serde_norway::from_str(text).ok()?;
    let mut all = Vec::new();
    paths(&doc, &mut Vec::new(), &mut all);
    let path = all[1 + (rng.next_u64() as usize) % (all.len() - 1)].clone();
    let pick = |rng: &mut SplitMix64, n: usize| (rng.next_u64() % n as u64) as usize;
    let choice = pick(rng, 10);
    let (parent_path, key) = path.split_at(path.len() - 1);
    match choice {
        // A number (or anything) becomes an out-of-range number.
        0..=4 => {
            let number = NUMBERS[pick(rng, NUMBERS.len())];
            *node_mut(&mut doc, &path) = serde_norway::from_str(number).unwrap();
        }
        // Delete the key or item.
        5 => match node_mut(&mut doc, parent_path) {
            Value::Mapping(m) => {
                m.remove(&key[0]);
            }
            Value::Sequence(s) => {
                s.remove(key[0].as_u64().unwrap() as usize);
            }
            _ => {}
        },
        // Empty a list or map, or double a list's item.
        6 => match node_mut(&mut doc, &path) {
            Value::Sequence(s) if pick(rng, 2) == 0 && !s.is_empty() => {
                let first = s[0].clone();
                s.push(first);
            }
            Value::Sequence(s) => s.clear(),
            Value::Mapping(m) => m.clear(),
            other => *other = Value::Sequence(Vec::new()),
        },
        // Change a type.
        7 => {
            let node = node_mut(&mut doc, &path);
            *node = match node {
                Value::String(_) => Value::from(-7),
                _ => Value::String("text".into()),
            }
        }
        // An unknown key beside this one.
        8 => {
            if let Value::Mapping(m) = node_mut(&mut doc, parent_path) {
                m.insert(Value::String("unknown_key".into()), Value::from(1));
            }
        }
        // A name made to clash: the value of a string copied over a sibling's.
        _ => {
            let node = node_mut(&mut doc, &path);
            if let Value::String(s) = node {
                *s = ["../escape", "", "a/b", "bar", "left", "soft", "tip"][pick(rng, 7)].into();
            }
        }
    }
    serde_norway::to_string(&doc).ok()
}

/// One mutation of the raw text: truncated, a byte flipped, a byte-order mark, a line doubled.
fn mutate_text(text: &str, rng: &mut SplitMix64) -> Vec<u8> {
    let mut bytes = text.as_bytes().to_vec();
    let at = (rng.next_u64() as usize) % bytes.len().max(1);
    match rng.next_u64() % 4 {
        0 => bytes.truncate(at),
        1 => bytes[at] ^= 1 << (rng.next_u64() % 8),
        2 => bytes.splice(0..0, [0xEF, 0xBB, 0xBF]).for_each(drop),
        _ => {
            let line_end = bytes[at..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(bytes.len(), |p| at + p + 1);
            let line_start = bytes[..at]
                .iter()
                .rposition(|&b| b == b'\n')
                .map_or(0, |p| p + 1);
            let line = bytes[line_start..line_end].to_vec();
            bytes.splice(line_start..line_start, line).for_each(drop);
        }
    }
    bytes
}

/// One line of a mutated mesh: a number in a node or element line replaced.
fn mutate_mesh(text: &str, rng: &mut SplitMix64) -> Vec<u8> {
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let i = (rng.next_u64() as usize) % lines.len();
    let mut words: Vec<String> = lines[i].split(' ').map(String::from).collect();
    let w = (rng.next_u64() as usize) % words.len();
    words[w] = [
        "0",
        "-1",
        "nan",
        "1e309",
        "4294967296",
        "18446744073709551615",
        "2",
        "7",
    ][(rng.next_u64() % 8) as usize]
        .into();
    lines[i] = words.join(" ");
    (lines.join("\n") + "\n").into_bytes()
}

/// The exit status of one input, or what is wrong with what it did.
fn judge(dir: &Path, command: &str, input: &Path) -> Result<i32, String> {
    let out = dir.join("out");
    let input_s = input.to_str().unwrap();
    let args: Vec<&str> = match command {
        "run" => vec![
            "run",
            input_s,
            "--reports",
            out.to_str().unwrap(),
            "--serial",
        ],
        "contact-compare" => vec![
            "contact-compare",
            input_s,
            "--out",
            out.to_str().unwrap(),
            "--time-limit",
            "2",
        ],
        // A mesh is read by the cube scene beside it.
        "mesh" => vec![
            "scene",
            "cube.yaml",
            "--out",
            out.to_str().unwrap(),
            "--no-fields",
        ],
        _ => vec![
            "scene",
            input_s,
            "--out",
            out.to_str().unwrap(),
            "--no-fields",
        ],
    };
    let mut child = Command::new(env!("CARGO_BIN_EXE_impact-vv"))
        .args(&args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(dir.join("stderr.txt")).unwrap())
        .spawn()
        .unwrap();
    let started = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        // A valid input may ask for a long run (`end_time: 3` of a penetration): past the
        // limit it must stop on SIGTERM as a user's Ctrl-C stops it, with status 130 and what
        // it computed written; one that does not is a hang.
        if started.elapsed() > LIMIT {
            let _ = Command::new("kill")
                .args(["-TERM", &child.id().to_string()])
                .status();
            let signalled = Instant::now();
            while signalled.elapsed() < Duration::from_secs(5) {
                if let Some(s) = child.try_wait().unwrap() {
                    return match s.code() {
                        Some(130) => Ok(3),
                        other => Err(format!("stopped by SIGTERM with status {other:?}")),
                    };
                }
                std::thread::sleep(Duration::from_millis(20));
            }
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "hang: still running {LIMIT:?} after it started and 5 s after SIGTERM"
            ));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let stderr = std::fs::read_to_string(dir.join("stderr.txt")).unwrap_or_default();
    let code = status.code();
    match code {
        None => Err(format!("killed by a signal (abort?): {stderr}")),
        Some(101) => Err(format!("panic: {stderr}")),
        _ if stderr.contains("panicked") => Err(format!("panic: {stderr}")),
        Some(2) => {
            let file = input.file_name().unwrap().to_str().unwrap();
            let names = stderr.contains(file)
                || stderr.contains("mesh.msh")
                || stderr.contains('`')
                || stderr.contains("--");
            if names {
                Ok(2)
            } else {
                Err(format!("an input error naming no file or key: {stderr}"))
            }
        }
        Some(0) => non_finite_output(&out).map_or(Ok(0), |f| Err(format!("exit 0 with {f}"))),
        // A run that failed (1) says why; it is judged by its message alone, which
        // `IMPACT_FUZZ_VERBOSE` prints for a person to read.
        Some(1) if !stderr.trim().is_empty() => {
            if std::env::var_os("IMPACT_FUZZ_VERBOSE").is_some() {
                eprintln!("status 1, {}: {}", input.display(), stderr.trim());
            }
            Ok(1)
        }
        Some(code) => Err(format!("exit {code}: {stderr}")),
    }
}

/// A written CSV or JSON file under `dir` that holds a non-finite number, if one does.
fn non_finite_output(dir: &Path) -> Option<String> {
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = entry.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "csv") {
                let text = std::fs::read_to_string(&p).unwrap_or_default();
                if text.split([',', '\n']).any(|f| {
                    let f = f.trim().to_ascii_lowercase();
                    f == "nan" || f == "inf" || f == "-inf"
                }) {
                    return Some(format!("a non-finite value in {}", p.display()));
                }
            }
        }
    }
    None
}

fn env_or(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Writes the cube scene and its mesh into `dir`, then `bytes` as the input `name` (a mutated
/// mesh replaces the cube's), and returns the input's path.
fn lay_out(dir: &Path, seeds: &[(&str, &str, String)], name: &str, bytes: &[u8]) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    for seed in ["cube.yaml", "mesh.msh"] {
        let text = &seeds.iter().find(|s| s.0 == seed).unwrap().2;
        std::fs::write(dir.join(seed), text).unwrap();
    }
    let input = dir.join(name);
    std::fs::write(&input, bytes).unwrap();
    input
}

/// Each seed runs as written (status 0), so that the mutations reach the solver and not only
/// the reader.
#[test]
fn every_seed_runs_as_written() {
    let seeds = seeds();
    let root = temp_dir("fuzz-seeds");
    for (name, command, text) in &seeds {
        let dir = root.join(name.replace('.', "-"));
        let input = lay_out(&dir, &seeds, name, text.as_bytes());
        let status = judge(&dir, command, &input);
        let stderr = std::fs::read_to_string(dir.join("stderr.txt")).unwrap_or_default();
        assert_eq!(status, Ok(0), "seed {name}: {stderr}");
    }
}

#[test]
fn mutated_inputs_never_panic_hang_or_pass_bad_numbers() {
    let inputs = env_or("IMPACT_FUZZ_INPUTS", 600) as usize;

    let seed = env_or("IMPACT_FUZZ_SEED", 1);
    let seeds = seeds();
    let mut rng = SplitMix64::new(seed);
    // The mutated inputs, made up front from one sequence so that a campaign is reproducible
    // whatever the order the workers take them in.
    let cases: Vec<(usize, Vec<u8>)> = (0..inputs)
        .map(|_| {
            let s = (rng.next_u64() as usize) % seeds.len();
            let (_, command, text) = &seeds[s];
            let bytes = match (*command, rng.next_u64() % 4) {
                ("mesh", _) => mutate_mesh(text, &mut rng),
                (_, 0) => mutate_text(text, &mut rng),
                _ => mutate_tree(text, &mut rng)
                    .map_or_else(|| text.clone().into_bytes(), String::into_bytes),
            };
            (s, bytes)
        })
        .collect();
    let root = temp_dir("fuzz");
    let next = std::sync::atomic::AtomicUsize::new(0);
    let findings = std::sync::Mutex::new(Vec::new());
    // How many inputs ended with status 0 (ran), 1 (a run that failed), 2 (refused), and how
    // many long runs stopped on SIGTERM (130).
    let statuses = std::sync::Mutex::new([0usize; 4]);
    let workers = std::thread::available_parallelism()
        .map_or(2, |n| n.get())
        .min(4);
    let started = Instant::now();
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some((s, bytes)) = cases.get(k) else {
                    break;
                };
                let (name, command, _) = &seeds[*s];
                let dir: PathBuf = root.join(format!("input-{k}"));
                std::fs::create_dir_all(&dir).unwrap();
                // The cube scene reads `mesh.msh`; a mutated mesh replaces it.
                let cube = &seeds.iter().find(|s| s.0 == "cube.yaml").unwrap().2;
                std::fs::write(dir.join("cube.yaml"), cube).unwrap();
                std::fs::write(
                    dir.join("mesh.msh"),
                    &seeds.iter().find(|s| s.0 == "mesh.msh").unwrap().2,
                )
                .unwrap();
                let input = dir.join(if *command == "mesh" { "mesh.msh" } else { name });
                std::fs::write(&input, bytes).unwrap();
                match judge(&dir, command, &input) {
                    Ok(code) => {
                        statuses.lock().unwrap()[code as usize] += 1;
                        let _ = std::fs::remove_dir_all(&dir);
                    }
                    Err(what) => findings.lock().unwrap().push(format!(
                        "input {k} (seed file {name}): {what}\n--- input ---\n{}",
                        String::from_utf8_lossy(bytes)
                    )),
                }
            });
        }
    });
    let findings = findings.into_inner().unwrap();
    let [ran, failed, refused, stopped] = statuses.into_inner().unwrap();
    eprintln!(
        "{inputs} mutated inputs (seed {seed}) in {:.1} s: {ran} ran (status 0), {failed} runs \
         failed (1), {refused} refused (2), {stopped} long runs stopped by SIGTERM (130), {} \
         findings",
        started.elapsed().as_secs_f64(),
        findings.len()
    );
    // Every seed runs as written, so the campaign reaches the solver and not only the reader.
    assert!(ran > 0, "no input ran: the seeds themselves are refused");
    assert!(findings.is_empty(), "{}", findings.join("\n\n"));
}
