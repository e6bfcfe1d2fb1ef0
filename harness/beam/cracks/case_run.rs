//! Diagnostics that run beam cases and print what the measures see (ignored tests, minutes
//! each): the crack table, the two tips and the layer openings of a case (`print_beam_case`),
//! and the traction-free tip beside the cohesive hinge's opening front on a static beam
//! (`tip_against_hinge`).
//!
//! `print_beam_case` runs a beam drop case and prints its crack table and tip history (about 30 s
//! per case):
//! `BEAM_CASE=drop-2ms cargo test --release -p impact-vv --lib -- --ignored print_beam_case`.

#![cfg(test)]

use super::*;

/// Prints a crack-tip report: thresholds, initiation, coalescence, both speed readings and the
/// two heights per snapshot.
fn print_tips(tip: &CrackTipReport) {
    let c_r = tip.rayleigh_speed;
    println!(
        "w_p {:.2} um, w_tf {:.3} mm, cell {:.4} m, c_R {:.0} m/s",
        tip.cohesive_opening * 1e6,
        tip.traction_free_opening * 1e3,
        tip.cell,
        c_r
    );
    match tip.initiation {
        Some(i) => println!(
            "initiation {:.4} ms: length {:.3} m (traction-free crack {:.3} m)",
            i.time * 1e3,
            i.length,
            i.traction_free_height
        ),
        None => println!("initiation: no traction-free crack"),
    }
    println!(
        "coalescence {:.3} m ({} elements)",
        tip.coalescence_length, tip.coalesced_elements
    );
    println!("cohesive tip {}", tip.cohesive_speed.describe(c_r));
    println!(
        "traction-free tip {}",
        tip.traction_free_speed.describe(c_r)
    );
    if let Some(w) = tip.cohesive_speed.fastest {
        println!("cohesive fastest {:?}", w);
    }
    if let Some(w) = tip.traction_free_speed.fastest {
        println!("traction-free fastest {:?}", w);
    }
    for ((t, c), f) in tip.times.iter().zip(&tip.cohesive).zip(&tip.traction_free) {
        println!("tips {:.4} ms {:.3} {:.3} m", t * 1e3, c, f);
    }
}

/// Builds and runs a scene without output files.
fn run_scene(
    scene: &impact_solver::scene::Scene,
) -> (
    impact_solver::problem::Problem,
    impact_solver::analysis::Execution,
) {
    let mut problem = impact_solver::scene::build_problem(scene).unwrap();
    let options = impact_solver::analysis::ExecuteOptions {
        out: None,
        stem: "run",
        final_state: true,
        fields: false,
        time_limit_s: None,
        stop: None,
        ranks: None,
        log: &impact_solver::analysis::log_to_stderr,
    };
    let run =
        impact_solver::analysis::execute(&mut problem, &scene.analysis, &options, &mut |_| {})
            .unwrap();
    (problem, run)
}

/// The beam case `BEAM_CASE` names (a case of `cases/beam` by name, or a case file's path;
/// `default` without it), loaded; the working directory then moves to `cases/beam`, where the
/// cases name their material files relatively.
fn beam_case(default: &str) -> crate::catalogue::CaseSpec {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let name = std::env::var("BEAM_CASE").unwrap_or_else(|_| default.into());
    let path = if name.ends_with(".yaml") {
        std::path::PathBuf::from(&name)
    } else {
        root.join("cases/beam").join(format!("{name}.yaml"))
    };
    let case = crate::case_file::load_spec(&path).unwrap();
    std::env::set_current_dir(root.join("cases/beam")).unwrap();
    case
}

