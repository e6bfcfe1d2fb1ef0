//! A run over several ranks gives the one-process run's history bit for bit (issue 22). The ranks
//! are threads here ([`ThreadGroup`]), with the same collectives the MPI ranks use, so the test
//! needs no MPI installation; `tests/mpi_ranks.rs` (feature `mpi`) runs the same under `mpirun`.

// Test code: an `unwrap` that fails is the failure (the lint is for library code).
#![allow(clippy::unwrap_used)]

mod common;

use std::ops::Range;
use std::path::{Path, PathBuf};

use common::material_history_bits;
use impact_solver::distributed::{Communicator, ThreadGroup};
use impact_solver::dynamics::{
    keeps_own_elements, restore_whole_problem, ExplicitSolver, OutputSettings,
};
use impact_solver::model::{body_part, MaterialHistory};
use impact_solver::scene::{build_problem_on_rank, Analysis, ExplicitAnalysis, Scene};

fn case(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path)
}

/// Bits of a run: the history rows, the final displacement and velocity, the material history
/// (a rank's: that of its own elements).
#[derive(Debug, PartialEq)]
struct Bits {
    history: Vec<u64>,
    state: Vec<u64>,
    material: MaterialHistory,
    /// The elements of each body, and those of this rank (all on one process).
    bodies: Vec<Range<usize>>,
    elements: Range<usize>,
    /// The elements whose shape-function gradients the model holds.
    kept: Range<usize>,
    /// The elements whose connectivity the model holds during the run.
    connected: Range<usize>,
    /// The nodes whose reference coordinates, masses and initial velocities the problem holds
    /// during the run, of how many.
    nodes_held: [usize; 3],
    node_count: usize,
    /// The nodes whose values the integrator stores.
    integrated: usize,
    /// The snapshots' times, displacements and crack openings.
    snapshots: Vec<u64>,
    /// Values this rank sent per step to complete the forces.
    sent: usize,
    /// Largest number of active contact nodes in a history row (0 without contact).
    most_in_contact: f64,
}

