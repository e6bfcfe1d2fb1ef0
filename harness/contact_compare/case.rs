//! Catalogue cases that run no scene but a contact-solver comparison on stored problems
//! (`contact_problems:` instead of `scene:`), judged with `contact_problem_error` metrics.
//!
//! A missing problem folder skips the case with a message saying where the data is expected:
//! the problems are shared data beside the repository, not part of it.

use std::time::Instant;

use super::output::write_outputs;
use super::{
    collect_problem_files, compare, load_problems, same_tolerance, solver_entries, CompareSettings,
    Comparison,
};
use crate::catalogue::{CaseSpec, LoadedCase};
use crate::judge::judge;
use crate::measure::Measure;
use crate::results::{CaseResult, Status};
use crate::runner::RunOptions;

/// Checks the parts of a case that concern scenes and comparisons: exactly one of `scene` and
/// `contact_problems`, no sweep, variants or plots with a comparison, and metrics that measure
/// what the case runs. The message says what to change.
pub fn validate(spec: &CaseSpec) -> Result<(), String> {
    let comparison = match (&spec.scene, &spec.contact_problems) {
        (Some(_), Some(_)) => {
            return Err("the case has both `scene` and `contact_problems`: give one of them".into())
        }
        (None, None) => {
            return Err(
                "the case has no `scene` (nor `contact_problems`, to compare contact \
                        solvers on stored problems instead)"
                    .into(),
            )
        }
        (Some(_), None) => {
            if let Some(m) = spec
                .metrics
                .iter()
                .find(|m| is_comparison_measure(&m.measure))
            {
                return Err(format!(
                    "metric `{}` measures a contact-solver comparison: it needs a case with \
                     `contact_problems` instead of a scene",
                    m.name
                ));
            }
            return Ok(());
        }
        (None, Some(c)) => c,
    };
    let unsupported = [
        ("sweep", spec.sweep.is_some()),
        ("variants", !spec.variants.is_empty()),
        ("plots", !spec.plots.is_empty()),
    ];
    if let Some((key, _)) = unsupported.iter().find(|(_, given)| *given) {
        return Err(format!(
            "`{key}` needs a scene; a `contact_problems` case has none: remove `{key}`"
        ));
    }
    if comparison.tolerances.is_empty() || comparison.tolerances.iter().any(|t| !(*t > 0.0)) {
        return Err(format!(
            "contact_problems: tolerances must be positive and at least one, got {:?}",
            comparison.tolerances
        ));
    }
    if !(comparison.time_limit_s > 0.0) {
        return Err(format!(
            "contact_problems: time_limit_s must be positive, got {}",
            comparison.time_limit_s
        ));
    }
    let solvers: Vec<String> = solver_entries(&comparison.solvers)
        .map_err(|e| format!("contact_problems: {e}"))?
        .into_iter()
        .map(|s| s.name)
        .collect();
    for m in &spec.metrics {
        let Measure::ContactProblemError {
            solver, tolerance, ..
        } = &m.measure
        else {
            return Err(format!(
                "metric `{}` measures a scene run; a `contact_problems` case takes \
                 `contact_problem_error` metrics only",
                m.name
            ));
        };
        if !solvers.contains(solver) {
            return Err(format!(
                "metric `{}` names solver `{solver}`, which the comparison does not run ({})",
                m.name,
                solvers.join(", ")
            ));
        }
        if !comparison
            .tolerances
            .iter()
            .any(|t| same_tolerance(*t, *tolerance))
        {
            return Err(format!(
                "metric `{}` asks for tolerance {tolerance:e}, which the comparison does not \
                 run (tolerances {:?}): add it to `contact_problems.tolerances`",
                m.name, comparison.tolerances
            ));
        }
    }
    Ok(())
}

fn is_comparison_measure(m: &Measure) -> bool {
    matches!(m, Measure::ContactProblemError { .. })
}

