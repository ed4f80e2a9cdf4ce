//! The access token: made afresh at each start, stored readable by its
//! owner only, and compared in constant time.

use std::io::Write;
use std::os::unix::fs::OpenOptionsExt;
use std::path::PathBuf;

use crate::WebError;

/// The header every request carries the token in (never the URL).
pub const HEADER: &str = "x-hal-token";

/// Random bytes in a token (printed as twice as many hex digits).
const TOKEN_BYTES: usize = 24;

/// A secret that requests must present.
#[derive(Clone, PartialEq, Eq)]
pub struct Token(pub(crate) String);

impl std::fmt::Debug for Token {
    /// Never prints the secret.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Token(..)")
    }
}

impl Token {
    /// A fresh token from the kernel's random source.
    pub fn generate() -> Result<Token, WebError> {
        let mut bytes = [0u8; TOKEN_BYTES];
        getrandom::fill(&mut bytes).map_err(WebError::Random)?;
        Ok(Token(bytes.iter().map(|b| format!("{b:02x}")).collect()))
    }

    /// The secret, to print once or store.
    pub fn secret(&self) -> &str {
        &self.0
    }

    /// Whether `offered` is this token; takes the same time wherever the
    /// two differ.
    pub fn matches(&self, offered: &[u8]) -> bool {
        let mine = self.0.as_bytes();
        if offered.len() != mine.len() {
            return false;
        }
        mine.iter()
            .zip(offered)
            .fold(0u8, |acc, (a, b)| acc | (a ^ b))
            == 0
    }
}

/// Where the token of `instance` is stored: in the private runtime
/// directory, beside the instance's other files.
pub fn path(instance: &str) -> Result<PathBuf, WebError> {
    Ok(hal_core::paths::runtime_file(instance, ".web-token")?)
}

/// Stores `token` at `path` with mode 0600 (a file left by an earlier run
/// is replaced; a link planted there is not followed).
pub fn store(token: &Token, path: &PathBuf) -> Result<(), WebError> {
    let err = |source| WebError::TokenFile {
        path: path.clone(),
        source,
    };
    hal_core::paths::ensure_runtime_dir()?;
    match std::fs::remove_file(path) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(err(e)),
    }
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o600)
        .custom_flags(libc_flags())
        .open(path)
        .map_err(err)?;
    writeln!(f, "{}", token.secret()).map_err(err)
}

/// `O_NOFOLLOW | O_CLOEXEC`.
fn libc_flags() -> i32 {
    nix::fcntl::OFlag::O_NOFOLLOW.bits() | nix::fcntl::OFlag::O_CLOEXEC.bits()
}

/// Removes the token file at the end (best effort: the next start
/// replaces it anyway).
pub fn remove(path: &PathBuf) {
    let _ = std::fs::remove_file(path);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_differ_and_match_only_themselves() {
        let a = Token::generate().unwrap();
        let b = Token::generate().unwrap();
        assert_ne!(a, b);
        assert_eq!(a.secret().len(), 2 * TOKEN_BYTES);
        assert!(a.matches(a.secret().as_bytes()));
        assert!(!a.matches(b.secret().as_bytes()));
        assert!(!a.matches(b""));
        assert!(!format!("{a:?}").contains(a.secret()));
    }
}
