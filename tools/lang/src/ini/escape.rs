//! Escapes in INI values: `\a \b \f \n \r \t \v`, octal
//! `\[0-3][0-7]{0,2}`, `\xHH`, `\uHHHH` (UTF-16, surrogate pairs joined),
//! `\UHHHHHHHH`, and `\\`. Another character after a backslash is kept as
//! written. The result must be UTF-8 without NUL.

/// Why a value's escapes do not make text.
pub(super) enum Unescape {
    /// This escape is malformed (as written).
    Escape(String),
    /// The value as a whole is not text.
    Text(&'static str),
}

const NUL: Unescape = Unescape::Text("contains a NUL character");
const UNPAIRED: Unescape = Unescape::Text("has an unpaired UTF-16 surrogate");

/// Resolves the escapes of a value.
pub(super) fn unescape(s: &str) -> Result<String, Unescape> {
    if !s.contains('\\') {
        return if s.contains('\0') {
            Err(NUL)
        } else {
            Ok(s.to_string())
        };
    }
    let mut u = Unescaper {
        s,
        out: Vec::with_capacity(s.len()),
        i: 0,
        pending_high: None,
    };
    while u.i < s.len() {
        u.step()?;
    }
    if u.pending_high.is_some() {
        return Err(UNPAIRED);
    }
    if u.out.contains(&0) {
        return Err(NUL);
    }
    String::from_utf8(u.out).map_err(|_| Unescape::Text("is not valid UTF-8 after its escapes"))
}

/// The one-letter escapes.
fn simple_escape(c: u8) -> Option<u8> {
    Some(match c {
        b'a' => 0x07,
        b'b' => 0x08,
        b'f' => 0x0c,
        b'n' => b'\n',
        b'r' => b'\r',
        b't' => b'\t',
        b'v' => 0x0b,
        b'\\' => b'\\',
        _ => return None,
    })
}

/// A value being unescaped: the bytes made so far, where the next escape
/// starts, and a UTF-16 high surrogate waiting for its low half.
struct Unescaper<'s> {
    s: &'s str,
    out: Vec<u8>,
    i: usize,
    pending_high: Option<u16>,
}

impl Unescaper<'_> {
    /// One plain byte, or one escape.
    fn step(&mut self) -> Result<(), Unescape> {
        let b = self.s.as_bytes();
        let i = self.i;
        if b[i] != b'\\' || i + 1 == b.len() {
            self.no_pending()?;
            self.out.push(b[i]);
            self.i += 1;
            return Ok(());
        }
        let c = b[i + 1];
        if let Some(v) = simple_escape(c) {
            self.no_pending()?;
            self.out.push(v);
            self.i += 2;
            return Ok(());
        }
        match c {
            b'0'..=b'3' => self.octal(c)?,
            b'x' => self.hex_byte()?,
            // A high surrogate waits here for its low half.
            b'u' => return self.utf16(),
            b'U' => self.utf32()?,
            _ => {
                // Not an escape: kept as written.
                self.out.push(b'\\');
                self.i += 1;
            }
        }
        self.no_pending()
    }

    /// Refuses a high surrogate that no low half follows.
    fn no_pending(&mut self) -> Result<(), Unescape> {
        match self.pending_high.take() {
            Some(_) => Err(UNPAIRED),
            None => Ok(()),
        }
    }

    /// `n` hex digits from byte `from`.
    fn hex(&self, from: usize, n: usize) -> Option<u32> {
        let t = self.s.get(from..from + n)?;
        if t.len() == n && t.bytes().all(|d| d.is_ascii_hexdigit()) {
            u32::from_str_radix(t, 16).ok()
        } else {
            None
        }
    }

    /// The malformed escape at `start`, `len` bytes of it as written.
    fn bad(&self, start: usize, len: usize) -> Unescape {
        Unescape::Escape(self.s[start..(start + len).min(self.s.len())].to_string())
    }

    /// `\[0-3][0-7]{0,2}`.
    fn octal(&mut self, first: u8) -> Result<(), Unescape> {
        let b = self.s.as_bytes();
        let mut v = u32::from(first - b'0');
        let mut j = self.i + 2;
        while j < b.len() && j < self.i + 4 && (b'0'..=b'7').contains(&b[j]) {
            v = v * 8 + u32::from(b[j] - b'0');
            j += 1;
        }
        if v == 0 {
            return Err(NUL);
        }
        self.out.push(v as u8);
        self.i = j;
        Ok(())
    }

    /// `\xHH`.
    fn hex_byte(&mut self) -> Result<(), Unescape> {
        let v = self.hex(self.i + 2, 2).ok_or_else(|| self.bad(self.i, 2))?;
        if v == 0 {
            return Err(NUL);
        }
        self.out.push(v as u8);
        self.i += 4;
        Ok(())
    }

    /// `\uHHHH`: a character, or half of a surrogate pair.
    fn utf16(&mut self) -> Result<(), Unescape> {
        let start = self.i;
        let v = self.hex(start + 2, 4).ok_or_else(|| self.bad(start, 2))? as u16;
        self.i += 6;
        if (0xd800..0xdc00).contains(&v) {
            return match self.pending_high.replace(v) {
                Some(_) => Err(UNPAIRED),
                None => Ok(()),
            };
        }
        let ch = if (0xdc00..0xe000).contains(&v) {
            let high = self.pending_high.take().ok_or(UNPAIRED)?;
            char::decode_utf16([high, v])
                .next()
                .and_then(|r| r.ok())
                .ok_or(UNPAIRED)?
        } else if self.pending_high.is_some() {
            return Err(UNPAIRED);
        } else {
            char::from_u32(u32::from(v)).ok_or_else(|| self.bad(start, 2))?
        };
        self.push_char(ch)
    }

    /// `\UHHHHHHHH`.
    fn utf32(&mut self) -> Result<(), Unescape> {
        let start = self.i;
        let v = self.hex(start + 2, 8).ok_or_else(|| self.bad(start, 2))?;
        let ch = char::from_u32(v).ok_or_else(|| self.bad(start, 10))?;
        self.push_char(ch)?;
        self.i += 10;
        Ok(())
    }

    fn push_char(&mut self, ch: char) -> Result<(), Unescape> {
        if ch == '\0' {
            return Err(NUL);
        }
        let mut buf = [0u8; 4];
        self.out
            .extend_from_slice(ch.encode_utf8(&mut buf).as_bytes());
        Ok(())
    }
}
