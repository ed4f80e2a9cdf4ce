//! Comments and the commands hidden in them: `(MSG,...)`,
//! `(DEBUG,...)`, `(PRINT,...)`, `(LOG...)`, `(ABORT,...)`.

use crate::canon::Canon;
use crate::cfmt;
use crate::comp::Queued;
use crate::error::{InterpError, Result};
use crate::interp::Interp;
use crate::source::is_c_space;

impl Interp {
    /// Execute a block's comment.
    pub(crate) fn convert_comment(&mut self, comment: &[u8], canon: &mut dyn Canon) -> Result<()> {
        let start = comment.iter().take_while(|&&b| is_c_space(b)).count();
        let body = &comment[start..];
        let lower: Vec<u8> = body
            .iter()
            .take(256)
            .map(|b| b.to_ascii_lowercase())
            .collect();
        let after = |prefix: &str| {
            String::from_utf8_lossy(&body[prefix.len().min(body.len())..]).into_owned()
        };
        if lower.starts_with(b"msg,") {
            canon.message(&after("msg,"));
        } else if lower.starts_with(b"debug,") {
            let text = self.expand_params(&body[6..])?;
            if self.params.get(5599) > 0.0 {
                canon.message(&text);
            }
        } else if lower.starts_with(b"print,") {
            let text = self.expand_params(&body[6..])?;
            canon.print(&text);
        } else if lower.starts_with(b"log,") {
            let text = self.expand_params(&body[4..])?;
            canon.log(&text);
        } else if lower.starts_with(b"logopen,") {
            canon.log_open(&after("logopen,"));
        } else if lower.starts_with(b"logappend,") {
            canon.log_append(&after("logappend,"));
        } else if lower.starts_with(b"abort,") {
            return Err(InterpError::Abort(self.expand_params(&body[6..])?));
        } else if lower == b"logclose" {
            canon.log_close();
        } else {
            self.enqueue(
                canon,
                Queued::Comment(String::from_utf8_lossy(body).into_owned()),
            );
        }
        Ok(())
    }

    /// Replace `#n` and `#<name>` in a DEBUG/PRINT/LOG text by their
    /// values (`%lf`), or `######` for unknown ones.
    fn expand_params(&self, text: &[u8]) -> Result<String> {
        let mut out = Vec::with_capacity(text.len());
        let mut i = 0;
        while i < text.len() {
            if text[i] != b'#' {
                out.push(text[i]);
                i += 1;
                continue;
            }
            i += 1;
            if i >= text.len() {
                return Err(InterpError::NamedParameterNotTerminated);
            }
            let value = if text[i].is_ascii_digit() {
                let start = i;
                while i < text.len() && text[i].is_ascii_digit() {
                    i += 1;
                }
                let number: usize = std::str::from_utf8(&text[start..i])
                    .ok()
                    .and_then(|s| s.parse().ok())
                    .unwrap_or(usize::MAX);
                (number < crate::params::MAX_PARAMETERS).then(|| self.numbered_param(number))
            } else if text[i] == b'<' {
                i += 1;
                if i >= text.len() {
                    return Err(InterpError::NamedParameterNotTerminated);
                }
                let mut name = String::new();
                while i < text.len() && text[i] != b')' && text[i] != b'>' {
                    if !is_c_space(text[i]) {
                        name.push(text[i].to_ascii_lowercase() as char);
                    }
                    i += 1;
                }
                if i >= text.len() || text[i] != b'>' {
                    return Err(InterpError::NamedParameterNotTerminated);
                }
                i += 1;
                self.find_named_param(&name)?
            } else {
                out.push(b'#');
                continue;
            };
            let shown = match value {
                Some(v) => {
                    let v = if (v - 0.0).abs() < 0.0001 { 0.0 } else { v };
                    let s = cfmt::f(v, 6);
                    if s.len() >= 30 {
                        "######".to_string()
                    } else {
                        s
                    }
                }
                None => "######".to_string(),
            };
            out.extend_from_slice(shown.as_bytes());
        }
        Ok(String::from_utf8_lossy(&out).into_owned())
    }
}
