//! The tensile-stress driver of the relaxation `psi` (`RelaxationDriver::TensileStress`,
//! docs/MICROPLANE.md "Tension under lateral compression"): under a lateral compression the
//! thesis' driver `e_V` stays near zero while the tension grows, the shear planes are never
//! released, and they carry the tension to 1.45 `f_t` at `sigma_2 = -f_t`.

use super::directions::contract;
use super::{discontinuity, largest_principal, state, MicroplaneConcrete, RelaxationDriver, Sym};

impl MicroplaneConcrete {
    /// The relaxation's driver under [`RelaxationDriver::TensileStress`]: the larger of `e_V` and
    /// `o (1 - 2 nu) / 3 <sigma~_I> / E`, with `sigma~ = lambda tr(E) I + 2 mu E` the elastic
    /// stress and `o` the largest crack opening reached ([`discontinuity::opening`])
    /// (docs/MICROPLANE.md "Tension under lateral compression").
    ///
    /// `sigma~_I / E <= lambda tr(E) + 2 mu |E|` (the largest principal strain is at most the
    /// norm), so where that bound cannot pass `<e_V>` (the caller takes the positive part) the
    /// eigenvalue is not computed: in an unopened element (`o = 0`) never. On the
    /// elastic path (`|dev E| <= L`, `e_V <= L`) the driver is below `0.5 L`, so that path's
    /// limit still keeps `psi` at 1.
    #[inline(always)]
    pub(super) fn tensile_stress_driver(&self, strain: &Sym, e_v: f64, opening: f64) -> f64 {
        let (lambda, two_mu) = (self.effective_lambda, self.effective_two_mu);
        let trace = 3.0 * e_v;
        let bound = opening
            * self.equivalent_factor
            * (lambda * trace + two_mu * contract(strain, strain).sqrt())
            * (1.0 + 1e-9);
        if bound <= e_v.max(0.0) {
            return e_v;
        }
        let effective: Sym =
            std::array::from_fn(|i| two_mu * strain[i] + if i < 3 { lambda * trace } else { 0.0 });
        e_v.max(opening * self.equivalent_factor * largest_principal(&effective))
    }

    /// Advances the largest crack opening reached ([`state::OPENING`]) with the stress `sigma` of
    /// this update, under [`RelaxationDriver::TensileStress`]; the eigenvalue is spent only
    /// while the opening is below 1.
    #[inline(always)]
    pub(super) fn advance_opening(&self, header: &mut [f32], sigma: &Sym) {
        if self.parameters.relaxation_driver != RelaxationDriver::TensileStress {
            return;
        }
        let reached = header[state::OPENING] as f64;
        if reached >= 1.0 {
            return;
        }
        let s_i = largest_principal(sigma);
        let opening = discontinuity::opening(s_i, self.parameters.s_i_min);
        if opening > reached {
            header[state::OPENING] = opening as f32;
        }
    }
}
