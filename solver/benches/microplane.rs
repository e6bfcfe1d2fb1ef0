//! One material-point update of the microplane concrete model
//! (`MicroplaneConcrete::update`, `material/microplane/`), per call, on one thread.
//!
//! Parameters are those of `cases/materials/thesis-concrete.yaml` (key `parameters:`; other keys
//! of the file are ignored), crack band of an element of h = 5 cm. Each benchmark updates a
//! *fresh copy* of a prepared history at a fixed strain, so every call takes the same path:
//! - `microplane/elastic/{21,37}/rate_{on,off}`: a virgin history and a small strain
//!   (`E11 = 2e-5`, `E22 = E33 = -0.18 E11`, tensor shear `E12 = 2e-6`) at 1 /s, with the rate
//!   effect as in the file and switched off (`rate_effect = None`);
//! - `microplane/elastic_path/{21,37}`: a virgin history at a strain ten times smaller
//!   (`E11 = 3e-7`), below the limit of the elastic path (`MicroplaneConcrete::elastic_limit`);
//! - `microplane/unloading/{21,37}`: a history loaded in uniaxial stress to `E11 = 6e-5` (half
//!   the tensile peak strain), updated at half that strain: every branch on its unloading line
//!   before the peak, the state of most of a vibrating beam;
//! - `microplane/softening_tension/{21,37}`: a history loaded in uniaxial tension to
//!   `E11 = 6e-4` (well past the peak, by the material-point driver at 1e-5 /s), updated at 1 %
//!   more strain on every component, so the tensile deviatoric branches load further on their
//!   virgin softening laws (the others, relaxed further by `psi`, unload: the printout counts
//!   the branches on their virgin law);
//! - `microplane/softening_compression/{21,37}`: the same in uniaxial compression, a ramp to
//!   `E11 = -4e-3`, or as far as the driver gets (the printout says where it stopped), updated
//!   at 1 % more strain;
//! - `microplane/copy_state/{21,37}`: `copy_from_slice` of the history alone, for reference;
//! - `microplane/portable_*/21*`: the 21-plane cases above through the portable build of the
//!   update, where the processor runs its AVX2 build (`MicroplaneConcrete::with_portable_code`).
//!
//! The restore of the prepared history is *not* timed: a batch of 32 copies is restored outside
//! the clock, then the 32 updates run under it (`iter_custom`), so the clock's own cost is spread
//! over 32 calls and the copies (1212 B each for 21 planes) stay in L1/L2. The numbers are thus
//! hot-cache costs of the update itself; a mesh sweep streams its histories from memory.
//! Throughput is one element per call, so `1e9 / throughput` is ns per update; divide by 21 or 37
//! for ns per microplane. The bench also prints the history size per element for both rules and,
//! for each prepared state, the peak of its driver path, the stress of the timed update and how
//! many branches it moves along their virgin law.
//!
//! Run with
//! `cargo bench -p impact-solver --bench microplane -- --warm-up-time 1 --measurement-time 3`
//! (about a minute); read the medians in `target/criterion/microplane/*/*/new/estimates.json`.
//! The two cores of the shared machine are busy with builds at times, which can double every
//! time; compare within one run, and rerun when criterion's intervals are wide.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use impact_solver::material::microplane::driver::{equivalent_rate, ramp, MaterialPoint};
use impact_solver::material::microplane::{
    CrackBand, MicroplaneConcrete, MicroplaneParameters, SphereRule, Sym,
};

/// Element size of the crack band (m).
const H: f64 = 0.05;
/// Strain rate of the driver paths that prepare the softened histories (1/s).
const PREPARE_RATE: f64 = 1e-5;
/// Updates timed per clock reading; the histories are restored between batches, untimed.
const BATCH: usize = 32;

