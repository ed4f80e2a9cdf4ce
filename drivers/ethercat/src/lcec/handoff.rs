//! How `lcec_conf` hands the configuration to `loadrt lcec`, as in
//! linuxcnc-ethercat: `loadusr -W lcec_conf ethercat-conf.xml` checks the
//! file and keeps it in a named region of the HAL instance (`lcec_conf`)
//! for as long as it runs; `loadrt lcec` without `config=` reads it from
//! there. The region holds a magic word, the lengths of the file's path
//! and text, then both, packed little-endian into words. The region is
//! shared memory any process of the instance may write, so reading it
//! checks every length and the text's UTF-8 before use.

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering::Relaxed;

use hal_core::{Component, Instance};

use crate::error::{Error, Result};

/// The region's name (and `lcec_conf`'s component's).
pub const REGION: &str = "lcec_conf";

/// Bytes of configuration `lcec_conf` takes at most.
pub const MAX_BYTES: usize = super::conf::MAX_FILE_BYTES;

const MAGIC: u64 = u64::from_le_bytes(*b"lcecconf");
const HEADER_WORDS: usize = 3;

/// The words holding `path` and `text`.
pub fn encode(path: &Path, text: &str) -> Vec<u64> {
    let p = path.to_string_lossy();
    let mut bytes = Vec::with_capacity(p.len() + text.len());
    bytes.extend_from_slice(p.as_bytes());
    bytes.extend_from_slice(text.as_bytes());
    let mut words = vec![MAGIC, p.len() as u64, text.len() as u64];
    words.extend(bytes.chunks(8).map(|c| {
        let mut w = [0u8; 8];
        w[..c.len()].copy_from_slice(c);
        u64::from_le_bytes(w)
    }));
    words
}

/// The path and text in `words`; an error says what is wrong.
pub fn decode(words: &[u64]) -> Result<(PathBuf, String)> {
    let bad = |reason: &str| Error::malformed(format!("HAL region {REGION}"), reason.to_string());
    let [magic, path_len, text_len] = match words.get(..HEADER_WORDS) {
        Some(&[a, b, c]) => [a, b, c],
        _ => return Err(bad("shorter than its header")),
    };
    if magic != MAGIC {
        return Err(bad("not written by lcec_conf (wrong magic word)"));
    }
    let room = (words.len() - HEADER_WORDS) as u64 * 8;
    let total = path_len
        .checked_add(text_len)
        .ok_or_else(|| bad("lengths overflow"))?;
    if total > room || text_len > MAX_BYTES as u64 {
        return Err(bad("lengths past the end of the region"));
    }
    let bytes: Vec<u8> = words[HEADER_WORDS..]
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .take(total as usize)
        .collect();
    let (p, t) = bytes.split_at(path_len as usize);
    let path = String::from_utf8(p.to_vec()).map_err(|_| bad("the path is not UTF-8"))?;
    let text = String::from_utf8(t.to_vec()).map_err(|_| bad("the configuration is not UTF-8"))?;
    Ok((PathBuf::from(path), text))
}

/// Publishes `path` and `text` in a region of `c` (freed with it).
pub fn publish(c: &Component, path: &Path, text: &str) -> hal_core::Result<()> {
    let words = encode(path, text);
    let region = c.region(REGION, words.len() * 8)?;
    for (slot, w) in region.words().iter().zip(&words) {
        slot.store(*w, Relaxed);
    }
    Ok(())
}

/// What `lcec_conf` published in `inst`; None when it is not running.
pub fn take(inst: &Instance) -> Option<Result<(PathBuf, String)>> {
    let region = inst.region(REGION).ok()?;
    let words: Vec<u64> = region.words().iter().map(|w| w.load(Relaxed)).collect();
    Some(decode(&words))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_hostile_words() {
        let w = encode(Path::new("/etc/x/ethercat-conf.xml"), "<masters/>\n");
        let (p, t) = decode(&w).unwrap();
        assert_eq!(p, Path::new("/etc/x/ethercat-conf.xml"));
        assert_eq!(t, "<masters/>\n");
        let mut long = w.clone();
        long[2] = u64::MAX;
        assert!(decode(&long).unwrap_err().to_string().contains("overflow"));
        long[2] = 1 << 40;
        assert!(decode(&long)
            .unwrap_err()
            .to_string()
            .contains("past the end"));
        assert!(decode(&[MAGIC]).is_err());
        assert!(decode(&[0, 0, 0])
            .unwrap_err()
            .to_string()
            .contains("magic"));
    }
}
