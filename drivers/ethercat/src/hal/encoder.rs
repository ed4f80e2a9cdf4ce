//! The encoder of an EL5101 or an EL7041 as lcec drives it: the 16-bit
//! counter extended into `enc-count` and scaled into `enc-pos`; a latch
//! (index C, or the external input on its positive or negative edge)
//! that the terminal reports valid makes the latched count the new
//! zero, clears its `enc-*-enable` pin and shows the value in
//! `enc-raw-latch`; `enc-set-raw-count` drops once the terminal reports
//! the counter set; `enc-reset` zeroes the count. The EL5101 adds its
//! frequency and period.

use hal_core::HalHost;

use super::field::Field;
use super::slave::Named;
use crate::master::Layout;

/// Seconds per count of the EL5101's period value.
const PERIOD_SCALE: f64 = 500e-9;

/// The encoder's pins (indices into the slave's pins) and the entries
/// no pin carries whole.
pub(crate) struct EncoderPins {
    raw_count: Option<usize>,
    reset: Option<usize>,
    pos_scale: Option<usize>,
    count: Option<usize>,
    pos: Option<usize>,
    raw_latch: Option<usize>,
    latch_c_valid: Option<usize>,
    latch_ext_valid: Option<usize>,
    latch_c_enable: Option<usize>,
    ext_pos_enable: Option<usize>,
    ext_neg_enable: Option<usize>,
    set_raw_count: Option<usize>,
    raw_freq: Option<usize>,
    raw_period: Option<usize>,
    frequency: Option<usize>,
    period: Option<usize>,
    frequency_scale: Option<usize>,
    /// The latched count in the inputs.
    latch: Option<Field>,
    /// The terminal's "counter set" bit in the inputs.
    set_done: Option<Field>,
}

impl EncoderPins {
    /// The encoder of slave type `kind` (EL5101 or EL7041), its pins in
    /// `p`, its entries in `layout`.
    pub(crate) fn new<H: HalHost>(kind: &str, p: &Named<'_, H>, layout: &Layout) -> EncoderPins {
        // An input entry, or `bits` of it from `bit` on (0: all of it).
        let input = |index: u16, sub: u8, bit: usize, bits: u8| {
            layout.find(index, sub, false).map(|m| Field {
                bit: m.bit + bit,
                bits: if bits == 0 { m.bits } else { bits },
            })
        };
        let el5101 = kind == "EL5101";
        EncoderPins {
            raw_count: p.index("enc-raw-count"),
            reset: p.index("enc-reset"),
            pos_scale: p.index("enc-pos-scale"),
            count: p.index("enc-count"),
            pos: p.index("enc-pos"),
            raw_latch: p.index("enc-raw-latch"),
            latch_c_valid: p.index("enc-latch-c-valid"),
            latch_ext_valid: p.index("enc-latch-ext-valid"),
            latch_c_enable: p
                .index("enc-index-c-enable")
                .or_else(|| p.index("enc-latch-c-enable")),
            ext_pos_enable: p.index("enc-index-ext-pos-enable"),
            ext_neg_enable: p.index("enc-index-ext-neg-enable"),
            set_raw_count: p.index("enc-set-raw-count"),
            raw_freq: p.index("enc-raw-freq"),
            raw_period: p.index("enc-raw-period"),
            frequency: p.index("enc-frequency"),
            period: p.index("enc-period"),
            frequency_scale: p.index("enc-frequency-scale"),
            latch: if el5101 {
                input(0x6000, 3, 0, 0)
            } else {
                input(0x6000, 0x12, 0, 0)
            },
            set_done: if el5101 {
                input(0x6000, 1, 2, 1)
            } else {
                input(0x6000, 3, 0, 1)
            },
        }
    }
}

/// What the encoder keeps between cycles.
#[derive(Default)]
pub(crate) struct Encoder {
    /// The raw count of the last cycle (None: start afresh).
    last: Option<i16>,
    count: i64,
}

impl Encoder {
    /// One cycle's reception (the slave's pins already hold its inputs);
    /// `operational`: the slave exchanged data this cycle.
    pub(crate) fn read<H: HalHost>(
        &mut self,
        inputs: &[u8],
        operational: bool,
        at: &EncoderPins,
        p: &Named<'_, H>,
    ) {
        if !operational {
            self.last = None;
            return;
        }
        let is_set = |i| p.at(i).is_some_and(|x| x.is_set());
        let set = |i, v: f64| {
            if let Some(x) = p.at(i) {
                x.set(v);
            }
        };
        let Some(raw) = p.at(at.raw_count).map(|x| x.get() as i64 as i16) else {
            return;
        };
        let mut last = self.last.unwrap_or(raw);
        if at.set_done.is_some_and(|f| f.read(inputs) != 0) {
            last = raw;
            set(at.set_raw_count, 0.0);
        }
        if self.last.is_none() || is_set(at.reset) {
            last = raw;
            self.count = 0;
        }
        let latch = at.latch.map_or(0, |f| f.read_signed(inputs) as i16);
        for (valid, enables) in [
            (at.latch_ext_valid, [at.ext_pos_enable, at.ext_neg_enable]),
            (at.latch_c_valid, [at.latch_c_enable, None]),
        ] {
            if is_set(valid) {
                set(at.raw_latch, f64::from(latch));
                last = latch;
                self.count = 0;
                for e in enables {
                    set(e, 0.0);
                }
            }
        }
        self.count += i64::from(raw.wrapping_sub(last));
        self.last = Some(raw);
        let scale = p.at(at.pos_scale).map_or(1.0, |s| s.get());
        let scale = if scale.abs() < 1e-20 {
            set(at.pos_scale, 1.0);
            1.0
        } else {
            scale
        };
        set(at.count, self.count as f64);
        set(at.pos, self.count as f64 / scale);
        if let (Some(f), Some(raw_freq)) = (p.at(at.frequency), p.at(at.raw_freq)) {
            let fs = p.at(at.frequency_scale).map_or(1.0, |x| x.get());
            f.set(raw_freq.get() * fs);
        }
        if let (Some(t), Some(raw_period)) = (p.at(at.period), p.at(at.raw_period)) {
            t.set(raw_period.get() * PERIOD_SCALE);
        }
    }
}
