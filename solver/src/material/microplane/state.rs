//! The history an element carries from step to step, as `f32` (damage and turning points need no
//! more digits, and the state of 21 planes then fits in 1.2 KB).
//!
//! Layout: a header `[V+ strain, V+ stress, V- strain, rate factor, s_I, psi, dilatancy, virgin
//! planes, elastic updates, opening]`, then per plane
//! `[D+ (2), D- (2), M (5), K (5)]`, each branch `(largest strain, stress there)` and each shear
//! component ending with its cyclic dissipation `Lambda` (5.104); with crack friction, the two
//! slips of each plane's friction sliders after the last plane; with the tensile boundary, the
//! last stress and the strain less the crack strains after them ([`BOUNDARY_HISTORY`]).

/// Number of values of the element header, before the first plane.
pub const HEADER: usize = 10;
/// Index of the volumetric-tension branch (5.19): largest volumetric strain reached, then the
/// volumetric stress there (Pa), two values.
pub const V_TENSION: usize = 0;
/// Index of the largest volumetric compressive strain reached (a magnitude), the turning point
/// of the volumetric compression law (5.18).
pub const V_COMPRESSION: usize = 2;
/// Index of the rate factor `F` (5.110) of the last update; 1 in a virgin element.
pub const RATE_FACTOR: usize = 3;
/// Index of the largest principal stress `s_I` of the last update (Pa).
pub const PRINCIPAL_STRESS: usize = 4;
/// The smallest relaxation `psi` reached: the relaxation is damage and never heals.
pub const RELAXATION: usize = 5;
/// The largest dilatant volumetric strain reached (MICROPLANE "Dilatancy"): it never shrinks.
pub const DILATANCY: usize = 6;
/// 1 while no update has taken the full plane path (every plane branch still unloaded, its
/// history zero), 0 after: the elastic path (`MicroplaneConcrete::update`) needs the first.
pub const VIRGIN_PLANES: usize = 7;
/// Number of updates that took the elastic path (exact in `f32` up to 2^24 updates).
pub const ELASTIC_UPDATES: usize = 8;
/// The largest crack opening `o(s_I)` reached (`discontinuity::opening`), which weighs the
/// tensile-stress driver of the relaxation (`RelaxationDriver::TensileStress`); 0 in a virgin
/// element, and never smaller later: a crack once opened in tension stays a crack.
pub const OPENING: usize = 9;
/// Number of values of each microplane after the header.
pub const PER_PLANE: usize = 14;
/// Number of values per plane of the crack-friction sliders (MICROPLANE "Crack friction"): the
/// slip of the `m` and `k` components. With crack friction they follow the planes, two per
/// plane in plane order; without it there are none.
pub const FRICTION_PER_PLANE: usize = 2;
/// Number of values after the planes (and their sliders) with the tensile boundary
/// (`crack_strain`): the stress `sigma` of the last update, then the strain less the crack
/// strains it saw, six components each, from which a plane's driver is carried into the next
/// update. Without the boundary there are none.
pub const BOUNDARY_HISTORY: usize = 12;
/// Offset in a plane of the deviatoric-tension branch `D+` (5.19): largest strain, stress (Pa).
pub const D_POSITIVE: usize = 0;
/// Offset in a plane of the deviatoric-compression branch `D-` (5.19): largest strain magnitude,
/// stress (Pa).
pub const D_NEGATIVE: usize = 2;
/// Offset in a plane of the shear component along `m` (5.20): positive and negative branches
/// (strain, stress each), then its cyclic dissipation `Lambda` (5.104); five values.
pub const M: usize = 4;
/// Offset in a plane of the shear component along `k`, laid out as [`M`]; five values.
pub const K: usize = 9;

/// The history of one element (see the module doc for the layout).
#[derive(Debug, Clone, PartialEq)]
pub struct MicroplaneState {
    /// The header then [`PER_PLANE`] values per plane, strains dimensionless and stresses in Pa.
    pub values: Vec<f32>,
}

impl MicroplaneState {
    /// A virgin history of `len` values: all zero but the rate factor and the relaxation `psi`,
    /// which start at 1.
    pub fn new(len: usize) -> Self {
        let mut values = vec![0.0; len];
        values[RATE_FACTOR] = 1.0;
        values[RELAXATION] = 1.0;
        values[VIRGIN_PLANES] = 1.0;
        Self { values }
    }

    /// Bytes of history per element.
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.values.as_slice())
    }

    /// Number of updates that took the elastic path.
    pub fn elastic_updates(&self) -> f64 {
        self.values[ELASTIC_UPDATES] as f64
    }

    /// Rate factor of the last update.
    pub fn rate_factor(&self) -> f64 {
        self.values[RATE_FACTOR] as f64
    }

    /// Largest principal stress of the last update.
    pub fn principal_stress(&self) -> f64 {
        self.values[PRINCIPAL_STRESS] as f64
    }

    /// Secant `s / e` at the turning point of every branch that has been loaded (volumetric
    /// tension, then per plane D+, D-, M+, M-, K+, K-, for the model's `planes` planes): each
    /// can only fall as damage grows.
    ///
    /// With `crack_strains` (a model with the tensile boundary) the D+ slots hold a plane's
    /// largest crack strain `y_max` and its crack strain `y` (`crack_strain`), not a turning
    /// point: `y / y_max` rises whenever a crack reopens, which is no healing. Their entry is
    /// then `1 / y_max`, which likewise can only fall as the plane's damage (its boundary's
    /// fall `F(y_max)`) grows.
    pub fn secants(&self, planes: usize, crack_strains: bool) -> Vec<f64> {
        let mut out = Vec::new();
        let mut push = |e: f32, s: f32| {
            out.push(if e > 0.0 {
                s as f64 / e as f64
            } else {
                f64::INFINITY
            })
        };
        push(self.values[V_TENSION], self.values[V_TENSION + 1]);
        for plane in self.values[HEADER..].chunks_exact(PER_PLANE).take(planes) {
            for start in [D_POSITIVE, D_NEGATIVE, M, M + 2, K, K + 2] {
                if crack_strains && start == D_POSITIVE {
                    push(plane[start], 1.0);
                } else {
                    push(plane[start], plane[start + 1]);
                }
            }
        }
        out
    }
}
