//! # Little-endian byte strings, read with every length checked
//!
//! The pack ([`crate::pack`]) and the prepared image ([`crate::prepared`]'s `image`) are byte
//! strings of little-endian integers and floats; both are read through this one reader, which
//! never panics: a read past the end is an error naming the offset, built by the caller's
//! `err` (so a damaged pack and a damaged image say which they are).

use crate::DbError;

/// A cursor over a byte string.
pub(crate) struct ByteReader<'a> {
    bytes: &'a [u8],
    pos: usize,
    err: fn(String) -> DbError,
}

impl<'a> ByteReader<'a> {
    /// A reader at the start of `bytes`; `err` makes its errors.
    pub(crate) fn new(bytes: &'a [u8], err: fn(String) -> DbError) -> Self {
        Self { bytes, pos: 0, err }
    }

    /// An error of this reader's kind.
    pub(crate) fn error(&self, message: String) -> DbError {
        (self.err)(message)
    }

    /// Bytes not yet read.
    pub(crate) fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// The next `n` bytes.
    pub(crate) fn take(&mut self, n: usize) -> Result<&'a [u8], DbError> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.bytes.len())
            .ok_or_else(|| {
                self.error(format!(
                    "truncated: wanted {n} bytes at offset {}, {} left",
                    self.pos,
                    self.remaining()
                ))
            })?;
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], DbError> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N)?);
        Ok(a)
    }

    pub(crate) fn u8(&mut self) -> Result<u8, DbError> {
        Ok(self.array::<1>()?[0])
    }

    pub(crate) fn u32(&mut self) -> Result<u32, DbError> {
        Ok(u32::from_le_bytes(self.array()?))
    }

    pub(crate) fn u64(&mut self) -> Result<u64, DbError> {
        Ok(u64::from_le_bytes(self.array()?))
    }

    /// A `u64` that must fit a `usize`.
    pub(crate) fn len(&mut self) -> Result<usize, DbError> {
        let v = self.u64()?;
        usize::try_from(v).map_err(|_| self.error(format!("length {v} overflows")))
    }

    pub(crate) fn f32(&mut self) -> Result<f32, DbError> {
        Ok(f32::from_bits(self.u32()?))
    }

    pub(crate) fn f64(&mut self) -> Result<f64, DbError> {
        Ok(f64::from_bits(self.u64()?))
    }

    /// A `u32`-length-prefixed UTF-8 string.
    pub(crate) fn str(&mut self) -> Result<String, DbError> {
        let n = self.u32()? as usize;
        let b = self.take(n)?;
        std::str::from_utf8(b)
            .map(str::to_string)
            .map_err(|_| self.error(format!("text at offset {} is not UTF-8", self.pos - n)))
    }
}

/// Little-endian writers matching [`ByteReader`].
pub(crate) trait PutLe {
    fn put_u32(&mut self, v: u32);
    fn put_u64(&mut self, v: u64);
    fn put_str(&mut self, s: &str);
}

impl PutLe for Vec<u8> {
    fn put_u32(&mut self, v: u32) {
        self.extend_from_slice(&v.to_le_bytes());
    }

    fn put_u64(&mut self, v: u64) {
        self.extend_from_slice(&v.to_le_bytes());
    }

    fn put_str(&mut self, s: &str) {
        self.put_u32(s.len() as u32);
        self.extend_from_slice(s.as_bytes());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_what_was_written_and_refuses_past_the_end() {
        let mut b = Vec::new();
        b.put_u32(7);
        b.put_u64(u64::MAX - 1);
        b.put_str("é1");
        b.extend_from_slice(&1.5f32.to_bits().to_le_bytes());
        let mut r = ByteReader::new(&b, DbError::BadPack);
        assert_eq!(r.u32().unwrap(), 7);
        assert_eq!(r.u64().unwrap(), u64::MAX - 1);
        assert_eq!(r.str().unwrap(), "é1");
        assert_eq!(r.f32().unwrap(), 1.5);
        assert_eq!(r.remaining(), 0);
        let e = r.u8().unwrap_err().to_string();
        assert!(e.contains("truncated") && e.contains("pack"), "{e}");
        let bad = [2u8, 0, 0, 0, 0xff, 0xfe];
        assert!(ByteReader::new(&bad, DbError::BadPack).str().is_err());
    }
}
