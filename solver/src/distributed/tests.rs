use nalgebra::Vector3;

use super::*;
use crate::nodal::NodeField;

#[test]
fn element_ranges_cover_the_elements_in_order_and_nearly_equal() {
    for (elements, size) in [
        (10, 3),
        (3, 4),
        (21600, 2),
        (0, 2),
        (7, 1),
        (1000, 3),
        (1_008_000, 4),
    ] {
        let ranges = element_ranges(elements, size);
        assert_eq!(ranges.len(), size);
        assert_eq!(ranges[0].start, 0);
        assert_eq!(ranges[size - 1].end, elements);
        for pair in ranges.windows(2) {
            assert_eq!(
                pair[0].end, pair[1].start,
                "{elements} on {size}: consecutive"
            );
        }
        let (min, max) = (
            ranges.iter().map(|r| r.len()).min().unwrap(),
            ranges.iter().map(|r| r.len()).max().unwrap(),
        );
        assert!(
            max - min <= ELEMENT_LEAF + 1,
            "{elements} on {size}: {min}..{max}"
        );
        for r in &ranges[1..] {
            assert!(
                r.start % ELEMENT_LEAF == 0 || r.start == elements,
                "{elements} on {size}: {r:?} starts inside a block"
            );
        }
    }
}

#[test]
fn ranges_by_cost_give_each_rank_an_equal_share_of_the_cost_in_whole_blocks() {
    // A cheap body (elastic, cost 1) before a dear one (microplane, 22), as in the drop test.
    let cost = |e: usize| if e < 4000 { 1.0 } else { 22.0 };
    let elements = 30_000;
    let total: f64 = (0..elements).map(cost).sum();
    for size in [2, 3, 4] {
        let ranges = element_ranges_by_cost(elements, size, cost);
        assert_eq!((ranges[0].start, ranges[size - 1].end), (0, elements));
        for (r, range) in ranges.iter().enumerate() {
            let share: f64 = range.clone().map(cost).sum();
            assert!(
                (share - total / size as f64).abs() <= ELEMENT_LEAF as f64 * 22.0,
                "rank {r} of {size}: cost {share} of {total}"
            );
            assert!(
                range.start % ELEMENT_LEAF == 0,
                "{range:?} starts inside a block"
            );
        }
    }
}

/// A strip of tetrahedra over `nodes` node ids, element `e` on the strip's points `e..e + 4`,
/// with point `p` numbered `p / 2` when even and `nodes / 2 + p / 2` when odd: each half of the
/// strip numbers nodes in two quarters of the ids, so leaves straddle ranks.
fn wandering_strip(nodes: u32) -> Vec<[u32; 4]> {
    let id = |p: u32| (p % 2) * (nodes / 2) + p / 2;
    (0..nodes - 3)
        .map(|e| [0, 1, 2, 3].map(|k| id(e + k)))
        .collect()
}

#[test]
fn every_rank_holds_its_elements_nodes_and_each_leaf_has_one_rank_holding_it_whole() {
    let nodes = 1500u32;
    let tets = wandering_strip(nodes);
    for size in [2, 3] {
        let ranges = element_ranges(tets.len(), size);
        let plans: Vec<NodePlan> = (0..size)
            .map(|r| NodePlan::new(&tets, nodes as usize, &ranges, r, &[5, 700]))
            .collect();
        let active = |r: usize, a: usize| plans[r].active().iter().any(|run| run.contains(&a));
        let mut users = vec![std::collections::BTreeSet::new(); nodes as usize];
        for (r, range) in ranges.iter().enumerate() {
            for tet in &tets[range.clone()] {
                for &a in tet {
                    assert!(active(r, a as usize), "node {a} of rank {r}'s element");
                    users[a as usize].insert(r);
                }
            }
        }
        let exchanged = plans[0].exchanged();
        for (a, u) in users.iter().enumerate() {
            if u.len() != 1 {
                assert!(exchanged[a], "node {a} used by ranks {u:?}");
            }
        }
        assert!(
            exchanged[5] && exchanged[700],
            "replicated nodes are exchanged"
        );
        let mut owner = vec![None; (nodes as usize).div_ceil(NODE_LEAF)];
        for (r, plan) in plans.iter().enumerate() {
            assert_eq!(
                plan.exchanged(),
                exchanged,
                "every rank builds the same plan"
            );
            for &k in plan.my_leaves() {
                assert_eq!(owner[k as usize], None, "leaf {k} on two ranks");
                owner[k as usize] = Some(r);
                for a in plan.leaf_nodes(k) {
                    assert!(active(r, a), "node {a} of rank {r}'s leaf {k}");
                }
            }
            for a in 0..nodes as usize {
                let in_leaf = plan.my_leaves().contains(&((a / NODE_LEAF) as u32));
                let extra = plan.extra().iter().any(|run| run.contains(&a));
                assert_eq!(active(r, a), in_leaf || extra, "node {a} on rank {r}");
                assert!(!(in_leaf && extra), "node {a} twice on rank {r}");
            }
        }
        assert!(owner.iter().all(Option::is_some), "every leaf has a rank");
        // Consecutive elements of a strip: each cut between two ranges shares the three points
        // of the face between them.
        let shared = users.iter().filter(|u| u.len() > 1).count();
        assert_eq!(shared, 3 * (size - 1));
        assert!(plans.iter().all(|p| p.shared_nodes() == shared));
        // A split leaf: exchanged whole, though some of its nodes have one user.
        let split = (0..owner.len() as u32).any(|k| {
            let leaf = plans[0].leaf_nodes(k);
            leaf.clone().all(|a| exchanged[a]) && leaf.clone().any(|a| users[a].len() == 1)
        });
        assert!(
            split,
            "the wandering ids split a leaf (the case under test)"
        );
    }
}

