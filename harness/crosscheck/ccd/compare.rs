//! Comparing our answer to each query with ipctk's.

use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::min_distance;
use crate::crosscheck::ccd_queries::{our_time_of_impact, CcdQuery, QuerySource};
use crate::crosscheck::error::CrosscheckError;

/// How one query's answers compare.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Agreement {
    /// Neither finds an impact in the step.
    BothNone,
    /// Both find one (their times are compared).
    BothHit,
    /// ipctk finds an impact in the step, we find none: must not happen.
    Missed,
    /// We find an impact ipctk does not.
    Extra,
    /// The point starts within ipctk's tolerance of the triangle: ipctk answers "in contact at
    /// t = 0" without running its CCD (see `ipctk_ccd.py`), so the query is no test of either;
    /// counted apart, with our answer.
    StartsInContact,
}

/// One query compared.
#[derive(Debug, Clone, Copy)]
pub struct Compared {
    /// Where the query comes from.
    pub source: QuerySource,
    /// How the two answers compare.
    pub agreement: Agreement,
    /// Our time of impact as a step fraction in `[0, 1]`; `None`: no impact.
    pub ours: Option<f64>,
    /// ipctk's time of impact as a step fraction; `None`: no impact.
    pub theirs: Option<f64>,
    /// Smallest distance between the point and the triangle over the step (m).
    pub min_distance: f64,
}

/// Compares our answers with ipctk's (`hit`, `toi` arrays of its answer).
pub fn compare(
    queries: &[CcdQuery],
    answer: &Value,
    tolerance: f64,
) -> Result<Vec<Compared>, CrosscheckError> {
    let hits = answer["hit"].as_array().ok_or(ipctk_field("hit"))?;
    let tois = answer["toi"].as_array().ok_or(ipctk_field("toi"))?;
    let initial = answer["initial"].as_array().ok_or(ipctk_field("initial"))?;
    if [hits.len(), tois.len(), initial.len()]
        .iter()
        .any(|&n| n != queries.len())
    {
        return Err(CrosscheckError::AnswerCount {
            answered: hits.len(),
            queries: queries.len(),
        });
    }
    Ok(queries
        .iter()
        .zip(hits.iter().zip(tois).zip(initial))
        .map(|(q, ((h, t), i))| {
            let theirs = (h.as_u64() == Some(1)).then(|| t.as_f64().unwrap_or(f64::NAN));
            let ours = our_time_of_impact(q, tolerance);
            let agreement = match (ours.is_some(), theirs.is_some()) {
                _ if i.as_u64() == Some(1) => Agreement::StartsInContact,
                (false, false) => Agreement::BothNone,
                (true, true) => Agreement::BothHit,
                (false, true) => Agreement::Missed,
                (true, false) => Agreement::Extra,
            };
            Compared {
                source: q.source,
                agreement,
                ours,
                theirs,
                min_distance: min_distance(q),
            }
        })
        .collect())
}

/// A list missing from ipctk's answer.
fn ipctk_field(field: &'static str) -> CrosscheckError {
    CrosscheckError::AnswerField {
        script: "ipctk",
        field,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn answers_are_compared_one_sidedly() {
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let q = |p0: [f64; 3], p1: [f64; 3]| CcdQuery {
            source: QuerySource::Random,
            points: [p0, tri[0], tri[1], tri[2], p1, tri[0], tri[1], tri[2]],
        };
        let queries = [
            q([0.2, 0.2, 1.0], [0.2, 0.2, -1.0]),
            q([2.0, 2.0, 1.0], [2.0, 2.0, -1.0]),
        ];
        let answer = json!({"hit": [1, 1], "toi": [0.4999995, 0.3], "initial": [0, 0]});
        let c = compare(&queries, &answer, 1e-9).unwrap();
        assert_eq!(c[0].agreement, Agreement::BothHit);
        assert!((c[0].ours.unwrap() - 0.5).abs() < 1e-15);
        assert_eq!(c[1].agreement, Agreement::Missed);
        let starting = json!({"hit": [1, 1], "toi": [0.0, 0.0], "initial": [1, 0]});
        let c = compare(&queries, &starting, 1e-9).unwrap();
        assert_eq!(c[0].agreement, Agreement::StartsInContact);
        assert_eq!(c[1].agreement, Agreement::Missed);
        let short = json!({"hit": [1], "toi": [0.5], "initial": [0]});
        assert!(compare(&queries, &short, 1e-9)
            .unwrap_err()
            .to_string()
            .contains("answered 1"));
    }
}
