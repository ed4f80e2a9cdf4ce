//! `matrix_kb`: a matrix keypad. Either it scans the keypad itself
//! (`s` in the size: drives one `row-NN-out` per call, reads the
//! `col-NN-in`, debounces over two scans and reports each change as a
//! `keycode`), or it decodes the keycodes a Mesa 7I73 reports. Either
//! way each key has a pin `key.r<R>c<C>` (hex row and column) that is
//! TRUE while pressed, limited to `key_rollover` keys at once.
//!
//! `loadrt matrix_kb config=4x3s,8x8 names=pad,panel` (names optional:
//! `matrix_kb.N`).

use crate::error::CompError;
use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, In, Out, Param, Pin, Result, Rw};

/// Most keypads one load may create.
pub const MAX_CHAN: usize = 8;
/// Most columns.
pub const MAX_COLS: u32 = 32;
/// Most rows (LinuxCNC sets no limit; this keeps keycodes in 32 bits).
pub const MAX_ROWS: u32 = 256;
/// The keycode that says "no change".
pub const NO_CHANGE: u32 = 0x40;

/// One keypad's size and mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KbConfig {
    /// Rows.
    pub rows: u32,
    /// Columns.
    pub cols: u32,
    /// TRUE to scan the matrix here.
    pub scan: bool,
}

impl KbConfig {
    /// Parses `RxC` with an optional `s` (letters in any case; other
    /// characters are ignored, as in LinuxCNC).
    pub fn parse(s: &str) -> std::result::Result<KbConfig, CompError> {
        let config = || s.to_string();
        let (mut rows, mut a, mut scan) = (0u32, 0u32, false);
        for ch in s.chars().map(|c| c.to_ascii_lowercase()) {
            match ch {
                'x' => {
                    rows = a;
                    a = 0;
                }
                '0'..='9' => a = a.saturating_mul(10).saturating_add(ch as u32 - '0' as u32),
                's' => scan = true,
                _ => {}
            }
        }
        let cols = a;
        if rows == 0 || cols == 0 {
            return Err(CompError::KbSize { config: config() });
        }
        if cols > MAX_COLS {
            return Err(CompError::KbColumns {
                config: config(),
                max: MAX_COLS,
            });
        }
        if rows > MAX_ROWS {
            return Err(CompError::KbRows {
                config: config(),
                max: MAX_ROWS,
            });
        }
        Ok(KbConfig { rows, cols, scan })
    }

    /// Bits of the keycode holding the column (at least 1).
    pub fn rowshift(&self) -> u32 {
        let mut shift = 1;
        while self.cols > (1u32 << shift) {
            shift += 1;
        }
        shift
    }

    /// The key-down and key-up flags above the row and column bits.
    pub fn flags(&self) -> (u32, u32) {
        let (mut down, mut up) = (0xC0u32, 0x80u32);
        while (self.rows << self.rowshift()) > down {
            down <<= 1;
            up <<= 1;
        }
        (down, up)
    }
}

/// One keypad's decoding and scanning state.
#[derive(Debug, Clone)]
pub struct Keypad {
    cfg: KbConfig,
    rowshift: u32,
    keydown: u32,
    keyup: u32,
    now: Vec<u32>,
    then: Vec<u32>,
    row: usize,
    num_keys: u32,
}

impl Keypad {
    /// A keypad of `cfg`, no key pressed.
    pub fn new(cfg: KbConfig) -> Keypad {
        let (keydown, keyup) = cfg.flags();
        Keypad {
            cfg,
            rowshift: cfg.rowshift(),
            keydown,
            keyup,
            now: vec![0; cfg.rows as usize],
            then: vec![0; cfg.rows as usize],
            row: 0,
            num_keys: 0,
        }
    }

    /// The key index a keycode names, if it is on the keypad.
    fn key(&self, keycode: u32) -> Option<usize> {
        let code = keycode & !(self.keydown | self.keyup);
        let r = code >> self.rowshift;
        let c = code & !(u32::MAX << self.rowshift);
        (r < self.cfg.rows && c < self.cfg.cols).then(|| (r * self.cfg.cols + c) as usize)
    }

    fn press(&mut self, keycode: u32, rollover: u32, keys: &mut [bool]) {
        if let Some(k) = self.key(keycode) {
            if self.num_keys < rollover {
                self.num_keys += 1;
                keys[k] = true;
            }
        }
    }

    fn release(&mut self, keycode: u32, keys: &mut [bool]) {
        if let Some(k) = self.key(keycode) {
            self.num_keys = self.num_keys.saturating_sub(1);
            keys[k] = false;
        }
    }

