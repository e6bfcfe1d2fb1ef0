//! The checkpoint's byte layout: little-endian integers, `f64` as their raw bits (so a value
//! read back is the value written, NaN payloads and the sign of zero included), and the 64-bit
//! FNV-1a hash that checks the payload and identifies the inputs.

use nalgebra::Vector3;

/// FNV-1a over `bytes` with 64-bit offset basis and prime (Fowler, Noll, Vo; the parameters of
/// the IETF draft `draft-eastlake-fnv`): `h = (h ^ byte) * 0x100000001b3` from
/// `0xcbf29ce484222325`. Not cryptographic: it detects damage (a flipped byte changes it), not
/// tampering.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// Appends values to a byte buffer.
#[derive(Debug, Default)]
pub struct Writer {
    /// The bytes written so far.
    pub bytes: Vec<u8>,
}

impl Writer {
    /// A `u64`, little-endian.
    pub fn u64(&mut self, v: u64) {
        self.bytes.extend_from_slice(&v.to_le_bytes());
    }

    /// A `usize` as a `u64`.
    pub fn usize(&mut self, v: usize) {
        self.u64(v as u64);
    }

    /// A `u32`, little-endian.
    pub fn u32(&mut self, v: u32) {
        self.bytes.extend_from_slice(&v.to_le_bytes());
    }

    /// A `bool` as one byte.
    pub fn bool(&mut self, v: bool) {
        self.bytes.push(u8::from(v));
    }

    /// An `f64` as its raw bits.
    pub fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }

    /// An `Option<f64>`: a presence byte, then the value.
    pub fn opt_f64(&mut self, v: Option<f64>) {
        self.bool(v.is_some());
        if let Some(v) = v {
            self.f64(v);
        }
    }

    /// A length, then the values' raw bits.
    pub fn f64s(&mut self, v: &[f64]) {
        self.usize(v.len());
        v.iter().for_each(|&x| self.f64(x));
    }

    /// A length, then each `f32`'s raw bits.
    pub fn f32s(&mut self, v: &[f32]) {
        self.usize(v.len());
        for x in v {
            self.bytes.extend_from_slice(&x.to_bits().to_le_bytes());
        }
    }

    /// A length, then the values, little-endian.
    pub fn u32s(&mut self, v: &[u32]) {
        self.usize(v.len());
        v.iter().for_each(|&x| self.u32(x));
    }

    /// A length, then three components per vector.
    pub fn vectors(&mut self, v: &[Vector3<f64>]) {
        self.usize(v.len());
        for x in v {
            x.iter().for_each(|&c| self.f64(c));
        }
    }

    /// A length, then the UTF-8 bytes.
    pub fn str(&mut self, s: &str) {
        self.usize(s.len());
        self.bytes.extend_from_slice(s.as_bytes());
    }
}

/// Reads what a [`Writer`] wrote; every read past the end is an error saying what was being
/// read, not a panic.
#[derive(Debug)]
pub struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

/// A read that ran past the end of the bytes, or met a value that cannot be.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Short(pub String);

/// The result of one read.
pub type Read<T> = std::result::Result<T, Short>;

