//! `exp(-c x^m)` without `powf` or `exp` on the hot path: a table of quintic Hermite pieces over
//! binary sub-octaves of `x`.
//!
//! Every virgin microplane law is `g(x) = x exp(-x^m)` (5.19-5.20) with a calibrated, non-integer
//! `m`, and the cyclic shear damage is `exp(-1.2 lambda^1.1)` (5.104): through `powf` and `exp`
//! these were half the instructions of an update (docs/performance.md, "The microplane update").
//!
//! The pieces follow the floating-point representation of `x`: octave `[2^e, 2^(e+1))` is cut into
//! `2^bits` equal intervals (64 for `m <= 5.5`, twice as many per doubling of `m` beyond), so the
//! index is the exponent and the leading mantissa bits of `x`, and the local coordinate `t` in
//! `[0, 1)` is the rest of the mantissa, exactly. Each interval is relatively as wide as any
//! other (1/64 of its left end for `m <= 5.5`), which suits `x^m` on every
//! scale, including `x -> 0` where a uniform grid would meet the singular derivatives of a
//! non-integer power. On each interval the quintic matches value, slope and curvature at both
//! ends (quintic Hermite interpolation; error `w^6 max|f^(6)| / 46080` for width `w`). Below the
//! first octave `c x^m < 2^-60` and the function is 1 to double precision; above the last,
//! `c x^m > 750` and it is 0 (`exp(-750)` underflows).
//!
//! The error is measured, not only bounded: `tests::table_error_against_exp_and_powf` samples
//! every interval and asserts an absolute error below `1e-10` (the largest is `1.4e-11`, for the
//! thesis concrete's `n = 5.04`) for the calibrated exponents of the thesis concrete, the cyclic
//! damage and exponents from 0.5 to 20.

/// Intervals per octave are `2^bits`, `bits` at least this; more for steep exponents.
const SUB_OCTAVE_BITS: u32 = 6;
/// The exponent up to which [`SUB_OCTAVE_BITS`] keep the error below `1e-10`: the error grows
/// like `(m / 2^bits)^6`, so each doubling of `m` beyond it takes one more bit.
const EXPONENT_PER_BITS: f64 = 5.5;
/// `c x^m` below which the function is 1 to double precision.
const NEGLIGIBLE_EXPONENT: f64 = 1.0 / (1u64 << 60) as f64;
/// `c x^m` above which the function is 0 (`exp(-745)` is the smallest subnormal).
const UNDERFLOW_EXPONENT: f64 = 750.0;

/// `phi(x) = exp(-c x^m)` for `x >= 0`, tabulated (see the module documentation).
#[derive(Clone, PartialEq)]
pub struct DecayTable {
    /// `c` of `exp(-c x^m)`, positive.
    pub coefficient: f64,
    /// `m` of `exp(-c x^m)`, positive.
    pub exponent: f64,
    /// Biased IEEE exponent of the first octave, `1023 + e_lo`.
    first_octave: i64,
    /// Number of octaves tabulated.
    octaves: i64,
    /// Each octave has `2^sub_octave_bits` intervals.
    sub_octave_bits: u32,
    /// Mantissa bits below the interval index: the local coordinate, `52 - sub_octave_bits`.
    local_bits: u32,
    /// Per interval, the quintic's coefficients in the local coordinate `t`, lowest first.
    pieces: Vec<[f64; 6]>,
}

impl std::fmt::Debug for DecayTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DecayTable")
            .field("coefficient", &self.coefficient)
            .field("exponent", &self.exponent)
            .field("octaves", &self.octaves)
            .field("intervals", &self.pieces.len())
            .finish()
    }
}