    /// One call decoding `keycode` from a 7I73 into `keys` (index
    /// `row * cols + col`).
    pub fn decode(&mut self, keycode: u32, rollover: u32, keys: &mut [bool]) {
        if keycode == NO_CHANGE {
            return;
        }
        if keycode & self.keydown == self.keydown {
            self.press(keycode, rollover, keys);
        } else if keycode & self.keydown == self.keyup {
            self.release(keycode, keys);
        }
    }

    /// One scanning call: `cols` read now (for the row driven since the
    /// last call), with `invert` for negative logic. Updates `keys` and
    /// `rows_out` and returns the keycode to output.
    pub fn scan(
        &mut self,
        cols: &[bool],
        invert: bool,
        rollover: u32,
        keys: &mut [bool],
        rows_out: &mut [bool],
    ) -> u32 {
        let scan = cols
            .iter()
            .enumerate()
            .fold(0u32, |s, (c, &b)| s + (((b != invert) as u32) << c));
        let row = self.row;
        let mut keycode = NO_CHANGE;
        if scan == self.now[row] && scan != self.then[row] {
            for c in 0..self.cfg.cols {
                let mask = 1u32 << c;
                let base = ((row as u32) << self.rowshift) + c;
                if self.then[row] & mask != 0 && scan & mask == 0 {
                    keycode = self.keyup + base;
                    self.release(keycode, keys);
                } else if self.then[row] & mask == 0 && scan & mask != 0 {
                    keycode = self.keydown + base;
                    self.press(keycode, rollover, keys);
                }
            }
        }
        self.then[row] = self.now[row];
        self.now[row] = scan;
        rows_out[row] = invert;
        self.row = (row + 1) % self.cfg.rows as usize;
        rows_out[self.row] = !invert;
        keycode
    }
}

/// The module parameters.
pub const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "config",
        kind: ParamKind::StrArray(MAX_CHAN),
        help: "size of each keypad, RxC, with s to scan it here",
    },
    ParamDecl {
        name: "names",
        kind: ParamKind::StrArray(MAX_CHAN),
        help: "names of the keypads",
    },
];

/// The `matrix_kb` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "matrix_kb",
    params: PARAMS,
    help: "convert integers to HAL pins, optionally scanning a key matrix",
    load,
};