impl<'a> Reader<'a> {
    /// A reader at the start of `bytes`.
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, at: 0 }
    }

    /// Bytes not read yet.
    pub fn remaining(&self) -> usize {
        self.bytes.len() - self.at
    }

    fn take(&mut self, n: usize, what: &str) -> Read<&'a [u8]> {
        if self.remaining() < n {
            return Err(Short(format!(
                "{what}: {n} bytes needed at offset {}, {} left",
                self.at,
                self.remaining()
            )));
        }
        let out = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(out)
    }

    /// A `u64`.
    pub fn u64(&mut self, what: &str) -> Read<u64> {
        let b = self.take(8, what)?;
        Ok(u64::from_le_bytes(
            b.try_into().map_err(|_| Short(what.into()))?,
        ))
    }

    /// A `u32`.
    pub fn u32(&mut self, what: &str) -> Read<u32> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes(
            b.try_into().map_err(|_| Short(what.into()))?,
        ))
    }

    /// A `usize` written as a `u64`.
    pub fn usize(&mut self, what: &str) -> Read<usize> {
        let v = self.u64(what)?;
        usize::try_from(v).map_err(|_| Short(format!("{what}: {v} does not fit a usize")))
    }

    /// A length of items of `item_bytes` bytes each, checked against the bytes left so that a
    /// damaged length cannot ask for more memory than the file holds.
    fn len(&mut self, item_bytes: usize, what: &str) -> Read<usize> {
        let n = self.usize(what)?;
        if n.saturating_mul(item_bytes) > self.remaining() {
            return Err(Short(format!(
                "{what}: {n} items of {item_bytes} bytes, but {} bytes left",
                self.remaining()
            )));
        }
        Ok(n)
    }

    /// A `bool` byte (0 or 1).
    pub fn bool(&mut self, what: &str) -> Read<bool> {
        match self.take(1, what)?[0] {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(Short(format!("{what}: byte {b} is not a bool"))),
        }
    }

    /// An `f64` from its raw bits.
    pub fn f64(&mut self, what: &str) -> Read<f64> {
        Ok(f64::from_bits(self.u64(what)?))
    }

    /// An `Option<f64>`.
    pub fn opt_f64(&mut self, what: &str) -> Read<Option<f64>> {
        Ok(if self.bool(what)? {
            Some(self.f64(what)?)
        } else {
            None
        })
    }

    /// What [`Writer::f64s`] wrote.
    pub fn f64s(&mut self, what: &str) -> Read<Vec<f64>> {
        let n = self.len(8, what)?;
        (0..n).map(|_| self.f64(what)).collect()
    }

    /// What [`Writer::f32s`] wrote.
    pub fn f32s(&mut self, what: &str) -> Read<Vec<f32>> {
        let n = self.len(4, what)?;
        (0..n)
            .map(|_| Ok(f32::from_bits(self.u32(what)?)))
            .collect()
    }

    /// What [`Writer::u32s`] wrote.
    pub fn u32s(&mut self, what: &str) -> Read<Vec<u32>> {
        let n = self.len(4, what)?;
        (0..n).map(|_| self.u32(what)).collect()
    }

    /// What [`Writer::vectors`] wrote.
    pub fn vectors(&mut self, what: &str) -> Read<Vec<Vector3<f64>>> {
        let n = self.len(24, what)?;
        (0..n)
            .map(|_| {
                Ok(Vector3::new(
                    self.f64(what)?,
                    self.f64(what)?,
                    self.f64(what)?,
                ))
            })
            .collect()
    }

    /// The next `n` bytes as they are (a part another reader reads).
    pub fn part(&mut self, n: usize, what: &str) -> Read<&'a [u8]> {
        self.take(n, what)
    }

    /// What [`Writer::str`] wrote.
    pub fn str(&mut self, what: &str) -> Read<String> {
        let n = self.len(1, what)?;
        let b = self.take(n, what)?;
        String::from_utf8(b.to_vec()).map_err(|_| Short(format!("{what}: not UTF-8")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The published FNV-1a 64 test vectors (draft-eastlake-fnv, appendix C): "" and "a".
    #[test]
    fn fnv1a64_matches_the_published_vectors() {
        assert_eq!(fnv1a64(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x85944171f73967e8);
    }

    #[test]
    fn values_read_back_bit_for_bit_and_short_input_is_an_error() {
        let mut w = Writer::default();
        let odd = [
            -0.0,
            f64::from_bits(0x7ff8_0000_dead_beef),
            1e-310,
            0.1 + 0.2,
        ];
        w.f64s(&odd);
        w.str("stem");
        w.opt_f64(None);
        w.f32s(&[1.5, -0.0]);
        let mut r = Reader::new(&w.bytes);
        let back = r.f64s("v").unwrap();
        assert_eq!(
            back.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            odd.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
        );
        assert_eq!(r.str("s").unwrap(), "stem");
        assert_eq!(r.opt_f64("o").unwrap(), None);
        assert_eq!(r.f32s("f").unwrap()[1].to_bits(), (-0.0f32).to_bits());
        assert_eq!(r.remaining(), 0);
        let mut short = Reader::new(&w.bytes[..12]);
        assert!(short.f64s("v").unwrap_err().0.starts_with("v: 4 items"));
    }
}