impl DecayTable {
    /// The table of `exp(-coefficient x^exponent)`; both must be positive and finite.
    pub fn new(coefficient: f64, exponent: f64) -> Self {
        assert!(
            coefficient > 0.0 && coefficient.is_finite() && exponent > 0.0 && exponent.is_finite(),
            "exp(-c x^m) needs positive c and m, got c = {coefficient}, m = {exponent}"
        );
        // x where c x^m reaches a level: (level / c)^(1/m).
        let at = |level: f64| (level / coefficient).powf(1.0 / exponent);
        let lowest = at(NEGLIGIBLE_EXPONENT).log2().floor() as i64;
        let highest = at(UNDERFLOW_EXPONENT).log2().ceil() as i64;
        let octaves = highest - lowest;
        let sub_octave_bits =
            SUB_OCTAVE_BITS + (exponent / EXPONENT_PER_BITS).log2().ceil().clamp(0.0, 8.0) as u32;
        let per_octave = 1usize << sub_octave_bits;
        let mut pieces = Vec::with_capacity(octaves as usize * per_octave);
        for octave in lowest..highest {
            let start = (octave as f64).exp2();
            let width = start / per_octave as f64;
            for j in 0..per_octave {
                let x0 = start + j as f64 * width;
                pieces.push(quintic_hermite(
                    derivatives(x0, coefficient, exponent),
                    derivatives(x0 + width, coefficient, exponent),
                    width,
                ));
            }
        }
        Self {
            coefficient,
            exponent,
            first_octave: 1023 + lowest,
            octaves,
            sub_octave_bits,
            local_bits: 52 - sub_octave_bits,
            pieces,
        }
    }

    /// `exp(-c x^m)` at `x >= 0` (NaN gives 0 through the last branch; callers pass strains that
    /// are finite or let the NaN travel through the factor `x` of the law).
    #[inline(always)]
    pub fn eval(&self, x: f64) -> f64 {
        let bits = x.to_bits();
        let octave = (bits >> 52) as i64 - self.first_octave;
        if octave < 0 {
            return 1.0;
        }
        if octave >= self.octaves {
            return 0.0;
        }
        let mantissa = bits & ((1u64 << 52) - 1);
        let index =
            ((octave as usize) << self.sub_octave_bits) | (mantissa >> self.local_bits) as usize;
        let local = mantissa & ((1u64 << self.local_bits) - 1);
        let t = f64::from_bits((local << self.sub_octave_bits) | (1023u64 << 52)) - 1.0;
        let c = &self.pieces[index];
        c[0] + t * (c[1] + t * (c[2] + t * (c[3] + t * (c[4] + t * c[5]))))
    }

    /// [`DecayTable::eval`] of every lane of `x`, the same operations on each (bit for bit its
    /// values), written without branches so that the lanes run side by side: the index of a lane
    /// outside the table reads the first piece, and its value is then replaced by 1 or 0.
    #[inline(always)]
    pub fn eval_lanes<const N: usize>(&self, x: &[f64; N]) -> [f64; N] {
        let mut out = [0.0; N];
        let last = self.pieces.len() - 1;
        for p in 0..N {
            let bits = x[p].to_bits();
            let octave = (bits >> 52) as i64 - self.first_octave;
            let inside = octave >= 0 && octave < self.octaves;
            let mantissa = bits & ((1u64 << 52) - 1);
            let index = ((octave as usize) << self.sub_octave_bits)
                | (mantissa >> self.local_bits) as usize;
            let index = if inside { index } else { 0 };
            let local = mantissa & ((1u64 << self.local_bits) - 1);
            let t = f64::from_bits((local << self.sub_octave_bits) | (1023u64 << 52)) - 1.0;
            let c = &self.pieces[index.min(last)];
            let value = c[0] + t * (c[1] + t * (c[2] + t * (c[3] + t * (c[4] + t * c[5]))));
            out[p] = if octave < 0 {
                1.0
            } else if octave >= self.octaves {
                0.0
            } else {
                value
            };
        }
        out
    }

    /// `exp(-c x^m)` by `powf` and `exp`: the function the table stands for.
    pub fn exact(&self, x: f64) -> f64 {
        (-self.coefficient * x.powf(self.exponent)).exp()
    }

