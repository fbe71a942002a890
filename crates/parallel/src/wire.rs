//! The little-endian wire primitives the distributed jobs share (`progressive.rs`,
//! `radiosity.rs`): a reader that fails on a short or lying message instead of
//! panicking, and the writers of its fixed-size fields.

/// Reads a message front to back, failing on a short one.
pub(crate) struct Reader<'b>(pub(crate) &'b [u8]);

impl<'b> Reader<'b> {
    pub(crate) fn take(&mut self, n: usize) -> Result<&'b [u8], String> {
        if self.0.len() < n {
            return Err(format!("message ends {} bytes early", n - self.0.len()));
        }
        let (a, rest) = self.0.split_at(n);
        self.0 = rest;
        Ok(a)
    }
    pub(crate) fn u8(&mut self) -> Result<u8, String> {
        Ok(self.take(1)?[0])
    }
    pub(crate) fn u32(&mut self) -> Result<u32, String> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    pub(crate) fn f32(&mut self) -> Result<f32, String> {
        Ok(f32::from_bits(self.u32()?))
    }
    pub(crate) fn f64(&mut self) -> Result<f64, String> {
        let b = self.take(8)?;
        Ok(f64::from_le_bytes([
            b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7],
        ]))
    }
    /// A u32 count of items of `size` bytes each, checked against the bytes left (so a
    /// lying count cannot make the receiver allocate).
    pub(crate) fn count(&mut self, size: usize) -> Result<usize, String> {
        let n = self.u32()? as usize;
        let left = self.0.len();
        if n.saturating_mul(size) > left {
            return Err(format!("{n} items of {size} bytes in {left} bytes"));
        }
        Ok(n)
    }
}

pub(crate) fn put_u32(b: &mut Vec<u8>, v: u32) {
    b.extend_from_slice(&v.to_le_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_and_lying_messages_are_errors() {
        let mut b = Vec::new();
        put_u32(&mut b, 7);
        b.extend_from_slice(&1.5f64.to_le_bytes());
        let mut r = Reader(&b);
        assert_eq!(r.u32(), Ok(7));
        assert_eq!(r.f64(), Ok(1.5));
        assert!(r.u8().is_err());
        let mut b = Vec::new();
        put_u32(&mut b, 1000);
        assert!(Reader(&b).count(16).is_err());
    }
}
