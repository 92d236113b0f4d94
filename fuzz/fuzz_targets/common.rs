//! Shared input decoding for the fuzz targets: any byte string becomes a
//! parameter set and a stream of samples, every f32 bit pattern included.

use breakaway::Params;

/// Reads little-endian words from the fuzzer's bytes.
pub struct Words<'a>(pub &'a [u8]);

impl Words<'_> {
    pub fn u32(&mut self) -> Option<u32> {
        let (head, rest) = self.0.split_first_chunk::<4>()?;
        self.0 = rest;
        Some(u32::from_le_bytes(*head))
    }
    pub fn f32(&mut self) -> Option<f32> {
        self.u32().map(f32::from_bits)
    }
    /// A parameter set: any bits, so most sets are invalid and must be
    /// rejected; the rest exercise the whole valid range.
    pub fn params(&mut self) -> Option<Params> {
        Some(Params {
            fc: self.f32()?,
            fs: self.f32()?,
            v_stribeck: self.f32()?,
            delta: self.f32()?,
            sigma: self.f32()?,
            z_max: self.f32()?,
            epsilon: self.f32()?,
        })
    }
}