/// Pins of a scanning keypad.
struct Scanning {
    rows: Vec<Pin<bool, Out>>,
    cols: Vec<Pin<bool, In>>,
    keycode: Pin<u32, Out>,
    invert: Param<bool, Rw>,
    rollover: Param<u32, Rw>,
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let bad = |param: &str, reason: String| HalError::ModuleParam {
        module: "matrix_kb".into(),
        param: param.into(),
        reason,
    };
    let config = args.str_array("config");
    let names = args.str_array("names");
    if config.is_empty() {
        return Err(bad(
            "config",
            "give each keypad's size, e.g. config=4x3s".into(),
        ));
    }
    if !names.is_empty() && names.len() != config.len() {
        return Err(bad(
            "names",
            "the numbers of sizes and names must match".into(),
        ));
    }
    let cfgs: Vec<KbConfig> = config
        .iter()
        .map(|c| KbConfig::parse(c).map_err(|r| bad("config", r.to_string())))
        .collect::<Result<_>>()?;
    let mut b = host.new_rt_component("matrix_kb")?;
    for (i, cfg) in cfgs.into_iter().enumerate() {
        let name = match names.get(i) {
            Some(n) if n.is_empty() => return Err(bad("names", format!("name {i} is empty"))),
            Some(n) => n.clone(),
            None => format!("matrix_kb.{i}"),
        };
        let c = b.component();
        // Created column by column, as LinuxCNC does.
        let mut key_pins: Vec<Option<Pin<bool, Out>>> =
            (0..cfg.rows * cfg.cols).map(|_| None).collect();
        for col in 0..cfg.cols {
            for row in 0..cfg.rows {
                key_pins[(row * cfg.cols + col) as usize] =
                    Some(c.pin(&format!("{name}.key.r{row:x}c{col:x}"))?);
            }
        }
        let key_pins: Vec<Pin<bool, Out>> = key_pins.into_iter().flatten().collect();
        let mut keys = vec![false; key_pins.len()];
        let mut pad = Keypad::new(cfg);
        if cfg.scan {
            let s = Scanning {
                rows: (0..cfg.rows)
                    .map(|r| c.pin(&format!("{name}.row-{r:02}-out")))
                    .collect::<Result<_>>()?,
                cols: (0..cfg.cols)
                    .map(|k| c.pin(&format!("{name}.col-{k:02}-in")))
                    .collect::<Result<_>>()?,
                keycode: c.pin(&format!("{name}.keycode"))?,
                invert: c.param(&format!("{name}.negative-logic"), true)?,
                rollover: c.param(&format!("{name}.key_rollover"), 2)?,
            };
            let mut cols = vec![false; cfg.cols as usize];
            let mut rows_out = vec![false; cfg.rows as usize];
            b.funct(&name, true, move |_| {
                for (v, p) in cols.iter_mut().zip(&s.cols) {
                    *v = p.get();
                }
                for (v, p) in rows_out.iter_mut().zip(&s.rows) {
                    *v = p.get();
                }
                for (v, p) in keys.iter_mut().zip(&key_pins) {
                    *v = p.get();
                }
                let code = pad.scan(
                    &cols,
                    s.invert.get(),
                    s.rollover.get(),
                    &mut keys,
                    &mut rows_out,
                );
                s.keycode.set(code);
                for (v, p) in rows_out.iter().zip(&s.rows) {
                    p.set(*v);
                }
                for (v, p) in keys.iter().zip(&key_pins) {
                    p.set(*v);
                }
            })?;
        } else {
            let keycode: Pin<u32, In> = c.pin(&format!("{name}.keycode"))?;
            b.funct(&name, true, move |_| {
                for (v, p) in keys.iter_mut().zip(&key_pins) {
                    *v = p.get();
                }
                pad.decode(keycode.get(), 2, &mut keys);
                for (v, p) in keys.iter().zip(&key_pins) {
                    p.set(*v);
                }
            })?;
        }
    }
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, U32};

    #[test]
    fn sizes_and_keycode_layout() {
        let c = KbConfig::parse("4x3S").unwrap();
        assert_eq!((c.rows, c.cols, c.scan), (4, 3, true));
        assert_eq!(c.rowshift(), 2);
        assert_eq!(c.flags(), (0xC0, 0x80));
        let big = KbConfig::parse("16x16").unwrap();
        assert_eq!(big.rowshift(), 4);
        assert_eq!(big.flags(), (0x180, 0x100));
        for bad in ["4", "x3", "4x33", "0x0"] {
            assert!(KbConfig::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn decoding_7i73_codes_with_rollover() {
        let cfg = KbConfig::parse("4x4").unwrap();
        let mut pad = Keypad::new(cfg);
        let mut keys = vec![false; 16];
        // Key down at row 1, column 2.
        pad.decode(0xC0 | (1 << 2) | 2, 2, &mut keys);
        assert!(keys[6]);
        pad.decode(0xC0 | 3, 2, &mut keys);
        pad.decode(0xC0 | 5, 2, &mut keys);
        assert!(keys[3] && !keys[5], "two keys at most");
        pad.decode(0x80 | (1 << 2) | 2, 2, &mut keys);
        assert!(!keys[6]);
        pad.decode(NO_CHANGE, 2, &mut keys);
    }

    #[test]
    fn scanning_debounces_over_two_scans() {
        let cfg = KbConfig::parse("2x2s").unwrap();
        let mut pad = Keypad::new(cfg);
        let (mut keys, mut rows) = (vec![false; 4], vec![false; 2]);
        // Negative logic off; column 1 pressed while row 0 is driven.
        let mut code = 0;
        for _ in 0..4 {
            code = pad.scan(&[false, pad.row == 0], false, 2, &mut keys, &mut rows);
            if code != NO_CHANGE {
                break;
            }
        }
        assert_eq!(code, 0xC0 | 1);
        assert!(keys[1]);
        assert_eq!(rows, [false, true], "row 1 driven next");
    }

    #[test]
    fn pins_per_mode_and_bad_configs() {
        let mut h = TestHost::new("matrix-kb");
        for bad in [&[][..], &["config=4"], &["config=2x2,2x2", "names=a"]] {
            h.check_load_fails(&MODULE, bad);
        }
        h.load(&MODULE, &["config=2x2s,1x2", "names=pad,dec"])
            .unwrap();
        h.check_pins(
            "pad",
            &[
                "key.r0c0 bit out 0",
                "key.r0c1 bit out 0",
                "key.r1c0 bit out 0",
                "key.r1c1 bit out 0",
                "row-00-out bit out 0",
                "row-01-out bit out 0",
                "col-00-in bit in 0",
                "col-01-in bit in 0",
                "keycode u32 out 0",
            ],
        );
        h.check_params("pad", &["negative-logic bit rw 1", "key_rollover u32 rw 2"]);
        h.check_pins(
            "dec",
            &[
                "key.r0c0 bit out 0",
                "key.r0c1 bit out 0",
                "keycode u32 in 0",
            ],
        );
        assert_eq!(h.functs(), ["dec", "pad"]);
        h.thread(&["dec"]);
        h.expect(&[("dec.keycode", U32(0xC1))], "dec.key.r0c1", Bit(true));
    }
}