/// The value of a comparison measure: the error `solver` reached at `tolerance` on each named
/// problem (infinite for a solve that returned nothing), reduced by the statistic. A problem the
/// comparison lacks is an error naming it.
pub fn measure_value(measure: &Measure, c: &Comparison) -> Result<f64, String> {
    let Measure::ContactProblemError {
        solver,
        problems,
        tolerance,
        statistic,
    } = measure
    else {
        return Err(format!(
            "{measure:?} does not measure a contact-solver comparison"
        ));
    };
    let names: Vec<String> = if problems.is_empty() {
        c.problem_names()
    } else {
        problems.clone()
    };
    let errors = names
        .iter()
        .map(|p| {
            if !c.problems.iter().any(|d| &d.name == p) {
                return Err(format!(
                    "problem `{p}` is not among the problems read ({})",
                    c.problem_names().join(", ")
                ));
            }
            c.row(p, solver, *tolerance)
                .map(|r| {
                    if r.error.is_nan() {
                        f64::INFINITY
                    } else {
                        r.error
                    }
                })
                .ok_or_else(|| format!("solver `{solver}` did not run on `{p}` at {tolerance:e}"))
        })
        .collect::<Result<Vec<f64>, String>>()?;
    Ok(statistic.of(&errors))
}

/// The folder as the case names it; or, when that does not exist and the path goes through a
/// `shared` folder, the same path below `$IMPACT_SHARED_DIR` (a checkout that does not sit beside
/// the shared data, such as CI's clone).
fn shared_folder(folder: &std::path::Path) -> Option<std::path::PathBuf> {
    if folder.is_dir() {
        return Some(folder.to_path_buf());
    }
    let root = std::env::var_os("IMPACT_SHARED_DIR")?;
    let components: Vec<_> = folder.components().collect();
    let at = components.iter().rposition(|c| c.as_os_str() == "shared")?;
    let mut path = std::path::PathBuf::from(root);
    components[at + 1..].iter().for_each(|c| path.push(c));
    path.is_dir().then_some(path)
}

/// Runs a `contact_problems` case: the comparison, its files under
/// `<output>/cases/<id>/contact-compare/`, and its metrics.
pub fn run_case(case: &LoadedCase, options: &RunOptions) -> CaseResult {
    let spec = &case.spec;
    let started = Instant::now();
    let mut result = crate::runner::unfinished_result(spec, "default");
    let Some(cp) = &spec.contact_problems else {
        result.message = Some("the case has neither a scene nor contact_problems".into());
        return result;
    };
    let Some(folder) = shared_folder(&cp.folder) else {
        result.status = Status::Skipped;
        result.message = Some(format!(
            "the contact problems are expected in `{}` (shared data: `shared/data/contact-problems` \
             beside the repository, see its README, or under `$IMPACT_SHARED_DIR`); that folder \
             does not exist, so the comparison did not run",
            cp.folder.display()
        ));
        return result;
    };
    let prepared = collect_problem_files(std::slice::from_ref(&folder))
        .and_then(|files| Ok((files, solver_entries(&cp.solvers)?)));
    let (files, solvers) = match prepared {
        Ok(p) => p,
        Err(e) => {
            result.message = Some(e);
            return result;
        }
    };
    let (problems, unreadable) = load_problems(&files);
    let settings = CompareSettings {
        tolerances: cp.tolerances.clone(),
        time_limit_s: cp.time_limit_s,
        ..CompareSettings::default()
    };
    let comparison = compare(&problems, unreadable, &solvers, &settings, &mut |_| {});
    let mut failures: Vec<String> = comparison
        .unreadable
        .iter()
        .map(|u| u.message.clone())
        .collect();
    let mut notes = vec![format!(
        "{} solver(s) on {} problem(s) at tolerances {:?}, {} s per solve",
        comparison.solvers.len(),
        comparison.problems.len(),
        comparison.tolerances,
        comparison.time_limit_s
    )];
    if let Some(dir) = &options.output_dir {
        let dir = dir
            .join("cases")
            .join(spec.id.replace('/', "__"))
            .join("contact-compare");
        match write_outputs(&dir, &comparison) {
            Ok(_) => notes.push(format!("tables and plots in {}", dir.display())),
            Err(e) => notes.push(format!("could not write {}: {e}", dir.display())),
        }
    }
    for m in &spec.metrics {
        let Some(reference) = &m.reference else {
            failures.push(format!(
                "metric `{}` has no reference: every metric needs one",
                m.name
            ));
            continue;
        };
        let outcome = reference
            .evaluate_for(None)
            .map_err(|e| format!("metric `{}`: reference: {e}", m.name))
            .and_then(|(r, source)| {
                measure_value(&m.measure, &comparison)
                    .map(|v| (v, r, source))
                    .map_err(|e| format!("metric `{}`: {e}", m.name))
            });
        match outcome {
            Ok((value, reference, source)) => {
                result
                    .metrics
                    .push(judge(m, value, reference, &source, &|_| None))
            }
            Err(e) => failures.push(e),
        }
    }
    result.contact_comparison = Some(comparison);
    result.wall_s = started.elapsed().as_secs_f64();
    let failed: Vec<String> = result
        .metrics
        .iter()
        .filter(|m| !m.pass)
        .map(|m| {
            format!(
                "`{}` = {:.6e} against {:.6e} (tolerance {:.3e})",
                m.name, m.value, m.reference, m.tolerance
            )
        })
        .collect();
    failures.extend(failed.iter().map(|f| format!("failed: {f}")));
    result.status = if failures.is_empty() {
        Status::Pass
    } else {
        Status::Fail
    };
    notes.splice(0..0, failures);
    result.message = Some(notes.join("; "));
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::catalogue::load_case;

    fn write_case(name: &str, body: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "impact-vv-contact-case-{name}-{}",
            std::process::id()
        ));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("case.yaml");
        std::fs::write(&path, body).unwrap();
        path
    }

    const METRIC: &str = "metrics:
  - name: gs_error
    measure: { contact_problem_error: { solver: gauss-seidel/exact, problems: [a], tolerance: 1.0e-8 } }
    reference: { analytic: zero }
    tolerance: { at_most: 1.0e-8 }
