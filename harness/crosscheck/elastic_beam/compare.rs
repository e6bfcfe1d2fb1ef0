//! Comparing solutions: extrapolation to `h -> 0`, relative differences, and the table of every
//! solution against the reference.

use std::collections::BTreeMap;

use super::{BeamValues, ElasticBeamSpec};
use crate::results::RecordTable;

/// The two finest of `rows` (solutions on `levels`) extrapolated to `h -> 0` at order 1
/// (Richardson): `v = v_2 + (v_2 - v_1) / (r - 1)` with `r = h_1 / h_2` from the cells along x.
pub(super) fn extrapolate(
    what: &str,
    levels: &[[usize; 3]],
    rows: &[BeamValues],
) -> Option<BeamValues> {
    let n = rows.len();
    if n < 2 {
        return None;
    }
    let (c1, c2) = (levels[n - 2], levels[n - 1]);
    let r = c2[0] as f64 / c1[0] as f64;
    let (a, b) = (&rows[n - 2], &rows[n - 1]);
    let x = |v1: f64, v2: f64| v2 + (v2 - v1) / (r - 1.0);
    let map = |m1: &BTreeMap<String, f64>, m2: &BTreeMap<String, f64>| {
        m2.iter()
            .map(|(k, v2)| (k.clone(), x(m1[k], *v2)))
            .collect()
    };
    Some(BeamValues {
        label: format!("ours, {what}, extrapolated at order 1 from the two finest levels"),
        deflection: map(&a.deflection, &b.deflection),
        reaction: map(&a.reaction, &b.reaction),
        stiffness: x(a.stiffness, b.stiffness),
        elements: b.elements,
        seconds: a.seconds + b.seconds,
    })
}

/// Largest relative difference of `ours` from `reference` over the deflections, and over the
/// reactions.
pub fn differences(ours: &BeamValues, reference: &BeamValues) -> (f64, f64, f64) {
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    let max_over = |a: &BTreeMap<String, f64>, b: &BTreeMap<String, f64>| {
        b.iter()
            .map(|(k, r)| a.get(k).map_or(f64::INFINITY, |v| rel(*v, *r)))
            .fold(0.0, f64::max)
    };
    (
        max_over(&ours.deflection, &reference.deflection),
        max_over(&ours.reaction, &reference.reaction),
        rel(ours.stiffness, reference.stiffness),
    )
}

/// The table of every solution against the converged reference.
pub fn table(spec: &ElasticBeamSpec, reference: &BeamValues, rows: &[BeamValues]) -> RecordTable {
    let mut head = vec!["solution".to_string(), "elements".into(), "time (s)".into()];
    head.extend(
        spec.deflection_points
            .keys()
            .map(|k| format!("deflection {k} (mm)")),
    );
    head.extend(spec.supports.iter().map(|s| format!("{s} (kN)")));
    head.extend([
        "stiffness (MN/mm)".to_string(),
        "deflection diff.".into(),
        "reaction diff.".into(),
        "stiffness diff.".into(),
    ]);
    let pct = |x: f64| format!("{:+.2} %", 100.0 * x);
    let signed = |a: f64, b: f64| (a - b) / b.abs();
    let worst = |a: &BTreeMap<String, f64>, b: &BTreeMap<String, f64>| {
        b.iter()
            .map(|(k, r)| signed(a[k], *r))
            .fold(0.0_f64, |m, d| if d.abs() > m.abs() { d } else { m })
    };
    let body = std::iter::once(reference)
        .chain(rows)
        .map(|v| {
            let mut r = vec![
                v.label.clone(),
                v.elements.to_string(),
                format!("{:.1}", v.seconds),
            ];
            r.extend(v.deflection.values().map(|d| format!("{:.5}", d * 1e3)));
            r.extend(v.reaction.values().map(|f| format!("{:.3}", f * 1e-3)));
            r.push(format!("{:.4}", v.stiffness * 1e-9));
            r.push(pct(worst(&v.deflection, &reference.deflection)));
            r.push(pct(worst(&v.reaction, &reference.reaction)));
            r.push(pct(signed(v.stiffness, reference.stiffness)));
            r
        })
        .collect();
    RecordTable {
        title: "Deflection and support reactions at the prescribed plate displacement".into(),
        head,
        rows: body,
        note: "Differences are signed, relative to scikit-fem's converged value (the first row); \
               for several points or supports the largest in magnitude is shown. Reactions \
               converge like h (the singular edges of the plate and supports), so the coarse \
               levels of both codes are stiffer than the limit; the extrapolated rows remove the \
               leading error term."
            .into(),
    }
}