#[test]
fn leaf_folds_and_node_gathers_give_every_rank_the_one_process_values() {
    let nodes = 1500u32;
    let tets = wandering_strip(nodes);
    let value = |a: usize| 1.0 / (1.0 + a as f64) + (a as f64).sin();
    let single = NodePlan::single(nodes as usize);
    let shares = |plan: &NodePlan| -> Vec<f64> {
        plan.my_leaves()
            .iter()
            .flat_map(|&k| {
                let leaf = plan.leaf_nodes(k);
                [leaf.clone().map(value).sum::<f64>(), leaf.len() as f64]
            })
            .collect()
    };
    // The one-process sums, written out: each block of NODE_LEAF ids folded, then the blocks in
    // order.
    let expected: Vec<f64> = (0..nodes as usize)
        .step_by(NODE_LEAF)
        .map(|start| {
            let leaf = start..(start + NODE_LEAF).min(nodes as usize);
            [leaf.clone().map(value).sum::<f64>(), leaf.len() as f64]
        })
        .fold(vec![0.0, 0.0], |acc, s| vec![acc[0] + s[0], acc[1] + s[1]]);
    assert_eq!(expected[1], nodes as f64);
    assert_eq!(
        single.fold(None, 2, &shares(&single))[0].to_bits(),
        expected[0].to_bits(),
        "one process"
    );
    for size in [2, 3] {
        let ranges = element_ranges(tets.len(), size);
        let results: Vec<(Vec<f64>, Vec<Vector3<f64>>)> = std::thread::scope(|s| {
            let handles: Vec<_> = ThreadGroup::new(size)
                .into_iter()
                .map(|comm| {
                    let (tets, ranges) = (&tets, &ranges);
                    s.spawn(move || {
                        let plan = NodePlan::new(tets, nodes as usize, ranges, comm.rank(), &[]);
                        let folded = plan.fold(Some(&comm), 2, &shares(&plan));
                        // Only the active nodes hold values before the gather.
                        let mut field = NodeField::filled(&plan.slots(), Vector3::repeat(f64::NAN));
                        for a in plan.active().iter().flat_map(Clone::clone) {
                            field[a] = Vector3::new(value(a), a as f64, -value(a));
                        }
                        (folded, plan.gather(&comm, &field))
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for (rank, (folded, field)) in results.iter().enumerate() {
            assert_eq!(
                folded.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                expected.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                "fold on rank {rank} of {size}"
            );
            for (a, v) in field.iter().enumerate() {
                assert_eq!(*v, Vector3::new(value(a), a as f64, -value(a)), "node {a}");
            }
        }
    }
}

/// Slabs of a box (cells numbered slab by slab, layers of 441 nodes): a node that only the two
/// lower ranks' elements share, or that only one rank uses, is integrated by those ranks alone;
/// a rank integrates another rank's node only where a leaf no rank holds whole (a cut inside it)
/// or the caller's replication asks for it.
#[test]
fn a_rank_integrates_the_nodes_its_elements_use_and_no_other_ranks_halo() {
    let mesh = crate::mesh::box_mesh(&crate::mesh::BoxSpec {
        origin: [0.0; 3],
        size: [1.0, 1.0, 0.3],
        divisions: [20, 20, 6],
        mirror: Vec::new(),
    });
    let (tets, nodes) = (&mesh.tets, mesh.nodes.len());
    let size = 3;
    let ranges = element_ranges(tets.len(), size);
    let replicated = [7u32];
    let plans: Vec<NodePlan> = (0..size)
        .map(|r| NodePlan::new(tets, nodes, &ranges, r, &replicated))
        .collect();
    let active = |r: usize, a: usize| plans[r].active().iter().any(|run| run.contains(&a));
    let mut users = vec![std::collections::BTreeSet::new(); nodes];
    for (r, range) in ranges.iter().enumerate() {
        for tet in &tets[range.clone()] {
            for &a in tet {
                users[a as usize].insert(r);
            }
        }
    }
    // The ranks that integrate each node by the rule: the span of its users, where the
    // spans of its leaf's nodes overlap; every rank for a replicated node or a split leaf.
    let span = |a: usize| {
        if replicated.contains(&(a as u32)) {
            (0, size - 1)
        } else {
            (*users[a].first().unwrap(), *users[a].last().unwrap())
        }
    };
    let mut halo_free = 0;
    for a in 0..nodes {
        let leaf = plans[0].leaf_nodes((a / NODE_LEAF) as u32);
        let lowest = leaf.clone().map(|b| span(b).0).max().unwrap();
        let highest = leaf.clone().map(|b| span(b).1).min().unwrap();
        let (first, last) = if lowest <= highest {
            span(a)
        } else {
            (0, size - 1)
        };
        for r in 0..size {
            assert_eq!(
                active(r, a),
                (first..=last).contains(&r),
                "node {a} (users {:?}) on rank {r}",
                users[a]
            );
        }
        halo_free += usize::from(users[a].len() == 2 && !active(size - 1, a));
    }
    assert!(
        halo_free > 0,
        "the top rank integrates no node that only the two lower ranks share (the case under test)"
    );
    let stored: Vec<usize> = plans.iter().map(|p| p.slots().stored()).collect();
    assert!(
        stored.iter().all(|&s| s < nodes * 2 / 3),
        "each of 3 ranks stores well under two thirds of {nodes} nodes: {stored:?}"
    );
}