#[test]
#[ignore]
fn print_beam_case() {
    let case = beam_case("drop-2ms");
    let mut scene = case.scene.clone().unwrap();
    // BEAM_END_MS and BEAM_SNAPSHOT_US shorten the run and refine the snapshots.
    if let impact_solver::scene::Analysis::Explicit(x) = &mut scene.analysis {
        if let Ok(end) = std::env::var("BEAM_END_MS") {
            x.settings.end_time = end.parse::<f64>().unwrap() * 1e-3;
        }
        if let Ok(dt) = std::env::var("BEAM_SNAPSHOT_US") {
            x.settings.snapshot_interval = Some(dt.parse::<f64>().unwrap() * 1e-6);
        }
    }
    let (problem, run) = run_scene(&scene);
    let spec = BeamSpec::default();
    let (mode, cracks, frame) = failure_mode_at(&problem, &spec, &run.u).unwrap();
    println!(
        "end of run\n{}",
        failure_mode_details(mode, &cracks, &frame)
    );
    let contact = BeamSpec {
        at: JudgedAt::ContactEnd {
            column: "impact_force_y".into(),
            fraction: 0.01,
        },
        ..BeamSpec::default()
    };
    match failure_mode_judged(&problem, &contact, &run) {
        Ok((mode, cracks, frame, t)) => println!(
            "end of contact {:.3} ms\n{}",
            t * 1e3,
            failure_mode_details(mode, &cracks, &frame)
        ),
        Err(e) => println!("no end of contact: {e}"),
    }
    match crack_tip_report(&problem, run.snapshots(), &spec) {
        Ok(tip) => print_tips(&tip),
        Err(e) => println!("no tip: {e}"),
    }
    // The largest opening (mm) of each cell layer of the mid-span strip, bottom first.
    let (frame, elements) = BeamFrame::of(&problem, &spec).unwrap();
    let range = beam_elements(&problem, &spec).unwrap();
    for s in run.snapshots() {
        let mut layers = [0.0f32; 12];
        let openings = s.crack_opening.get(range.clone()).unwrap_or(&[]);
        for (e, w) in elements.iter().zip(openings) {
            if (e.centroid.x - frame.x_load).abs() <= frame.load_half_width + frame.cell {
                let j = ((e.centroid.y / frame.cell) as usize).min(11);
                layers[j] = layers[j].max(*w * 1e3);
            }
        }
        let row: Vec<String> = layers.iter().map(|w| format!("{w:.3}")).collect();
        println!("w {:.4} ms {}", s.time * 1e3, row.join(" "));
        // ... and the largest crack indicator eps_1 / eps_r of each layer.
        let indicator = indicator_at(&problem, &spec, &s.u).unwrap();
        let mut layers = [0.0f64; 12];
        for (e, i) in elements.iter().zip(&indicator) {
            if (e.centroid.x - frame.x_load).abs() <= frame.load_half_width + frame.cell {
                let j = ((e.centroid.y / frame.cell) as usize).min(11);
                layers[j] = layers[j].max(*i);
            }
        }
        let row: Vec<String> = layers.iter().map(|i| format!("{i:.3}")).collect();
        println!("i {:.4} ms {}", s.time * 1e3, row.join(" "));
    }
}

/// The tip tracker on a quasi-static crack against the cohesive hinge (issue 17): runs a
/// static beam case (default `static-3pt-slice-h50`, about 3 min) with a snapshot every
/// millisecond and prints the tracked tip (opening front at `w_cr / 2`) at the snapshot
/// nearest the peak of `load_plate_reaction_y`, beside the hinge's opening front at its own
/// peak (the hinge of the case's `hinge` reference):
/// `BEAM_CASE=static-3pt-slice-h50 cargo test --release -p impact-vv --lib -- --ignored
/// tip_against_hinge --nocapture`.
#[test]
#[ignore]
fn tip_against_hinge() {
    let case = beam_case("static-3pt-slice-h50");
    let hinge_spec = case
        .metrics
        .iter()
        .find_map(|m| match &m.reference {
            Some(crate::reference::Reference::Hinge(h)) => Some(h.clone()),
            _ => None,
        })
        .expect("a case with a hinge reference");
    let mut scene = case.scene.clone().unwrap();
    if let impact_solver::scene::Analysis::Explicit(x) = &mut scene.analysis {
        x.settings.snapshot_interval = Some(
            std::env::var("BEAM_SNAPSHOT_MS").map_or(1e-3, |v| v.parse::<f64>().unwrap() * 1e-3),
        );
    }
    let hinge = impact_references::hinge::scene_hinge(&scene, &hinge_spec)
        .unwrap()
        .hinge;
    let (problem, run) = run_scene(&scene);
    let history = run.history.as_ref().unwrap();
    let (t, load) = (
        history.column("time").unwrap(),
        history.column("load_plate_reaction_y").unwrap(),
    );
    let peak_at = (0..load.len())
        .max_by(|&a, &b| load[a].abs().total_cmp(&load[b].abs()))
        .unwrap();
    let spec = BeamSpec::default();
    let report = crack_tip_report(&problem, run.snapshots(), &spec).unwrap();
    // The traction-free tip, as `(t, height reached)`: the opening front at `w_cr / 2`.
    let tip: Vec<(f64, f64)> = report
        .times
        .iter()
        .zip(&report.traction_free)
        .map(|(t, h)| (*t, if h.is_finite() { *h } else { 0.0 }))
        .collect();
    for (time, h) in &tip {
        println!("tip {:.1} ms {:.3} m", time * 1e3, h);
    }
    let nearest = tip
        .iter()
        .min_by(|a, b| {
            (a.0 - t[peak_at])
                .abs()
                .total_cmp(&(b.0 - t[peak_at]).abs())
        })
        .unwrap();
    let w_tip = TIP_OPENING_FRACTION * problem.model.crack_indicator.crack_width;
    let peak = hinge.peak(1e4);
    println!(
        "FE: peak load {:.2} kN at {:.1} ms; tip {:.3} m at {:.1} ms",
        load[peak_at].abs() / 1e3,
        t[peak_at] * 1e3,
        nearest.1,
        nearest.0 * 1e3
    );
    println!(
        "hinge: peak load {:.2} kN; cohesive tip {:.3} m; opening front at {:.2} mm: {:.3} m",
        peak.load / 1e3,
        peak.crack_tip,
        w_tip * 1e3,
        hinge.opening_front(&peak, w_tip)
    );
    // After the peak, at the same fraction of the peak load: the FE tip at each snapshot
    // beside the hinge's opening front on its falling branch.
    let curve = hinge.curve(1e4);
    let falling: Vec<(f64, f64)> = curve
        .points
        .iter()
        .filter(|p| p.rotation > curve.peak.rotation)
        .map(|p| (p.load / curve.peak.load, hinge.opening_front(p, w_tip)))
        .collect();
    let fe_peak = load[peak_at].abs();
    for (time, h) in tip.iter().filter(|p| p.0 > t[peak_at]) {
        let i = t.partition_point(|&x| x < *time).min(t.len() - 1);
        let ratio = load[i].abs() / fe_peak;
        let front = falling
            .windows(2)
            .find(|w| (w[1].0 - ratio) * (w[0].0 - ratio) <= 0.0)
            .map(|w| {
                let f = (ratio - w[0].0) / (w[1].0 - w[0].0);
                w[0].1 + f * (w[1].1 - w[0].1)
            });
        println!(
            "after the peak {:.1} ms: load / peak {:.3}; FE tip {:.3} m; hinge front {}",
            time * 1e3,
            ratio,
            h,
            front.map_or("-".into(), |f| format!("{f:.3} m"))
        );
    }
}

