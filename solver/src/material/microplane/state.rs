//! The history an element carries from step to step, as `f32` (damage and turning points need no
//! more digits, and the state of 21 planes then fits in 1.2 KB).
//!
//! Layout: a header `[V+ strain, V+ stress, V- strain, rate factor, s_I, psi, dilatancy]`, then per
//! plane
//! `[D+ (2), D- (2), M (5), K (5)]`, each branch `(largest strain, stress there)` and each shear
//! component ending with its cyclic dissipation `Lambda` (5.104).

pub const HEADER: usize = 7;
pub const V_TENSION: usize = 0;
pub const V_COMPRESSION: usize = 2;
pub const RATE_FACTOR: usize = 3;
pub const PRINCIPAL_STRESS: usize = 4;
/// The smallest relaxation `psi` reached: the relaxation is damage and never heals.
pub const RELAXATION: usize = 5;
/// The largest dilatant volumetric strain reached (MICROPLANE "Dilatancy"): it never shrinks.
pub const DILATANCY: usize = 6;
pub const PER_PLANE: usize = 14;
pub const D_POSITIVE: usize = 0;
pub const D_NEGATIVE: usize = 2;
pub const M: usize = 4;
pub const K: usize = 9;

/// The history of one element (see the module doc for the layout).
#[derive(Debug, Clone, PartialEq)]
pub struct MicroplaneState {
    pub values: Vec<f32>,
}

impl MicroplaneState {
    pub fn new(len: usize) -> Self {
        let mut values = vec![0.0; len];
        values[RATE_FACTOR] = 1.0;
        values[RELAXATION] = 1.0;
        Self { values }
    }

    /// Bytes of history per element.
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.values.as_slice())
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
    /// tension, then per plane D+, D-, M+, M-, K+, K-): each can only fall as damage grows.
    pub fn secants(&self) -> Vec<f64> {
        let mut out = Vec::new();
        let mut push = |e: f32, s: f32| {
            out.push(if e > 0.0 {
                s as f64 / e as f64
            } else {
                f64::INFINITY
            })
        };
        push(self.values[V_TENSION], self.values[V_TENSION + 1]);
        for plane in self.values[HEADER..].chunks_exact(PER_PLANE) {
            for start in [D_POSITIVE, D_NEGATIVE, M, M + 2, K, K + 2] {
                push(plane[start], plane[start + 1]);
            }
        }
        out
    }
}