    /// Bytes of the table.
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.pieces.as_slice())
    }
}

/// `(phi, phi', phi'')` of `phi = exp(-u)`, `u = c x^m`: `phi' = -u' phi`,
/// `phi'' = (u'^2 - u'') phi`.
fn derivatives(x: f64, c: f64, m: f64) -> [f64; 3] {
    let u = c * x.powf(m);
    let du = c * m * x.powf(m - 1.0);
    let ddu = c * m * (m - 1.0) * x.powf(m - 2.0);
    let phi = (-u).exp();
    [phi, -du * phi, (du * du - ddu) * phi]
}

/// The quintic `p(t)`, `t` in `[0, 1]` over an interval of `width`, with the values, slopes and
/// curvatures `a` at its left end and `b` at its right end: `p = f0 + d0 t + s0 t^2 / 2 + c3 t^3
/// + c4 t^4 + c5 t^5`, the last three from the conditions at `t = 1`.
fn quintic_hermite(a: [f64; 3], b: [f64; 3], width: f64) -> [f64; 6] {
    let (f0, d0, s0) = (a[0], a[1] * width, a[2] * width * width);
    let (f1, d1, s1) = (b[0], b[1] * width, b[2] * width * width);
    let value = f1 - f0 - d0 - 0.5 * s0;
    let slope = d1 - d0 - s0;
    let curvature = s1 - s0;
    [
        f0,
        d0,
        0.5 * s0,
        10.0 * value - 4.0 * slope + 0.5 * curvature,
        -15.0 * value + 7.0 * slope - curvature,
        6.0 * value - 3.0 * slope + 0.5 * curvature,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Largest absolute error of the table over a sample of every interval (its ends, its middle
    /// and four points between) and of the ranges below and above it.
    fn largest_error(table: &DecayTable) -> (f64, f64) {
        let mut worst = (0.0, 0.0);
        let lowest = (table.first_octave - 1023) as f64;
        let per_octave = 1usize << table.sub_octave_bits;
        let mut check = |x: f64| {
            let error = (table.eval(x) - table.exact(x)).abs();
            if error > worst.0 {
                worst = (error, x);
            }
        };
        for octave in -1..=table.octaves {
            let start = (lowest + octave as f64).exp2();
            let width = start / per_octave as f64;
            for j in 0..per_octave {
                for t in [0.0, 0.13, 0.29, 0.5, 0.71, 0.87, 0.999] {
                    check(start + (j as f64 + t) * width);
                }
            }
        }
        check(0.0);
        worst
    }

    #[test]
    fn table_error_against_exp_and_powf() {
        // The thesis concrete's m, n, k (cases/materials/thesis-concrete.yaml), the cyclic shear
        // damage, integer exponents, and the ends of the calibration's exponent range.
        for (c, m) in [
            (1.0, 4.357788286638685),
            (1.0, 5.036789334890636),
            (1.0, 2.3393347216935663),
            (1.2, 1.1),
            (1.0, 1.0),
            (1.0, 2.0),
            (1.0, 0.5),
            (1.0, 20.0),
        ] {
            let table = DecayTable::new(c, m);
            let (error, at) = largest_error(&table);
            eprintln!(
                "exp(-{c} x^{m}): error {error:.2e} at x = {at:.4e}, {} KB",
                table.bytes() / 1024
            );
            assert!(
                error < 1e-10,
                "exp(-{c} x^{m}): error {error:.2e} at x = {at:.6e} ({} KB)",
                table.bytes() / 1024
            );
        }
    }

    #[test]
    fn ends_of_the_table() {
        let table = DecayTable::new(1.0, 3.0);
        assert_eq!(table.eval(0.0), 1.0);
        assert_eq!(table.eval(1e-30), 1.0);
        assert_eq!(table.eval(1e3), 0.0);
        assert_eq!(table.eval(f64::INFINITY), 0.0);
        assert!((table.eval(1.0) - (-1.0f64).exp()).abs() < 1e-15);
    }
}