/// What the coalescence rule takes out at the start of a bending crack: runs a beam case
/// (`BEAM_CASE`, default `drop-2ms`) and prints, for each element of the connected cohesive
/// crack that passed `w_p` before a face neighbour of it was in the crack, its centroid, the
/// snapshot it passed `w_p`, the snapshot its first face neighbour joined and the snapshot its
/// first node-sharing neighbour joined. An element whose node-sharing neighbour was in the crack
/// before it passed `w_p` was reached through an edge or a corner, which the face rule does not
/// see:
/// `BEAM_CASE=drop-2ms cargo test --release -p impact-vv --lib -- --ignored coalescence_neighbours --nocapture`.
#[test]
#[ignore]
fn coalescence_neighbours() {
    let case = beam_case("drop-2ms");
    let mut scene = case.scene.clone().unwrap();
    if let impact_solver::scene::Analysis::Explicit(x) = &mut scene.analysis {
        x.settings.end_time = 0.7e-3;
    }
    let (problem, run) = run_scene(&scene);
    let spec = BeamSpec::default();
    let report = crack_tip_report(&problem, run.snapshots(), &spec).unwrap();
    let (frame, elements) = BeamFrame::of(&problem, &spec).unwrap();
    let range = beam_elements(&problem, &spec).unwrap();
    let path = tip::CrackPath::of(&frame, &elements);
    let w_p = report.cohesive_opening;
    let n = elements.len();
    // First snapshot past w_p and first snapshot in the connected cohesive crack.
    let (mut past, mut joined) = (vec![None; n], vec![None; n]);
    let mut w_max = vec![0.0f64; n];
    for (k, s) in run.snapshots().iter().enumerate() {
        for (m, w) in w_max.iter_mut().zip(&s.crack_opening[range.clone()]) {
            *m = m.max(f64::from(*w));
        }
        let open: Vec<bool> = w_max.iter().map(|&w| w >= w_p).collect();
        let crack = path.connected(&open);
        for e in 0..n {
            if open[e] && past[e].is_none() {
                past[e] = Some(k);
            }
            if crack[e] && joined[e].is_none() {
                joined[e] = Some(k);
            }
        }
    }
    let seed: std::collections::HashSet<usize> = path.seeds.iter().copied().collect();
    let times: Vec<f64> = run.snapshots().iter().map(|s| s.time * 1e3).collect();
    let at = |k: Option<usize>| k.map_or("never".to_string(), |k| format!("{:.4}", times[k]));
    let (mut by_corner, mut count) = (0, 0);
    for e in 0..n {
        let (Some(p), Some(_)) = (past[e], joined[e]) else {
            continue;
        };
        let face = path.neighbours[e].iter().filter_map(|&m| joined[m]).min();
        if seed.contains(&e) || face.is_none_or(|f| p >= f) {
            continue;
        }
        let corner = path.touching[e].iter().filter_map(|&m| joined[m]).min();
        count += 1;
        if corner.is_some_and(|c| c <= p) {
            by_corner += 1;
        }
        let c = elements[e].centroid;
        println!(
            "pre-damaged ({:.4}, {:.4}, {:.4}) m: past w_p {} ms, face neighbour joined {} ms, node neighbour joined {} ms",
            c.x,
            c.y,
            c.z,
            at(Some(p)),
            at(face),
            at(corner)
        );
    }
    println!(
        "{count} pre-damaged elements in the cohesive crack to 0.7 ms, {by_corner} with a node-sharing neighbour in the crack when they passed w_p; coalescence {:.4} m",
        report.coalescence_length
    );
}
