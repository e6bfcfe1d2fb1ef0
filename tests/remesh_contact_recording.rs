//! A run that remeshes records its contact problems as any other run does: the pair's
//! `record_problems_every` writes `contact-problem/1` files over the whole run, across the
//! remeshings, with the steps counting on (the nail's hardest problems in
//! `references/contact-problems/scenes` were recorded so).

mod cli_common;

use cli_common::*;

#[test]
fn a_remeshing_run_records_its_contact_problems_across_the_remeshings() {
    // Run to 200 us with a collapse limit of 1.5: the striker's block remeshes from its second
    // step on, while the striker presses on it.
    let scene = remeshing_striker("      check_every: 2\n      collapse_limit: 1.5\n")
        .replace("end_time: 4.0e-5", "end_time: 2.0e-4")
        .replace(
            "penetration_release_speed: 20.0 }",
            "penetration_release_speed: 20.0, record_problems_every: 1 }",
        );
    let dir = temp_dir("remesh-recording");
    let file = dir.join("striker.yaml");
    std::fs::write(&file, scene).unwrap();
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
    let printed = text(&o);
    assert_eq!(o.status.code(), Some(0), "{printed}");

    // The step the first remeshing was made at: its time over the run's first time step (the
    // step changes only at a remeshing or a pause, so it is constant up to there).
    let dt: f64 = printed
        .split("dt = ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("the plan gives the time step: {printed}"));
    let remeshings = std::fs::read_to_string(out.join("remesh_remeshing.csv")).unwrap();
    let first_remeshing: f64 = remeshings
        .lines()
        .nth(1)
        .unwrap_or_else(|| panic!("the block remeshes: {remeshings}"))
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let first_remeshing_step = (first_remeshing / dt).round() as u64;

    let folder = out.join("remesh-contact-problems");
    let names: Vec<String> = std::fs::read_dir(&folder)
        .unwrap_or_else(|e| panic!("{}: {e}\n{printed}", folder.display()))
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let mut steps: Vec<u64> = names
        .iter()
        .map(|name| name["step".len()..name.find('-').unwrap()].parse().unwrap())
        .collect();
    steps.sort_unstable();
    steps.dedup();
    let (first, last) = (steps[0], *steps.last().unwrap());
    // Every step records (every: 1): while the bodies touch, the recorded steps run on one by
    // one through the remeshings, none skipped, and go on past the first remeshing.
    assert_eq!(
        steps.len() as u64,
        last - first + 1,
        "recorded steps {steps:?}"
    );
    assert!(
        first <= first_remeshing_step && last > first_remeshing_step + 5,
        "recorded steps {first}..{last}, first remeshing at step {first_remeshing_step}"
    );
    let one = std::fs::read_to_string(folder.join(&names[0])).unwrap();
    let parsed: serde_json::Value = serde_json::from_str(&one).unwrap();
    assert_eq!(parsed["format"], "contact-problem/1");
    assert!(parsed["contacts"].as_u64().unwrap() > 0);
}