";

    #[test]
    fn a_case_needs_exactly_one_of_scene_and_contact_problems() {
        let none = write_case(
            "none",
            &format!("id: x\ndescription: d\ntier: nightly\n{METRIC}"),
        );
        let e = load_case(&none).unwrap_err().to_string();
        assert!(e.contains("case.yaml") && e.contains("no `scene`"), "{e}");

        let ok = write_case(
            "ok",
            &format!(
                "id: x\ndescription: d\ntier: nightly\ncontact_problems: {{ folder: data }}\n{METRIC}"
            ),
        );
        let case = load_case(&ok).unwrap();
        let cp = case.spec.contact_problems.as_ref().unwrap();
        assert_eq!(
            cp.folder,
            ok.parent().unwrap().join("data"),
            "relative to the case file"
        );
        assert_eq!(cp.tolerances, vec![1e-4, 1e-6, 1e-8]);

        let bad_tol = write_case(
            "tol",
            &format!(
                "id: x\ndescription: d\ntier: nightly\ncontact_problems: {{ folder: d, tolerances: [1.0e-4] }}\n{METRIC}"
            ),
        );
        let e = load_case(&bad_tol).unwrap_err().to_string();
        assert!(
            e.contains("tolerance 1e-8") && e.contains("gs_error"),
            "{e}"
        );

        let typo = write_case(
            "typo",
            &format!(
                "id: x\ndescription: d\ntier: nightly\ncontact_problems: {{ folder: d, time_limit: 3 }}\n{METRIC}"
            ),
        );
        let e = load_case(&typo).unwrap_err().to_string();
        assert!(e.contains("unknown field `time_limit`"), "{e}");

        let both = write_case(
            "both",
            &format!(
                "id: x\ndescription: d\ntier: nightly\ncontact_problems: {{ folder: d }}\n\
                 scene: {{ name: s, bodies: [], analysis: {{ static: {{}} }} }}\n{METRIC}"
            ),
        );
        let e = load_case(&both).unwrap_err().to_string();
        assert!(e.contains("both `scene` and `contact_problems`"), "{e}");
    }

    #[test]
    fn a_missing_folder_skips_the_case_saying_where_the_data_belongs() {
        let path = write_case(
            "missing",
            &format!(
                "id: x\ndescription: d\ntier: nightly\ncontact_problems: {{ folder: no/such/folder }}\n{METRIC}"
            ),
        );
        let case = load_case(&path).unwrap();
        let options = RunOptions {
            output_dir: None,
            time_limit_s: 1.0,
            parallel: false,
            stop: None,
        };
        let r = crate::runner::run_case(&case, None, &options);
        assert_eq!(r.status, Status::Skipped);
        let m = r.message.unwrap();
        assert!(
            m.contains("no/such/folder") && m.contains("shared/data/contact-problems"),
            "{m}"
        );
    }

    fn row(problem: &str, solver: &str, error: f64) -> crate::contact_compare::ComparisonRow {
        crate::contact_compare::ComparisonRow {
            problem: problem.into(),
            solver: solver.into(),
            tolerance: 1e-8,
            error,
            absolute_error: error,
            iterations: 1,
            outer_iterations: 1,
            seconds: 0.1,
            repeats: 1,
            status: "converged".into(),
            solved: error <= 1e-8,
            notes: vec![],
        }
    }

    #[test]
    fn the_measure_reduces_the_named_problems_and_names_a_missing_one() {
        let p = crate::contact_compare::test_problem(&[(0, 0, 1.0)], &[-1.0, 0.0, 0.0], &[0.1]);
        let c = Comparison {
            normalisation: String::new(),
            tolerances: vec![1e-8],
            time_limit_s: 1.0,
            solvers: vec!["gs".into()],
            problems: ["a", "b", "c"]
                .iter()
                .map(|n| crate::contact_compare::describe(&p, n, n))
                .collect(),
            unreadable: vec![],
            rows: vec![
                row("a", "gs", 1e-9),
                row("b", "gs", 4e-9),
                row("c", "gs", f64::NAN),
            ],
        };
        let measure = |problems: &[&str], statistic| Measure::ContactProblemError {
            solver: "gs".into(),
            problems: problems.iter().map(|s| s.to_string()).collect(),
            tolerance: 1e-8,
            statistic,
        };
        use crate::measure::Statistic;
        assert_eq!(
            measure_value(&measure(&["a", "b"], Statistic::Max), &c),
            Ok(4e-9)
        );
        assert_eq!(
            measure_value(&measure(&["a", "b"], Statistic::Min), &c),
            Ok(1e-9)
        );
        assert_eq!(
            measure_value(&measure(&["a", "b"], Statistic::Mean), &c),
            Ok(2.5e-9)
        );
        // A solve that returned nothing counts as an infinite error; empty means all problems.
        assert_eq!(
            measure_value(&measure(&[], Statistic::Max), &c),
            Ok(f64::INFINITY)
        );
        let e = measure_value(&measure(&["a", "zz"], Statistic::Max), &c).unwrap_err();
        assert!(e.contains("`zz`") && e.contains("a, b, c"), "{e}");
        let mut other = measure(&["a"], Statistic::Max);
        if let Measure::ContactProblemError { solver, .. } = &mut other {
            *solver = "conic".into();
        }
        assert!(measure_value(&other, &c).unwrap_err().contains("conic"));
    }

    #[test]
    fn a_case_on_a_folder_is_judged_and_an_unreadable_file_fails_it() {
        let path = write_case(
            "folder",
            "id: x\ndescription: d\ntier: nightly\n\
             contact_problems: { folder: data, tolerances: [1.0e-8], time_limit_s: 5, solvers: [gauss-seidel/exact] }\n\
             metrics:\n  - name: e\n    measure: { contact_problem_error: { solver: gauss-seidel/exact, tolerance: 1.0e-8 } }\n\
             \x20   reference: { analytic: zero }\n    tolerance: { at_most: 1.0e-8 }\n",
        );
        let data = path.parent().unwrap().join("data");
        std::fs::create_dir_all(&data).unwrap();
        // W = 2 I, q = (-1, 0.1, 0), mu = 0.5: the contact sticks with r = (0.5, -0.05, 0).
        let p = crate::contact_compare::test_problem(
            &[(0, 0, 2.0), (1, 1, 2.0), (2, 2, 2.0)],
            &[-1.0, 0.1, 0.0],
            &[0.5],
        );
        impact_solver::contact::problem_file::ProblemFile::from_problem(&p, vec![])
            .write(&data.join("one.json"))
            .unwrap();
        let case = load_case(&path).unwrap();
        let options = RunOptions {
            output_dir: None,
            time_limit_s: 1.0,
            parallel: false,
            stop: None,
        };
        let r = run_case(&case, &options);
        assert_eq!(r.status, Status::Pass, "{:?}", r.message);
        assert!(r.metrics[0].value <= 1e-8);
        let c = r.contact_comparison.as_ref().unwrap();
        assert_eq!((c.problems.len(), c.rows.len()), (1, 1));

        std::fs::write(data.join("zz-broken.json"), "[]").unwrap();
        let r = run_case(&case, &options);
        assert_eq!(r.status, Status::Fail);
        assert!(r.message.unwrap().contains("zz-broken.json"));
        std::fs::remove_dir_all(data).ok();
    }
}
