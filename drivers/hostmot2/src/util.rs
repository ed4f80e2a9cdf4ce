//! Small helpers for realtime code.

/// A line of at most `N` bytes formatted on the stack, for messages from
/// realtime functions (no allocation); longer text is cut at `N`.
pub struct LineBuf<const N: usize> {
    buf: [u8; N],
    len: usize,
}

impl<const N: usize> LineBuf<N> {
    /// An empty line.
    pub fn new() -> Self {
        LineBuf {
            buf: [0; N],
            len: 0,
        }
    }

    /// The text so far.
    pub fn as_str(&self) -> &str {
        // Only whole UTF-8 sequences are ever copied in.
        std::str::from_utf8(&self.buf[..self.len]).unwrap_or("")
    }
}

impl<const N: usize> Default for LineBuf<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> std::fmt::Write for LineBuf<N> {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        let room = N - self.len;
        let mut take = s.len().min(room);
        while !s.is_char_boundary(take) {
            take -= 1;
        }
        self.buf[self.len..self.len + take].copy_from_slice(&s.as_bytes()[..take]);
        self.len += take;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fmt::Write;

    #[test]
    fn lines_are_cut_at_their_size() {
        let mut l = LineBuf::<8>::new();
        write!(l, "{}-abcdef", 1234).unwrap();
        assert_eq!(l.as_str(), "1234-abc");
        let mut l = LineBuf::<3>::new();
        write!(l, "aé").unwrap();
        assert_eq!(l.as_str(), "aé");
        let mut l = LineBuf::<2>::new();
        write!(l, "aé").unwrap();
        assert_eq!(l.as_str(), "a");
    }
}
