//! Fuzz bodies for the parsers of outside bytes in this crate: register
//! images through the IDROM loader, and config strings. The workspace's
//! fuzz crate (`hal-fuzz`) can call them as its targets; until it has
//! them, this crate's tests run them for 100,000 generated cases each.
//!
//! A body panics on a finding: a panic in the code under test, or an
//! accepted board that breaks what the driver relies on, or a refusal
//! that does not say why.

use crate::config;
use crate::firmware::{self, Debug};
use crate::image::{ImageTransport, WINDOW_WORDS};
use crate::llio::Llio;
use crate::log::MessageLog;
use crate::md;
use crate::pins::PinOwner;
use crate::sim::boards;
use crate::test_patterns;

/// The board an IDROM fuzz input starts from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IdromCase {
    /// The llio the image is loaded for.
    pub llio: Llio,
    /// The register image.
    pub image: Vec<u32>,
    /// The config string.
    pub config: String,
}

/// Decodes fuzz bytes into a board: byte 0 picks the starting image (a
/// simulated board's, an hm2_test pattern, or raw bytes); byte 1 may
/// change the llio's connectors and pins per connector; the rest are
/// edits (a word index near the identification and IDROM area, then a
/// value) or, for a raw image, the image itself from 0x0100.
pub fn decode(data: &[u8]) -> IdromCase {
    let pick = data.first().copied().unwrap_or(0);
    let tweak = data.get(1).copied().unwrap_or(0);
    let rest = data.get(2..).unwrap_or(&[]);
    let presets = boards::PRESETS;
    let (mut llio, mut image) = match pick % 8 {
        k @ 0..=3 => {
            let spec = boards::preset(presets[k as usize % presets.len()]).expect("preset");
            (spec.llio(0), spec.image())
        }
        4 | 5 => test_patterns::pattern(pick as u32 % 15).expect("pattern"),
        _ => {
            let spec = boards::preset("5i25").expect("preset");
            let mut img = vec![0u32; WINDOW_WORDS];
            for (i, w) in rest.chunks(4).enumerate() {
                let mut b = [0u8; 4];
                b[..w.len()].copy_from_slice(w);
                if let Some(slot) = img.get_mut(0x40 + i) {
                    *slot = u32::from_le_bytes(b);
                }
            }
            return IdromCase {
                llio: spec.llio(0),
                image: img,
                config: String::new(),
            };
        }
    };
    if tweak & 0x80 != 0 {
        llio.connectors
            .truncate(1 + (tweak as usize & 0x7) % llio.connectors.len().max(1));
        llio.pins_per_connector = match tweak >> 3 & 0xF {
            0 => llio.pins_per_connector,
            k => [0, 1, 5, 17, 24, 29, 32, 33, 37, 64][k as usize % 10],
        };
    }
    for edit in rest.chunks(6) {
        if edit.len() < 6 {
            break;
        }
        // Mostly the identification and IDROM area (0x0100..0x0900).
        let at = 0x40 + (u16::from_le_bytes([edit[0], edit[1]]) as usize % 0x200);
        let v = u32::from_le_bytes([edit[2], edit[3], edit[4], edit[5]]);
        let value = match edit[2] % 8 {
            0 => 0,
            1 => u32::MAX,
            2 => image[at] ^ (1 << (edit[3] % 32)),
            3 => image[at].wrapping_add(edit[4] as u32) & 0xFF,
            4 => v & 0xFFFF,
            _ => v,
        };
        image[at] = value;
    }
    IdromCase {
        llio,
        image,
        config: String::new(),
    }
}

/// The IDROM loader on the board `data` decodes to: no panic; an accepted
/// board's pins, instances and registers are what the driver relies on;
/// a refusal says why.
pub fn idrom_image(data: &[u8]) {
    let case = decode(data);
    let config = config::parse(&case.config).unwrap_or_default();
    let mut t = ImageTransport::new(case.image, "fuzz");
    let mut log = MessageLog::default();
    match firmware::load(&case.llio, &config, Debug::default(), &mut t, &mut log) {
        Ok(fw) => {
            assert_eq!(fw.pins.len() as u32, fw.idrom.io_width);
            assert_eq!(fw.idrom.port_width, case.llio.pins_per_connector);
            assert_eq!(fw.idrom.io_ports as usize, case.llio.connectors.len());
            for p in &fw.pins {
                assert!((p.port as usize) < case.llio.connectors.len() && p.bit < 32);
                if let PinOwner::Module { gtag, .. } = p.owner {
                    assert!([4, 5, 6].contains(&gtag), "pin {p:?}");
                }
            }
            for m in [
                Some(fw.ioport),
                fw.watchdog,
                fw.encoder,
                fw.stepgen,
                fw.pwmgen,
                fw.led,
            ]
            .into_iter()
            .flatten()
            {
                assert!(m.instances >= 1);
                if m.md.gtag != crate::regs::gtag::LED {
                    assert!(m.instances <= m.md.instances as u32);
                }
                assert!(md::check_window(&m.md).is_ok());
            }
        }
        Err(e) => {
            let text = e.to_string();
            assert!(!text.trim().is_empty(), "a refusal without a reason: {e:?}");
            assert!(text.lines().all(|l| !l.trim().is_empty()), "{text:?}");
        }
    }
}

/// The config string parser on `text`: no panic; a refusal says why and
/// names the token it refused (`sserial_port` excepted, whose message is
/// LinuxCNC's fixed text).
pub fn config_string(text: &str) {
    match config::parse(text) {
        Ok(c) => {
            assert!(c.num_encoders >= -1 && c.num_stepgens >= -1 && c.num_pwmgens >= -1);
            assert!((0..=8).contains(&c.stepgen_width));
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(!msg.trim().is_empty());
            let named = text
                .split_ascii_whitespace()
                .any(|t| msg.contains(t) || msg.contains(t.split('=').nth(1).unwrap_or(t)));
            assert!(named || msg.contains("sserial_port"), "{msg} for {text:?}");
        }
    }
}
