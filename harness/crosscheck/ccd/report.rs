//! The tables and the plot of the comparison for the report.

use super::{Agreement, Compared};
use crate::crosscheck::ccd_queries::{CcdQuery, QuerySource};
use crate::results::{MaterialPlot, RecordTable};
use crate::results::{PlotData, Series};

const SOURCES: [QuerySource; 3] = [QuerySource::Sphere, QuerySource::Beam, QuerySource::Random];

pub(super) fn agreement_table(compared: &[Compared]) -> RecordTable {
    let rows = SOURCES
        .iter()
        .map(|s| {
            let of: Vec<&Compared> = compared.iter().filter(|c| c.source == *s).collect();
            let n = |a: Agreement| of.iter().filter(|c| c.agreement == a).count();
            let dt: Vec<f64> = of
                .iter()
                .filter(|c| c.agreement == Agreement::BothHit)
                .filter_map(|c| Some((c.ours? - c.theirs?).abs()))
                .collect();
            let starting: Vec<&&Compared> = of
                .iter()
                .filter(|c| c.agreement == Agreement::StartsInContact)
                .collect();
            let median = median(&dt);
            vec![
                s.name().to_string(),
                of.len().to_string(),
                n(Agreement::BothNone).to_string(),
                n(Agreement::BothHit).to_string(),
                n(Agreement::Missed).to_string(),
                n(Agreement::Extra).to_string(),
                format!(
                    "{} ({} found by us at t = 0)",
                    starting.len(),
                    starting.iter().filter(|c| c.ours == Some(0.0)).count()
                ),
                format!("{median:.2e}"),
                format!("{:.2e}", dt.iter().cloned().fold(0.0, f64::max)),
            ]
        })
        .collect();
    RecordTable {
        title: "Vertex-face CCD: ours against ipctk".into(),
        head: [
            "queries from",
            "queries",
            "no impact (both)",
            "impact (both)",
            "ipctk only (missed by us)",
            "ours only",
            "starting within ipctk's tolerance",
            "median |toi difference|",
            "largest |toi difference|",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect(),
        rows,
        note: "Times of impact are step fractions in [0, 1]. ipctk's Tight-Inclusion is \
               conservative: a query it answers without impact has none, and its impact time is \
               a lower bound within its distance tolerance."
            .into(),
    }
}

fn median(v: &[f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s[s.len() / 2]
}

/// Every query the two answer differently, and the 10 largest time differences.
pub(super) fn disagreement_table(compared: &[Compared], queries: &[CcdQuery]) -> RecordTable {
    let mut idx: Vec<usize> = (0..compared.len())
        .filter(|&i| matches!(compared[i].agreement, Agreement::Missed | Agreement::Extra))
        .collect();
    let mut by_dt: Vec<usize> = (0..compared.len())
        .filter(|&i| compared[i].agreement == Agreement::BothHit)
        .collect();
    let dt = |i: usize| {
        let c = &compared[i];
        let both = "`BothHit` means both answers are a hit time";
        (c.ours.expect(both) - c.theirs.expect(both)).abs()
    };
    by_dt.sort_by(|&a, &b| dt(b).total_cmp(&dt(a)));
    idx.extend(by_dt.into_iter().take(10));
    let t = |x: Option<f64>| x.map_or("none".to_string(), |t| format!("{t:.9}"));
    let rows = idx
        .iter()
        .map(|&i| {
            let c = &compared[i];
            let size = queries[i]
                .points
                .iter()
                .flatten()
                .fold(0.0_f64, |m, x| m.max(x.abs()));
            vec![
                i.to_string(),
                c.source.name().to_string(),
                format!("{:?}", c.agreement).to_lowercase(),
                t(c.ours),
                t(c.theirs),
                format!("{:.3e}", c.min_distance),
                format!("{size:.3e}"),
            ]
        })
        .collect();
    RecordTable {
        title: "Queries answered differently, and the largest time differences".into(),
        head: [
            "query",
            "from",
            "kind",
            "ours",
            "ipctk",
            "smallest distance in the step (m)",
            "largest coordinate (m)",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect(),
        rows,
        note: "The smallest distance is computed here by sampling and golden-section search on \
               the exact point-triangle distance, independently of both CCD algorithms: a query \
               with an impact reaches 0 (to the sampling's accuracy)."
            .into(),
    }
}

/// Sorted |toi difference| of the queries both find an impact in, per source.
pub(super) fn toi_plot(compared: &[Compared]) -> MaterialPlot {
    let series = SOURCES
        .iter()
        .filter_map(|s| {
            let mut dt: Vec<f64> = compared
                .iter()
                .filter(|c| c.source == *s && c.agreement == Agreement::BothHit)
                .filter_map(|c| Some((c.ours? - c.theirs?).abs().max(1e-17)))
                .collect();
            if dt.is_empty() {
                return None;
            }
            dt.sort_by(f64::total_cmp);
            let n = dt.len() as f64;
            Some(Series {
                name: s.name().to_string(),
                x: (0..dt.len()).map(|i| (i as f64 + 1.0) / n).collect(),
                y: dt,
            })
        })
        .collect();
    MaterialPlot {
        plot: PlotData {
            title: "Time-of-impact differences, ours against ipctk (sorted)".into(),
            x_label: "fraction of the queries with an impact in both".into(),
            y_label: "|toi ours - toi ipctk| (step fractions; 1e-17 = equal)".into(),
            series,
            reference_lines: vec![],
            log_log: false,
        },
        log_x: false,
        log_y: true,
        boxes: vec![],
        dashed: vec![],
    }
}
