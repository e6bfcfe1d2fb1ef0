//! The bound on the growth of the dilatant strain by the planes' dissipation (MICROPLANE
//! "Dilatancy"): the second law lets the shift of the volumetric law store no more energy than
//! the planes dissipate.

use super::MicroplaneConcrete;

impl MicroplaneConcrete {
    /// The dilatant strain the next update may use, given the one used now (`reached`), the
    /// one the planes ask for (`wanted`, larger), the volumetric strain `e_V` of this update, the
    /// largest compressive strain the volumetric law has reached (`compressed`) and the energy
    /// per unit volume the planes dissipated in this update (`dissipated()`, J/m^3, evaluated
    /// only where the shift reaches volumetric compression).
    ///
    /// The dilatant strain shifts the volumetric law's argument (MICROPLANE "Dilatancy"): a growth
    /// `d` at fixed `e_V` raises the law's stored energy by `3 int p dx` over the compressive part
    /// of the shift, energy that no work put in. The second law allows that only out of what the
    /// planes dissipate, so the growth is capped where `3 p d` reaches `dissipated` (with `p` the
    /// pressure at the end of the shift, the largest on it: the cap never lets the stored energy
    /// grow by more). Under small confinement (uniaxial compression) the planes' dissipation pays
    /// for the whole growth; under the GPa pressures of a penetrator it pays for little, and
    /// without the cap a sheared element pushed its neighbours apart with energy it never stored.
    #[inline(always)]
    pub(super) fn admissible_dilatancy(
        &self,
        reached: f64,
        wanted: f64,
        e_v: f64,
        compressed: f64,
        dissipated: impl FnOnce() -> f64,
    ) -> f64 {
        // Compressive strain of the volumetric law at the start and at the end of the shift.
        let (x0, x1) = (reached - e_v, wanted - e_v);
        if x1 <= 0.0 {
            return wanted;
        }
        let pressure = self.volumetric_pressure(x1, compressed);
        if pressure <= 0.0 {
            return wanted;
        }
        // The part of the shift in volumetric tension (x < 0) stores nothing.
        let free = (-x0).max(0.0);
        (reached + free + dissipated().max(0.0) / (3.0 * pressure)).min(wanted)
    }
}
