//! The state of a running simulation as bytes, and back: what a checkpoint holds.
//!
//! A checkpoint stores everything a run changes as it goes (the particles, every random
//! stream's position, which is a particle's id and impact count, the deposits and their
//! bounds, the tallies, the failures, the impact log, the time), never what its configuration
//! fixes: [`crate::Simulation::restore_state`] writes it over a simulation freshly built from
//! the same configuration, which then continues exactly as the saved one would have. The
//! encoding is little-endian, each list prefixed by its length, and begins with
//! [`STATE_VERSION`]; framing, checksums and files are the writer's business.

use glam::DVec3;

/// Version of the state encoding; a state of another version is refused. Version 5: particles
/// are 48-byte records flown in layer epochs, volumes are booked in integer quanta, and the
/// deposits of the epoch under way are kept with the cells they touched.
pub const STATE_VERSION: u32 = 6;

/// Why a saved state could not be restored.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum StateError {
    /// The bytes end before the state does.
    #[error("the saved state is truncated")]
    Truncated,
    /// Written by another version of the encoding.
    #[error("the saved state has version {found}, this program reads version {STATE_VERSION}")]
    Version {
        /// The version found.
        found: u32,
    },
    /// The state does not belong to this simulation's configuration.
    #[error("the saved state does not fit this scenario: {0}")]
    Mismatch(String),
    /// A value the state holds is impossible: non-finite, negative, outside the domain, beyond
    /// a counter's range.
    #[error("the saved state is invalid: {0}")]
    Invalid(String),
    /// Bytes are left after the state.
    #[error("the saved state has {0} bytes too many")]
    Trailing(usize),
}

/// Writes values as little-endian bytes.
#[derive(Debug, Default)]
pub(crate) struct Enc(pub Vec<u8>);

impl Enc {
    pub fn u8(&mut self, x: u8) {
        self.0.push(x);
    }
    pub fn bool(&mut self, x: bool) {
        self.0.push(u8::from(x));
    }
    pub fn u16(&mut self, x: u16) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub fn u32(&mut self, x: u32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub fn u128(&mut self, x: u128) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub fn usize(&mut self, x: usize) {
        self.u64(x as u64);
    }
    pub fn f32(&mut self, x: f32) {
        self.u32(x.to_bits());
    }
    pub fn f64(&mut self, x: f64) {
        self.u64(x.to_bits());
    }
    pub fn vec3(&mut self, v: DVec3) {
        v.to_array().into_iter().for_each(|x| self.f64(x));
    }
    pub fn str(&mut self, s: &str) {
        self.usize(s.len());
        self.0.extend_from_slice(s.as_bytes());
    }
    /// A list: its length, then each item.
    pub fn list<T>(&mut self, items: &[T], mut each: impl FnMut(&mut Enc, &T)) {
        self.usize(items.len());
        for x in items {
            each(self, x);
        }
    }
}

/// Reads what [`Enc`] wrote.
#[derive(Debug)]
pub(crate) struct Dec<'a> {
    bytes: &'a [u8],
}

impl<'a> Dec<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        Dec { bytes }
    }
    fn take<const N: usize>(&mut self) -> Result<[u8; N], StateError> {
        let (head, rest) = self.bytes.split_first_chunk::<N>().ok_or(StateError::Truncated)?;
        self.bytes = rest;
        Ok(*head)
    }
    pub fn u8(&mut self) -> Result<u8, StateError> {
        Ok(self.take::<1>()?[0])
    }
    pub fn bool(&mut self) -> Result<bool, StateError> {
        Ok(self.u8()? != 0)
    }
    pub fn u16(&mut self) -> Result<u16, StateError> {
        Ok(u16::from_le_bytes(self.take()?))
    }
    pub fn u32(&mut self) -> Result<u32, StateError> {
        Ok(u32::from_le_bytes(self.take()?))
    }
    pub fn u64(&mut self) -> Result<u64, StateError> {
        Ok(u64::from_le_bytes(self.take()?))
    }
    pub fn u128(&mut self) -> Result<u128, StateError> {
        Ok(u128::from_le_bytes(self.take()?))
    }
    pub fn usize(&mut self) -> Result<usize, StateError> {
        usize::try_from(self.u64()?).map_err(|_| StateError::Truncated)
    }
    pub fn f32(&mut self) -> Result<f32, StateError> {
        Ok(f32::from_bits(self.u32()?))
    }
    pub fn f64(&mut self) -> Result<f64, StateError> {
        Ok(f64::from_bits(self.u64()?))
    }
    pub fn vec3(&mut self) -> Result<DVec3, StateError> {
        Ok(DVec3::new(self.f64()?, self.f64()?, self.f64()?))
    }
    pub fn str(&mut self) -> Result<String, StateError> {
        let n = self.len(1)?;
        let (head, rest) = self.bytes.split_at(n);
        self.bytes = rest;
        String::from_utf8(head.to_vec()).map_err(|_| StateError::Mismatch("a name is not UTF-8".into()))
    }
    /// A list length, refused when the bytes left cannot hold that many items of at least
    /// `min_item` bytes each (so a corrupt length never allocates beyond the input's size).
    pub fn len(&mut self, min_item: usize) -> Result<usize, StateError> {
        let n = self.usize()?;
        if n.saturating_mul(min_item.max(1)) > self.bytes.len() && min_item > 0 {
            return Err(StateError::Truncated);
        }
        Ok(n)
    }
    /// A list of items of at least `min_item` bytes each.
    pub fn list<T>(
        &mut self,
        min_item: usize,
        mut each: impl FnMut(&mut Dec<'a>) -> Result<T, StateError>,
    ) -> Result<Vec<T>, StateError> {
        let n = self.len(min_item)?;
        (0..n).map(|_| each(self)).collect()
    }
    /// A list that must have `expected` items (a map over a surface's cells, say); `what`
    /// names it in the error.
    pub fn list_of<T>(
        &mut self,
        expected: usize,
        what: &str,
        min_item: usize,
        each: impl FnMut(&mut Dec<'a>) -> Result<T, StateError>,
    ) -> Result<Vec<T>, StateError> {
        let v = self.list(min_item, each)?;
        if v.len() != expected {
            return Err(StateError::Mismatch(format!("{what} has {} entries, expected {expected}", v.len())));
        }
        Ok(v)
    }
    /// Fails unless every byte has been read.
    pub fn finish(self) -> Result<(), StateError> {
        if self.bytes.is_empty() { Ok(()) } else { Err(StateError::Trailing(self.bytes.len())) }
    }
}