/// Runs `steps` steps of the scene (the scene of a case file under `scene`, or a plain scene file)
/// as rank `comm.rank()` (or alone).
fn run(path: &Path, steps: usize, comm: Option<&dyn Communicator>) -> Bits {
    let scene = Scene::from_yaml_file_entry(path, "scene")
        .or_else(|_| Scene::from_yaml_file(path))
        .unwrap();
    // As a scene run does: a rank's model holds no element's shape gradients until its solver
    // has kept its part (then its own elements' only, checked below).
    let mut problem = build_problem_on_rank(&scene, comm.map(|c| (c.rank(), c.size()))).unwrap();
    let ranked = comm.is_some_and(|c| c.size() > 1);
    assert_eq!(
        problem.model.kept_elements().is_empty(),
        ranked,
        "{}",
        path.display()
    );
    let whole = problem.model.tets.clone();
    let whole_nodes = (
        problem.model.reference.clone(),
        problem.model.mass.clone(),
        problem.initial_velocity.clone(),
    );
    let Analysis::Explicit(ExplicitAnalysis { mut settings, .. }) = scene.analysis.clone() else {
        panic!("{}: an explicit scene", path.display())
    };
    settings.max_steps = Some(steps);
    // Snapshots gather the nodes and the crack openings from the ranks (at the end at least).
    settings
        .snapshot_interval
        .get_or_insert(settings.end_time / 1000.0);
    // As `execute` does: a rank keeps its own elements' data, and in a run without contact its
    // own elements' connectivity and its nodes' arrays.
    let keeps = comm.is_some_and(|c| keeps_own_elements(&problem, c));
    let mut solver = match comm {
        Some(comm) => ExplicitSolver::new_rank_keeping_own_elements(
            &mut problem,
            settings,
            OutputSettings::default(),
            comm,
        )
        .unwrap(),
        None => ExplicitSolver::new(&problem, settings, OutputSettings::default()).unwrap(),
    };
    let running = solver.problem();
    let summary = solver.run(&mut |_| {}).unwrap();
    let sent = comm.map_or(0, |c| solver.exchange_counts()[c.rank()]);
    let history = &summary.history;
    let most_in_contact = history
        .columns()
        .iter()
        .filter(|c| c.ends_with("_active"))
        .flat_map(|c| history.column(c).unwrap())
        .fold(0.0, f64::max);
    let bits = Bits {
        history: summary
            .history
            .rows()
            .iter()
            .flatten()
            .map(|x| x.to_bits())
            .collect(),
        state: solver
            .whole(&solver.u)
            .iter()
            .chain(solver.whole(&solver.v_full).iter())
            .flat_map(|x| x.iter().map(|c| c.to_bits()))
            .collect(),
        material: solver.history().clone(),
        bodies: running
            .model
            .bodies
            .iter()
            .map(|b| b.elements.clone())
            .collect(),
        elements: solver
            .rank_elements()
            .unwrap_or(0..running.model.element_count()),
        kept: running.model.kept_elements(),
        connected: running.model.tets.stored_range(),
        nodes_held: [
            running.model.reference.stored().len(),
            running.model.mass.stored().len(),
            running.initial_velocity.stored().len(),
        ],
        node_count: running.model.node_count(),
        integrated: solver.u.stored().len(),
        snapshots: summary
            .snapshots
            .iter()
            .flat_map(|s| {
                let u = s.u.iter().flat_map(|x| x.iter().map(|c| c.to_bits()));
                let w = s.crack_opening.iter().map(|w| u64::from(w.to_bits()));
                std::iter::once(s.time.to_bits()).chain(u).chain(w)
            })
            .collect(),
        sent,
        most_in_contact,
    };
    drop(solver);
    if let Some(comm) = comm.filter(|_| keeps) {
        restore_whole_problem(&mut problem, comm);
    }
    assert_eq!(
        problem.model.tets, whole,
        "the whole connectivity after the run"
    );
    assert!(problem.model.reference.is_whole() && problem.initial_velocity.is_whole());
    assert!(
        (
            problem.model.reference.clone(),
            problem.model.mass.clone(),
            problem.initial_velocity.clone()
        ) == whole_nodes,
        "the whole nodal arrays after the run"
    );
    bits
}

/// The bits of every rank of a run on `ranks` threads.
fn run_ranks(path: &Path, steps: usize, ranks: usize) -> Vec<Bits> {
    let group = ThreadGroup::new(ranks);
    std::thread::scope(|s| {
        let handles: Vec<_> = group
            .iter()
            .map(|comm| s.spawn(move || run(path, steps, Some(comm))))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    })
}

/// Fails with the first differing value (the vectors hold millions).
fn same(got: &[u64], expected: &[u64], what: &str) {
    assert_eq!(got.len(), expected.len(), "{what}: lengths differ");
    if let Some(i) = (0..got.len()).find(|&i| got[i] != expected[i]) {
        panic!(
            "{what} differs first at value {i} of {}: {:e} instead of {:e} (as f64 bits)",
            got.len(),
            f64::from_bits(got[i]),
            f64::from_bits(expected[i])
        );
    }
}

/// The history of the elements of `elements` (global ids) cut from a whole `history` of bodies
/// over `bodies`.
fn part(
    history: &MaterialHistory,
    bodies: &[Range<usize>],
    elements: &Range<usize>,
) -> MaterialHistory {
    let bodies = history
        .bodies
        .iter()
        .zip(bodies)
        .map(|(h, body)| {
            h.as_ref().map(|h| {
                assert_eq!(h.held(), 0..body.len(), "one process holds every element");
                h.part(body_part(body, elements))
            })
        })
        .collect();
    MaterialHistory { bodies }
}

