//! Which run of an experiment a metric measures, and picking its value and its target band
//! among the experiment's values.

use impact_solver::material::microplane::SphereRule;
use serde::{Deserialize, Serialize};

use super::{MaterialPointError, Quantity, Value};
use crate::catalogue::{CaseSpec, Tolerance};

/// What a `material_point` metric measures: a quantity of the experiment, and which of its runs
/// when it has several (element size, strain rate, sphere rule, cycle).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialMeasure {
    /// What to measure.
    pub quantity: Quantity,
    /// Element size (m) of a crack-band run.
    #[serde(default)]
    pub element_size: Option<f64>,
    /// Strain rate (1/s) of a rate-study run.
    #[serde(default)]
    pub rate: Option<f64>,
    /// Sphere rule of an isotropy run.
    #[serde(default)]
    pub rule: Option<SphereRule>,
    /// A cycle's name (`name#k` for its k-th repetition).
    #[serde(default)]
    pub cycle: Option<String>,
    /// Cycles run with the deviatoric trace term (true, the default) or without (false).
    #[serde(default)]
    pub deviatoric_trace_term: Option<bool>,
    /// Held lateral stress `sigma_22` (Pa) of a tension-compression run.
    #[serde(default)]
    pub lateral_stress: Option<f64>,
}

impl MaterialMeasure {
    /// The runs this measure selects.
    pub fn at(&self) -> Selector {
        Selector {
            element_size: self.element_size,
            rate: self.rate,
            rule: self.rule,
            cycle: self.cycle.clone(),
            deviatoric_trace_term: self.deviatoric_trace_term,
            lateral_stress: self.lateral_stress,
        }
    }
}

/// Which run of an experiment a value belongs to; in a measure, a field left out matches any.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Selector {
    /// Element size (m).
    pub element_size: Option<f64>,
    /// Strain rate (1/s).
    pub rate: Option<f64>,
    /// Microplane direction rule.
    pub rule: Option<SphereRule>,
    /// A cycle's name (`name#k` for its k-th repetition).
    pub cycle: Option<String>,
    /// With the deviatoric trace term of the homogenisation (cycles).
    pub deviatoric_trace_term: Option<bool>,
    /// Held lateral stress `sigma_22` (Pa).
    pub lateral_stress: Option<f64>,
}

pub(super) fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

impl Selector {
    /// Whether a value measured at `value` is selected: every field given here matches.
    pub fn selects(&self, value: &Selector) -> bool {
        let num = |want: Option<f64>, have: Option<f64>| match (want, have) {
            (None, _) => true,
            (Some(w), Some(h)) => close(w, h),
            (Some(_), None) => false,
        };
        num(self.element_size, value.element_size)
            && num(self.rate, value.rate)
            && num(self.lateral_stress, value.lateral_stress)
            && self.rule.is_none_or(|r| value.rule == Some(r))
            && self
                .cycle
                .as_ref()
                .is_none_or(|c| value.cycle.as_ref() == Some(c))
            && self
                .deviatoric_trace_term
                .is_none_or(|t| value.deviatoric_trace_term.unwrap_or(true) == t)
    }

    /// A short label, e.g. `h = 25 mm`, `rate 1e-3 /s`; empty when nothing is set.
    pub fn label(&self) -> String {
        let mut parts = Vec::new();
        if let Some(h) = self.element_size {
            parts.push(format!("h = {} mm", crate::report::format::num(h * 1e3)));
        }
        if let Some(r) = self.rate {
            parts.push(format!("rate {r:e} /s"));
        }
        if let Some(r) = self.rule {
            parts.push(rule_name(r).to_string());
        }
        if let Some(c) = &self.cycle {
            parts.push(format!("cycle {c}"));
        }
        if let Some(s) = self.lateral_stress {
            parts.push(format!(
                "sigma_22 = {} MPa",
                crate::report::format::num(s / 1e6)
            ));
        }
        match self.deviatoric_trace_term {
            // (The model's default is on since issue 16; off is the thesis' homogenisation.)
            Some(true) => parts.push("with trace term".into()),
            Some(false) => parts.push("thesis default (no trace term)".into()),
            None => {}
        }
        parts.join(", ")
    }
}

/// The name of a sphere rule as the parameter files spell it.
pub fn rule_name(r: SphereRule) -> &'static str {
    match r {
        SphereRule::BazantOh21 => "bazant_oh21",
        SphereRule::Bazant37 => "bazant37",
    }
}

/// What a `material_point` case measures: `{ material_point: { quantity, at } }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PointMeasure {
    /// The quantity and the run it is taken from.
    MaterialPoint(MaterialMeasure),
}

/// The value a measure selects among an experiment's values: exactly one must match.
pub fn select(measure: &MaterialMeasure, values: &[Value]) -> Result<f64, MaterialPointError> {
    let of_quantity: Vec<&Value> = values
        .iter()
        .filter(|v| v.quantity == measure.quantity)
        .collect();
    let chosen: Vec<&&Value> = of_quantity
        .iter()
        .filter(|v| measure.at().selects(&v.at))
        .collect();
    let available = || {
        of_quantity
            .iter()
            .map(|v| format!("`{}`", v.at.label()))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match chosen.as_slice() {
        [one] => Ok(one.value),
        [] if of_quantity.is_empty() => Err(MaterialPointError::NothingMeasured {
            quantity: measure.quantity.name(),
        }),
        [] => Err(MaterialPointError::NotAt {
            quantity: measure.quantity.name(),
            at: measure.at().label(),
            available: available(),
        }),
        _ => Err(MaterialPointError::Ambiguous {
            quantity: measure.quantity.name(),
            available: available(),
        }),
    }
}

/// The acceptance band of each metric, known before the run (reference and tolerance), so that
/// the plots can draw the targets.
#[derive(Debug, Clone, Default)]
pub struct Targets {
    entries: Vec<(MaterialMeasure, f64, [f64; 2])>,
}

impl Targets {
    pub(super) fn new(spec: &CaseSpec, measures: &[MaterialMeasure]) -> Self {
        let entries = spec
            .metrics
            .iter()
            .zip(measures)
            .filter_map(|(m, measure)| {
                let (r, _) = m.reference.as_ref()?.evaluate_for(None).ok()?;
                let band = match &m.tolerance {
                    Tolerance::Relative(t) => [r - t * r.abs(), r + t * r.abs()],
                    Tolerance::Absolute(t) => [r - t, r + t],
                    Tolerance::AtMost(t) => [f64::NEG_INFINITY, *t],
                    Tolerance::AtLeast(t) => [*t, f64::INFINITY],
                    Tolerance::AtLeastRatio(t) => [t * r, f64::INFINITY],
                    Tolerance::RelativeToPeak { .. } => return None,
                };
                Some((measure.clone(), r, band))
            })
            .collect();
        Targets { entries }
    }

    /// The band of the first metric on `quantity` whose selector selects `at`.
    pub fn band(&self, quantity: Quantity, at: &Selector) -> Option<[f64; 2]> {
        self.find(quantity, at).map(|e| e.2)
    }

    /// The reference value of the first metric on `quantity` whose selector selects `at`.
    pub fn reference(&self, quantity: Quantity, at: &Selector) -> Option<f64> {
        self.find(quantity, at).map(|e| e.1)
    }

    fn find(&self, quantity: Quantity, at: &Selector) -> Option<&(MaterialMeasure, f64, [f64; 2])> {
        self.entries
            .iter()
            .find(|(m, _, _)| m.quantity == quantity && m.at().selects(at))
    }
}
