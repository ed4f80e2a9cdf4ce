//! Writing a firmware image into a remote's flash, block by block
//! (hostmot2-more.md 2.3): the remote says its erase and write sizes;
//! block 0 is the remote's own and never written; an all-zero block is
//! skipped; each other block is erased, then written one write-size
//! chunk at a time, each erase and write confirmed by the cookie.
//!
//! The image is never read past its end: its last chunk is padded with
//! zeros.

use crate::error::{Hm2Error, Result};
use crate::sserial::{access, flash};

use super::ops::Channel;

/// Largest erase or write size a remote may report (log2).
const MAX_SHIFT: u8 = 16;

/// What a flash did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Flashed {
    /// Erase block size.
    pub erase_size: usize,
    /// Write size.
    pub write_size: usize,
    /// Blocks erased and written.
    pub written: usize,
    /// All-zero blocks skipped.
    pub skipped: usize,
}

/// Runs `step` named `what`, the remote's name added to its error.
fn at<T>(remote: &str, what: impl Into<String>, step: Result<T>) -> Result<T> {
    step.map_err(|e| Hm2Error::SetsserialStep {
        remote: remote.to_string(),
        step: what.into(),
        source: Box::new(e),
    })
}

/// Flashes `image` into the remote on `ch` (already checked: setup
/// mode, SSLBP version), saying each block's progress through `say`.
pub fn flash(
    ch: &mut Channel<'_>,
    remote: &str,
    image: &[u8],
    say: &mut dyn FnMut(String),
) -> Result<Flashed> {
    at(remote, "setup start", ch.start_setup())?;
    at(remote, "flash access on", ch.access(access::FLASH))?;
    let write_shift = at(
        remote,
        "reading the write size",
        ch.read_byte(flash::WRITE_SIZE),
    )?;
    let erase_shift = at(
        remote,
        "reading the erase size",
        ch.read_byte(flash::ERASE_SIZE),
    )?;
    at(remote, "flash access off", ch.access(access::RAM))?;
    if !(3..=MAX_SHIFT).contains(&write_shift) || !(write_shift..=MAX_SHIFT).contains(&erase_shift)
    {
        return at(
            remote,
            "reading the flash sizes",
            Err(Hm2Error::Sserial {
                port: ch.port,
                channel: Some(ch.chan),
                reason: format!(
                    "the remote reports a write size of 2^{write_shift} and an erase size of 2^{erase_shift} bytes (8 ≤ write ≤ erase ≤ 2^{MAX_SHIFT} expected)"
                ),
            }),
        );
    }
    let (es, ws) = (1usize << erase_shift, 1usize << write_shift);
    let blocks = image.len().div_ceil(es);
    let mut done = Flashed {
        erase_size: es,
        write_size: ws,
        written: 0,
        skipped: 0,
    };
    for block in 1..blocks {
        let start = block * es;
        let end = (start + es).min(image.len());
        if image[start..end].iter().all(|&b| b == 0) {
            done.skipped += 1;
            say(format!(
                "{remote}: block {block} of {} is empty, skipped",
                blocks - 1
            ));
            continue;
        }
        let step = |s: &str| format!("{s} (block {block})");
        at(remote, step("flash access on"), ch.access(access::FLASH))?;
        at(remote, step("erase"), erase(ch, start as u32))?;
        at(remote, step("flash access off"), ch.access(access::RAM))?;
        at(remote, step("flash access on"), ch.access(access::FLASH))?;
        for chunk in (start..end).step_by(ws) {
            let what = format!("write at 0x{chunk:06X} (block {block})");
            at(
                remote,
                what,
                write_chunk(ch, chunk, &image[chunk..end.min(chunk + ws)], ws),
            )?;
        }
        at(remote, step("flash access off"), ch.access(access::RAM))?;
        done.written += 1;
        say(format!("{remote}: block {block} of {} written", blocks - 1));
    }
    Ok(done)
}

fn erase(ch: &mut Channel<'_>, start: u32) -> Result<()> {
    ch.write_long(flash::ADDR, start)?;
    ch.write_byte(flash::COMMAND, flash::ERASE)?;
    ch.check_cookie()
}

/// Writes `bytes` (at most `ws`, padded with zeros to `ws`) at `start`.
fn write_chunk(ch: &mut Channel<'_>, start: usize, bytes: &[u8], ws: usize) -> Result<()> {
    ch.write_long(flash::ADDR, start as u32)?;
    for off in (0..ws).step_by(8) {
        let mut d = [0u8; 8];
        for (k, b) in d.iter_mut().enumerate() {
            *b = bytes.get(off + k).copied().unwrap_or(0);
        }
        ch.write_double(off as u16, d)?;
    }
    ch.write_byte(flash::COMMAND, flash::WRITE)?;
    ch.check_cookie()
}