/// Each rank's material history and shape-function gradients hold exactly its own elements of
/// each body, and the ranks' histories together hold every element once.
fn holds_own_elements_only(bits: &[Bits], path: &Path) {
    for (rank, r) in bits.iter().enumerate() {
        assert_eq!(
            r.kept,
            r.elements,
            "{}: rank {rank}'s gradients",
            path.display()
        );
        // Contact reads its surfaces' layers every step: the connectivity stays whole there.
        let connected = if r.most_in_contact > 0.0 || bits.len() == 1 {
            r.connected.clone()
        } else {
            r.elements.clone()
        };
        assert_eq!(
            r.connected,
            connected,
            "{}: rank {rank}'s connectivity",
            path.display()
        );
        // The model's nodal arrays are kept with the connectivity: for the nodes the
        // integrator stores.
        let held = match r.connected.len() < r.bodies.iter().map(|b| b.end).max().unwrap_or(0) {
            true => r.integrated,
            false => r.node_count,
        };
        assert_eq!(
            r.nodes_held,
            [held; 3],
            "{}: rank {rank}'s reference coordinates, masses and initial velocities",
            path.display()
        );
    }
    for (b, body) in bits[0].bodies.iter().enumerate() {
        let mut covered = 0;
        for (rank, r) in bits.iter().enumerate() {
            let Some(h) = &r.material.bodies[b] else {
                continue;
            };
            let own = body_part(body, &r.elements);
            assert_eq!(h.held(), own, "{}: rank {rank}, body {b}", path.display());
            assert_eq!(h.values.len(), own.len() * h.state_len);
            covered += own.len();
        }
        if bits[0].material.bodies[b].is_some() {
            assert_eq!(covered, body.len(), "{}: body {b}", path.display());
        }
    }
}

/// Runs the case alone and on each count of `ranks`; with `contact`, the bodies must touch.
fn check(path: &str, steps: usize, ranks: &[usize], contact: bool) {
    let path = case(path);
    let alone = run(&path, steps, None);
    assert_eq!(
        alone.most_in_contact > 0.0,
        contact,
        "{}: contact within the steps run",
        path.display()
    );
    assert!(
        alone.state.iter().any(|&b| b != 0),
        "{}: the run must move something",
        path.display()
    );
    assert!(
        !alone.snapshots.is_empty(),
        "{}: the run keeps snapshots",
        path.display()
    );
    for &n in ranks {
        let bits = run_ranks(&path, steps, n);
        for (rank, b) in bits.iter().enumerate() {
            let what = format!("{} on {n} ranks, rank {rank}", path.display());
            same(&b.history, &alone.history, &format!("{what}: history"));
            same(&b.state, &alone.state, &format!("{what}: final state"));
            same(
                &material_history_bits(&b.material),
                &material_history_bits(&part(&alone.material, &b.bodies, &b.elements)),
                &format!("{what}: material history"),
            );
            same(
                &b.snapshots,
                &alone.snapshots,
                &format!("{what}: snapshots"),
            );
        }
        holds_own_elements_only(&bits, &path);
        // Ranks above the first send contributions to their lower neighbour's nodes: the
        // exchange is exercised, not bypassed (by every rank that has elements, where two
        // ranks have; a rank alone with elements shares no node).
        let with_elements = bits.iter().filter(|b| !b.elements.is_empty());
        assert!(
            with_elements.clone().count() < 2 || with_elements.clone().all(|b| b.sent > 0),
            "{}: every rank sends",
            path.display()
        );
    }
}

#[test]
fn confined_column_on_two_and_three_ranks_is_bitwise_the_one_process_run() {
    check("cases/examples/confined-column.yaml", 200, &[2, 3], false);
}

#[test]
fn head_on_spheres_in_contact_on_two_ranks_are_bitwise_the_one_process_run() {
    check("cases/contact/spheres-headon.yaml", 150, &[2, 4], true);
}

#[test]
fn the_microplane_drop_test_on_two_ranks_is_bitwise_the_one_process_run() {
    // 60 steps of 4.4 us: the hammer, 0.1 mm above the beam at 2 m/s, is on it from step 11.
    check("cases/beam/drop-2ms.yaml", 60, &[2], true);
}

