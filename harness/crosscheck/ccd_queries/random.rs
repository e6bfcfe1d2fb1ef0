//! Random queries built to be hard: constructed contacts and near misses, endpoint, parallel,
//! box and sliver families. The generator lives in `impact-references`
//! (`references/queries/hard.rs`), where the solver's CCD tests draw from it too; the family
//! mix, the arithmetic and the order of the draws are ipctk's cache keys, so they stay as they
//! were when the cache was made.

use impact_references::queries::{queries, CROSSCHECK_MIX};

pub use impact_references::queries::Family as RandomFamily;

use super::{CcdQuery, QuerySource};

/// The family of query `i`: [`CROSSCHECK_MIX`], a fixed cycle of 20 that gives 8 constructed,
/// 2 endpoint, 3 parallel, 4 box and 3 sliver queries, interleaved so that any prefix holds a
/// mix.
pub fn random_family(i: usize) -> RandomFamily {
    CROSSCHECK_MIX[i % CROSSCHECK_MIX.len()]
}

/// `n` random queries, deterministic for a `seed`, mixed so that about half are hits and many
/// are hard: query `i` belongs to family [`random_family`]`(i)`, described in
/// `impact_references::queries::hard`.
pub fn random_queries(n: usize, seed: u64) -> Vec<CcdQuery> {
    queries(&CROSSCHECK_MIX, n, seed)
        .map(|(_, q)| CcdQuery {
            source: QuerySource::Random,
            points: q.points(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::our_time_of_impact;
    use super::*;
    use impact_references::queries::direction;
    use impact_references::queries::hard::{inside_weights, lerp, moving_triangle, through};
    use impact_solver::rng::SplitMix64;

    #[test]
    fn random_queries_are_deterministic_and_about_half_hits() {
        let a = random_queries(2000, 42);
        let b = random_queries(2000, 42);
        assert!(a.iter().zip(&b).all(|(x, y)| x.key() == y.key()));
        assert_ne!(random_queries(10, 43)[0].key(), a[0].key());
        let hits = a
            .iter()
            .filter(|q| our_time_of_impact(q, 1e-9).is_some())
            .count();
        let fraction = hits as f64 / a.len() as f64;
        let by_family = |f: RandomFamily| {
            let (n, h) = a
                .iter()
                .enumerate()
                .filter(|(i, _)| random_family(*i) == f)
                .fold((0, 0), |(n, h), (_, q)| {
                    (
                        n + 1,
                        h + usize::from(our_time_of_impact(q, 1e-9).is_some()),
                    )
                });
            format!("{f:?} {h}/{n}")
        };
        eprintln!(
            "hit fraction {fraction:.3}: {}",
            [
                RandomFamily::Constructed,
                RandomFamily::Endpoint,
                RandomFamily::Parallel,
                RandomFamily::Box,
                RandomFamily::Sliver
            ]
            .map(by_family)
            .join(", ")
        );
        assert!((0.2..=0.8).contains(&fraction), "hit fraction {fraction}");
    }

    #[test]
    fn a_constructed_hit_well_inside_is_found_at_its_time() {
        let mut rng = SplitMix64::new(5);
        let mut checked = 0;
        for _ in 0..200 {
            let (t0, t1, s) = moving_triangle(&mut rng);
            let t_star = rng.uniform(0.05, 0.95);
            let w = inside_weights(&mut rng);
            // Crossing the plane steeply: along the normal at t*, plus a tangential part.
            let at = lerp(&t0, &t1, t_star);
            let normal = (at[1] - at[0]).cross(&(at[2] - at[0])).normalize();
            let d = (normal * 0.5 + direction(&mut rng) * 0.2) * s;
            let q = CcdQuery {
                source: QuerySource::Random,
                points: through(&t0, &t1, t_star, w, d).points(),
            };
            // The node may meet the deforming triangle earlier at another root; the
            // construction's contact is the answer when it is the first.
            let t = our_time_of_impact(&q, 1e-9).expect("a hit well inside is found");
            if t < t_star - 1e-6 {
                continue;
            }
            assert!((t - t_star).abs() < 1e-9, "t {t} against t* {t_star}");
            checked += 1;
        }
        assert!(checked > 150, "{checked}");
    }
}