fn thesis_concrete() -> MicroplaneParameters {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../cases/materials/thesis-concrete.yaml");
    impact_solver::material::read_microplane_file(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn model(rule: SphereRule, rate_effect: bool) -> MicroplaneConcrete {
    let mut p = thesis_concrete();
    p.rule = rule;
    if !rate_effect {
        p.rate_effect = None;
    }
    MicroplaneConcrete::new(p).expect("thesis-concrete parameters are valid")
}

/// A prepared history with the strain and rate of the update to time.
struct Case {
    state: Vec<f32>,
    strain: Sym,
    gamma_dot: f64,
    band: CrackBand,
}

/// Virgin history, small uniaxial-stress-like strain with a little shear, at 1 /s.
fn elastic(model: &MicroplaneConcrete) -> Case {
    let e = 2e-5;
    Case {
        state: model.initial_state().values,
        strain: [e, -0.18 * e, -0.18 * e, 0.0, 0.0, 0.1 * e],
        gamma_dot: 1.0,
        band: model.crack_band(H).expect("h = 5 cm is admissible"),
    }
}

/// Virgin history and a strain below the elastic path's limit (`E11 = 3e-7`, the same shape as
/// [`elastic`]): the update takes the elastic path.
fn elastic_path(model: &MicroplaneConcrete) -> Case {
    let e = 3e-7;
    Case {
        strain: [e, -0.18 * e, -0.18 * e, 0.0, 0.0, 0.1 * e],
        ..elastic(model)
    }
}

/// History after uniaxial stress to `E11 = 6e-5` (half the tensile peak strain), updated at half
/// that strain: every branch unloads before its peak, the state of most of a vibrating beam.
fn unloading(model: &MicroplaneConcrete) -> Case {
    let mut point = MaterialPoint::new(model, H).expect("h = 5 cm is admissible");
    point
        .uniaxial_stress(&ramp(6e-5, 30), PREPARE_RATE)
        .expect("uniaxial stress before the peak converges");
    scaled_update(model, &point, 0.5)
}

/// The update of `point`'s history to `factor` times its strain, at the rate of the driver.
fn scaled_update(model: &MicroplaneConcrete, point: &MaterialPoint, factor: f64) -> Case {
    let from = point.strain;
    let strain = from.map(|e| factor * e);
    let dt = (strain[0] - from[0]).abs() / PREPARE_RATE;
    Case {
        state: point.state.values.clone(),
        strain,
        gamma_dot: equivalent_rate(&from, &strain, dt),
        band: model.crack_band(H).expect("h = 5 cm is admissible"),
    }
}

/// History after uniaxial stress to `end` (or as far as the driver gets), then 1 % more strain on
/// every component at the same rate.
fn beyond_peak(model: &MicroplaneConcrete, end: f64) -> Case {
    let mut point = MaterialPoint::new(model, H).expect("h = 5 cm is admissible");
    let path = ramp(end, 100);
    // `uniaxial_stress(&ramp(end, 100), rate)` one point at a time (the same increments and time
    // steps): the driver returns its points only on success, and the peak is wanted either way.
    let mut peak: f64 = 0.0;
    for &e in &path {
        if let Err(err) = point.uniaxial_stress(&[e], PREPARE_RATE) {
            eprintln!(
                "  driver stopped at E11 = {:.3e} of {end:.1e}: {err}",
                point.strain[0]
            );
            break;
        }
        peak = peak.max(point.stress[0].abs());
    }
    eprintln!(
        "  ramp to E11 = {:+.3e}: peak |s11| {:.3e} Pa, last {:+.3e} Pa",
        point.strain[0], peak, point.stress[0]
    );
    scaled_update(model, &point, 1.01)
}

/// How many branches (volumetric tension plus 6 per plane) load further on their virgin law in
/// the timed update, and the stress before and after.
fn describe(name: &str, model: &MicroplaneConcrete, case: &Case) {
    let mut after = case.state.clone();
    let (stress, info) = model.update(&mut after, &case.strain, case.gamma_dot, &case.band);
    let advanced = case
        .state
        .iter()
        .zip(&after)
        .enumerate()
        .filter(|&(i, (a, b))| is_reached_strain(i) && b > a)
        .count();
    eprintln!(
        "  {name:<28} E11 = {:+.3e}, s11 = {:+.3e} Pa, F = {:.4}, psi = {:.3}, {advanced} \
         branches on their virgin law",
        case.strain[0], stress[0], info.rate_factor, info.psi
    );
}

/// Whether history slot `i` is the largest strain reached of a branch (state.rs layout).
fn is_reached_strain(i: usize) -> bool {
    use impact_solver::material::microplane::state::{
        D_NEGATIVE, D_POSITIVE, HEADER, K, M, PER_PLANE, V_COMPRESSION, V_TENSION,
    };
    if i < HEADER {
        return i == V_TENSION || i == V_COMPRESSION;
    }
    let j = (i - HEADER) % PER_PLANE;
    [D_POSITIVE, D_NEGATIVE, M, M + 2, K, K + 2].contains(&j)
}

/// Time `iters` updates of fresh copies of `case.state`, restoring `BATCH` copies outside the
/// clock.
fn time_updates(model: &MicroplaneConcrete, case: &Case, iters: u64) -> Duration {
    let mut copies = vec![case.state.clone(); BATCH];
    let mut total = Duration::ZERO;
    let mut left = iters as usize;
    while left > 0 {
        let n = left.min(BATCH);
        for copy in &mut copies[..n] {
            copy.copy_from_slice(&case.state);
        }
        let start = Instant::now();
        for copy in &mut copies[..n] {
            black_box(model.update(
                black_box(copy.as_mut_slice()),
                black_box(&case.strain),
                black_box(case.gamma_dot),
                &case.band,
            ));
        }
        total += start.elapsed();
        left -= n;
    }
    total
}

/// Time `iters` copies of the history into `BATCH` buffers in turn (what a naive per-call
/// `clone_from` in the timed loop would add).
fn time_copies(case: &Case, iters: u64) -> Duration {
    let mut copies = vec![case.state.clone(); BATCH];
    let start = Instant::now();
    for i in 0..iters as usize {
        black_box(&mut copies[i % BATCH]).copy_from_slice(black_box(&case.state));
    }
    start.elapsed()
}

fn microplane(c: &mut Criterion) {
    let rules = [(SphereRule::BazantOh21, "21"), (SphereRule::Bazant37, "37")];
    eprintln!("microplane history per element (thesis-concrete, f32):");
    for (rule, label) in rules {
        let state = model(rule, true).initial_state();
        eprintln!(
            "  {label} planes: {} values, {} B (target 1.2 KB = 1200 B for 21 planes)",
            state.values.len(),
            state.bytes()
        );
    }

    let mut cases = Vec::new();
    eprintln!("prepared states (h = {H} m):");
    for (rule, label) in rules {
        for (rate, rate_label) in [(true, "rate_on"), (false, "rate_off")] {
            if rule == SphereRule::Bazant37 && !rate {
                continue;
            }
            let m = model(rule, rate);
            let case = elastic(&m);
            describe(&format!("elastic/{label}/{rate_label}"), &m, &case);
            cases.push(("elastic", format!("{label}/{rate_label}"), m, case));
        }
    }
    for (rule, label) in rules {
        let m = model(rule, true);
        let case = elastic_path(&m);
        describe(&format!("elastic_path/{label}"), &m, &case);
        cases.push(("elastic_path", label.to_string(), m, case));
        let m = model(rule, true);
        let case = unloading(&m);
        describe(&format!("unloading/{label}"), &m, &case);
        cases.push(("unloading", label.to_string(), m, case));
    }
    for (rule, label) in rules {
        let m = model(rule, true);
        let case = beyond_peak(&m, 6e-4);
        describe(&format!("softening_tension/{label}"), &m, &case);
        cases.push(("softening_tension", label.to_string(), m, case));
    }
    for (rule, label) in rules {
        let m = model(rule, true);
        let case = beyond_peak(&m, -4e-3);
        describe(&format!("softening_compression/{label}"), &m, &case);
        cases.push(("softening_compression", label.to_string(), m, case));
    }

    let mut group = c.benchmark_group("microplane");
    group.throughput(Throughput::Elements(1));
    for (kind, id, m, case) in &cases {
        group.bench_function(BenchmarkId::new(*kind, id), |b| {
            b.iter_custom(|iters| time_updates(m, case, iters))
        });
    }
    // The portable build of the same updates, where the processor runs the AVX2 one: the gain
    // of the wider registers, in the same run.
    for (kind, id, m, case) in &cases {
        if m.runs_wide_vectors() && id.starts_with("21") {
            let portable = m.clone().with_portable_code();
            group.bench_function(BenchmarkId::new(format!("portable_{kind}"), id), |b| {
                b.iter_custom(|iters| time_updates(&portable, case, iters))
            });
        }
    }
    for (kind, id, _, case) in &cases {
        if *kind == "elastic" && id.ends_with("rate_on") {
            let label = id.split('/').next().unwrap_or(id);
            group.bench_function(BenchmarkId::new("copy_state", label), |b| {
                b.iter_custom(|iters| time_copies(case, iters))
            });
        }
    }
    group.finish();
}

fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
}

criterion_group! {
    name = benches;
    config = config();
    targets = microplane
}
criterion_main!(benches);
