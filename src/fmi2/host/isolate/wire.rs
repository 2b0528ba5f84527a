//! The mailbox's message format: little-endian numbers and length-prefixed arrays written into and
//! read from the payload, every read bounds-checked (a host whose FMU scribbled over the mapping
//! yields an error in the master, never a panic).

/// What a message could not hold or did not contain.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum WireError {
    #[error("a message of more than {0} bytes does not fit the isolation mailbox")]
    Full(usize),
    #[error("malformed message at byte {0}")]
    Malformed(usize),
}

pub struct Writer<'a> {
    buf: &'a mut [u8],
    pub pos: usize,
}

impl<'a> Writer<'a> {
    pub fn at(buf: &'a mut [u8], pos: usize) -> Self {
        Self { buf, pos }
    }

    pub fn bytes(&mut self, b: &[u8]) -> Result<(), WireError> {
        let end = self.pos + b.len();
        if end > self.buf.len() {
            return Err(WireError::Full(self.buf.len()));
        }
        self.buf[self.pos..end].copy_from_slice(b);
        self.pos = end;
        Ok(())
    }

    pub fn u32(&mut self, x: u32) -> Result<(), WireError> {
        self.bytes(&x.to_le_bytes())
    }

    pub fn i32(&mut self, x: i32) -> Result<(), WireError> {
        self.bytes(&x.to_le_bytes())
    }

    pub fn u64(&mut self, x: u64) -> Result<(), WireError> {
        self.bytes(&x.to_le_bytes())
    }

    pub fn f64(&mut self, x: f64) -> Result<(), WireError> {
        self.bytes(&x.to_le_bytes())
    }

    fn len(&mut self, n: usize) -> Result<(), WireError> {
        self.u32(u32::try_from(n).map_err(|_| WireError::Full(self.buf.len()))?)
    }

    pub fn blob(&mut self, b: &[u8]) -> Result<(), WireError> {
        self.len(b.len())?;
        self.bytes(b)
    }

    pub fn str(&mut self, s: &str) -> Result<(), WireError> {
        self.blob(s.as_bytes())
    }

    pub fn u32s(&mut self, xs: &[u32]) -> Result<(), WireError> {
        self.len(xs.len())?;
        xs.iter().try_for_each(|&x| self.u32(x))
    }

    pub fn i32s(&mut self, xs: &[i32]) -> Result<(), WireError> {
        self.len(xs.len())?;
        xs.iter().try_for_each(|&x| self.i32(x))
    }

    pub fn f64s(&mut self, xs: &[f64]) -> Result<(), WireError> {
        self.len(xs.len())?;
        xs.iter().try_for_each(|&x| self.f64(x))
    }
}

pub struct Reader<'a> {
    buf: &'a [u8],
    pub pos: usize,
}

impl<'a> Reader<'a> {
    pub fn at(buf: &'a [u8], pos: usize) -> Self {
        Self { buf, pos }
    }

    pub fn bytes(&mut self, n: usize) -> Result<&'a [u8], WireError> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.buf.len())
            .ok_or(WireError::Malformed(self.pos))?;
        let b = &self.buf[self.pos..end];
        self.pos = end;
        Ok(b)
    }

    /// What was read since `start`.
    pub fn slice(&self, start: usize) -> &'a [u8] {
        &self.buf[start.min(self.pos)..self.pos]
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], WireError> {
        Ok(self.bytes(N)?.try_into().expect("N bytes"))
    }

    pub fn u32(&mut self) -> Result<u32, WireError> {
        self.array().map(u32::from_le_bytes)
    }

    pub fn i32(&mut self) -> Result<i32, WireError> {
        self.array().map(i32::from_le_bytes)
    }

    pub fn u64(&mut self) -> Result<u64, WireError> {
        self.array().map(u64::from_le_bytes)
    }

    pub fn f64(&mut self) -> Result<f64, WireError> {
        self.array().map(f64::from_le_bytes)
    }

    /// A length prefix for items of `size` bytes, checked against what is left.
    fn len(&mut self, size: usize) -> Result<usize, WireError> {
        let at = self.pos;
        let n = self.u32()? as usize;
        if n.saturating_mul(size) > self.buf.len() - self.pos {
            return Err(WireError::Malformed(at));
        }
        Ok(n)
    }

    pub fn blob(&mut self) -> Result<&'a [u8], WireError> {
        let n = self.len(1)?;
        self.bytes(n)
    }

    pub fn string(&mut self) -> Result<String, WireError> {
        self.blob().map(|b| String::from_utf8_lossy(b).into_owned())
    }

    /// A length-prefixed array of `size`-byte items into `out`.
    fn items<T>(
        &mut self,
        size: usize,
        out: &mut Vec<T>,
        item: fn(&mut Self) -> Result<T, WireError>,
    ) -> Result<(), WireError> {
        let n = self.len(size)?;
        out.clear();
        for _ in 0..n {
            out.push(item(self)?);
        }
        Ok(())
    }

    pub fn u32s(&mut self, out: &mut Vec<u32>) -> Result<(), WireError> {
        self.items(4, out, Self::u32)
    }

    pub fn i32s(&mut self, out: &mut Vec<i32>) -> Result<(), WireError> {
        self.items(4, out, Self::i32)
    }

    pub fn f64s(&mut self, out: &mut Vec<f64>) -> Result<(), WireError> {
        self.items(8, out, Self::f64)
    }

    /// A length-prefixed array straight into `out`, whose length the reader knows.
    fn items_into<T>(
        &mut self,
        size: usize,
        out: &mut [T],
        item: fn(&mut Self) -> Result<T, WireError>,
    ) -> Result<(), WireError> {
        let at = self.pos;
        if self.len(size)? != out.len() {
            return Err(WireError::Malformed(at));
        }
        for v in out.iter_mut() {
            *v = item(self)?;
        }
        Ok(())
    }

    pub fn f64s_into(&mut self, out: &mut [f64]) -> Result<(), WireError> {
        self.items_into(8, out, Self::f64)
    }

    pub fn i32s_into(&mut self, out: &mut [i32]) -> Result<(), WireError> {
        self.items_into(4, out, Self::i32)
    }

    /// 0/1 Integers into Booleans.
    pub fn bools_into(&mut self, out: &mut [bool]) -> Result<(), WireError> {
        self.items_into(4, out, |r| r.i32().map(|b| b != 0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn what_is_written_reads_back_and_short_or_lying_messages_are_refused() {
        let mut buf = vec![0u8; 64];
        let mut w = Writer::at(&mut buf, 0);
        w.u32(7).unwrap();
        w.f64s(&[1.5, -0.0]).unwrap();
        w.str("né").unwrap();
        let end = w.pos;
        assert_eq!(w.f64s(&[0.0; 8]), Err(WireError::Full(64)));
        let mut r = Reader::at(&buf[..end], 0);
        assert_eq!(r.u32(), Ok(7));
        let mut xs = Vec::new();
        r.f64s(&mut xs).unwrap();
        assert_eq!(xs, [1.5, -0.0]);
        assert_eq!(r.string().unwrap(), "né");
        assert!(r.u32().is_err());
        // a length prefix larger than the message
        let mut lying = Vec::new();
        lying.extend_from_slice(&u32::MAX.to_le_bytes());
        assert_eq!(Reader::at(&lying, 0).f64s(&mut xs), Err(WireError::Malformed(0)));
    }
}