#[test]
fn the_mirrored_drop_test_with_its_symmetry_planes_on_two_ranks_is_bitwise_the_one_process_run() {
    // The symmetry planes hold nodes of every rank, each rank those it stores.
    check("cases/beam/drop-2ms-mirrored.yaml", 60, &[2], true);
}

#[test]
fn gravity_and_a_load_spread_over_the_ranks_are_bitwise_the_one_process_run() {
    // A rank applies the load to the nodes it stores; the loaded top face crosses every rank's
    // slab, and its nodes are neither probed nor prescribed (not exchanged).
    let scene = "name: loaded-cantilever
bodies:
  - name: beam
    mesh: { box: { origin: [0, 0, 0], size: [0.4, 0.1, 0.1], divisions: [16, 4, 4] } }
    material: { linear_elastic: { density: 2400, youngs_modulus: 30.0e9, poisson_ratio: 0.2 } }
gravity: [0, -9.81, 0]
boundary_conditions:
  - { name: clamp, body: beam, nodes: { plane: { point: [0, 0, 0], normal: [1, 0, 0] } }, motion: { fixed: [x, y, z] } }
loads:
  - { name: top, body: beam, nodes: { plane: { point: [0, 0.1, 0], normal: [0, 1, 0] } }, force_per_node: [0, -50.0, 20.0] }
probes:
  - { name: tip, body: beam, nodes: { plane: { point: [0.4, 0, 0], normal: [1, 0, 0] } }, quantity: displacement }
analysis:
  explicit: { end_time: 1.0e-3, safety: 0.6, history_interval: 1.0e-5 }
";
    check_scene_text("loaded-cantilever", scene, 200, &[2, 3]);
}

/// [`check`] of the scene `text`, written to a file `<name>.yaml` of its own folder.
fn check_scene_text(name: &str, text: &str, steps: usize, ranks: &[usize]) {
    let dir = std::env::temp_dir().join(format!("distributed-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.yaml"));
    std::fs::write(&path, text).unwrap();
    check(path.to_str().unwrap(), steps, ranks, false);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A model of fewer elements than one leaf of the energy sums: the second rank has no element and
/// no leaf (its empty range once took the first rank's leaf too, and the stored energy was
/// counted twice).
#[test]
fn a_model_smaller_than_one_leaf_on_two_ranks_is_bitwise_the_one_process_run() {
    let scene = "name: bar
bodies:
  - name: bar
    mesh: { box: { origin: [0, 0, 0], size: [1, 0.1, 0.1], divisions: [2, 1, 1] } }
    material: { linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 } }
boundary_conditions:
  - name: push
    body: bar
    nodes: { plane: { point: [0, 0, 0], normal: [1, 0, 0] } }
    motion: { velocity: { components: [x], value: { constant: 1.0 } } }
analysis: { explicit: { end_time: 1.0e-4 } }
";
    check_scene_text("bar", scene, 20, &[2]);
}

/// A pushed end face and a fixed one that cross every rank's slab (layers of 289 nodes, more than
/// a leaf): each rank integrates its own part of the faces, and the conditions' reactions,
/// gathered for the history rows, are summed in the one-process order on every rank.
#[test]
fn conditions_across_every_rank_give_the_one_process_reactions_bit_for_bit() {
    let scene = "name: faces
bodies:
  - name: block
    mesh: { box: { origin: [0, 0, 0], size: [0.4, 0.4, 0.3], divisions: [16, 16, 6] } }
    material: { linear_elastic: { density: 2300, youngs_modulus: 30.0e9, poisson_ratio: 0.2 } }
boundary_conditions:
  - name: push
    body: block
    nodes: { plane: { point: [0, 0, 0], normal: [1, 0, 0] } }
    motion: { velocity: { components: [x], value: { constant: 1.0 } } }
  - name: hold
    body: block
    nodes: { plane: { point: [0.4, 0, 0], normal: [1, 0, 0] } }
    motion: { fixed: [x, y, z] }
analysis: { explicit: { end_time: 1.0e-4 } }
";
    check_scene_text("faces", scene, 20, &[2, 3]);
}
