//! `limit_axis`: picks one of 2 to 10 ranges by where the feedback `fb`
//! is and outputs that range's position limits (a rotary axis allowed a
//! smaller travel while Z is low, say). The first valid range containing
//! `fb` wins; a `sticky` current range is kept while `fb` stays in it.
//! Ranges or limits given backwards raise their error pins and are
//! skipped. `personality` is the number of ranges (clamped to 2..10).

use hal_core::{In, Out, Pin, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;
use crate::notice::Notice;

/// Most ranges.
pub const MAX_RANGES: usize = 10;

/// What limit_axis writes to stderr.
pub static TEXTS: &[&str] = &[
    "limit_axis: Error in range settings! Min > Max\n",
    "limit_axis: Error in limit settings! Min > Max\n",
    "limit_axis: No Range found corresponding to feedback\n",
];

/// One range's pins.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Range {
    /// `min-limit-NN`.
    pub min_limit: f64,
    /// `max-limit-NN`.
    pub max_limit: f64,
    /// `min-range-NN`.
    pub min_range: f64,
    /// `max-range-NN`.
    pub max_range: f64,
    /// `enable-NN` (LinuxCNC consults it only for a backwards range).
    pub enable: bool,
    /// `sticky-NN`.
    pub sticky: bool,
    /// `error-range-NN` (read back).
    pub error_range: bool,
    /// `error-limit-NN` (read back).
    pub error_limit: bool,
}

/// The outputs besides the per-range error pins.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisLimits {
    /// `min-output`.
    pub min_output: f64,
    /// `max-output`.
    pub max_output: f64,
    /// `current-range`.
    pub current_range: u32,
    /// `error-no-range`.
    pub error_no_range: bool,
}

/// One call; returns the indices of [`TEXTS`] to print (as a bit set).
pub fn limit_axis(fb: f64, ranges: &mut [Range], o: &mut AxisLimits) -> u8 {
    let mut msgs = 0;
    if let Some(cur) = ranges.get(o.current_range as usize) {
        if cur.sticky && cur.min_range <= fb && fb <= cur.max_range && cur.enable {
            o.max_output = cur.max_limit;
            o.min_output = cur.min_limit;
            return msgs;
        }
    }
    for (i, r) in ranges.iter_mut().enumerate() {
        if r.max_range < r.min_range {
            if !r.enable {
                continue;
            }
            if !r.error_range {
                msgs |= 1;
                r.error_range = true;
            }
            continue;
        }
        r.error_range = false;
        if r.max_limit < r.min_limit {
            if !r.error_limit {
                msgs |= 2;
                r.error_limit = true;
            }
            continue;
        }
        r.error_limit = false;
        if r.min_range <= fb && fb <= r.max_range {
            o.max_output = r.max_limit;
            o.min_output = r.min_limit;
            o.error_no_range = false;
            o.current_range = i as u32;
            return msgs;
        }
    }
    if !o.error_no_range {
        o.error_no_range = true;
        msgs |= 4;
    }
    msgs
}

/// Pins of one range.
struct RangePins {
    min_limit: Pin<f64, In>,
    max_limit: Pin<f64, In>,
    min_range: Pin<f64, In>,
    max_range: Pin<f64, In>,
    enable: Pin<bool, In>,
    sticky: Pin<bool, In>,
    error_range: Pin<bool, Out>,
    error_limit: Pin<bool, Out>,
}

/// The `limit_axis` component.
pub struct LimitAxis;
impl HalComp for LimitAxis {
    const NAME: &'static str = "limit_axis";
    const PERSONALITY: bool = true;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let n = inst.personality.clamp(2, MAX_RANGES as i64) as usize;
        let error_no_range = inst.pin_out::<bool>("error-no-range")?;
        let min_output = inst.pin_out::<f64>("min-output")?;
        let max_output = inst.pin_out::<f64>("max-output")?;
        let fb = inst.pin_in::<f64>("fb")?;
        let current_range = inst.pin_out::<u32>("current-range")?;
        let mut pins = Vec::with_capacity(n);
        for i in 0..n {
            pins.push(RangePins {
                min_limit: inst.pin_in(&format!("min-limit-{i:02}"))?,
                max_limit: inst.pin_in(&format!("max-limit-{i:02}"))?,
                min_range: inst.pin_in(&format!("min-range-{i:02}"))?,
                max_range: inst.pin_in(&format!("max-range-{i:02}"))?,
                enable: inst.pin_in(&format!("enable-{i:02}"))?,
                sticky: inst.pin_in(&format!("sticky-{i:02}"))?,
                error_range: inst.pin_out_init(&format!("error-range-{i:02}"), true)?,
                error_limit: inst.pin_out_init(&format!("error-limit-{i:02}"), true)?,
            });
        }
        let notice = Notice::new(TEXTS);
        let mut ranges = vec![Range::default(); n];
        inst.funct("_", true, move |_| {
            for (r, p) in ranges.iter_mut().zip(&pins) {
                *r = Range {
                    min_limit: p.min_limit.get(),
                    max_limit: p.max_limit.get(),
                    min_range: p.min_range.get(),
                    max_range: p.max_range.get(),
                    enable: p.enable.get(),
                    sticky: p.sticky.get(),
                    error_range: p.error_range.get(),
                    error_limit: p.error_limit.get(),
                };
            }
            let mut o = AxisLimits {
                min_output: min_output.get(),
                max_output: max_output.get(),
                current_range: current_range.get(),
                error_no_range: error_no_range.get(),
            };
            let msgs = limit_axis(fb.get(), &mut ranges, &mut o);
            for k in 0..3 {
                if msgs & (1 << k) != 0 {
                    notice.post(k);
                }
            }
            for (r, p) in ranges.iter().zip(&pins) {
                p.error_range.set(r.error_range);
                p.error_limit.set(r.error_limit);
            }
            min_output.set(o.min_output);
            max_output.set(o.max_output);
            current_range.set(o.current_range);
            error_no_range.set(o.error_no_range);
        })
    }
}
halcomp_module!(pub MODULE, LimitAxis, "dynamic range based axis limits");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float, U32};

    fn range(min_range: f64, max_range: f64, min_limit: f64, max_limit: f64) -> Range {
        Range {
            min_range,
            max_range,
            min_limit,
            max_limit,
            enable: true,
            ..Default::default()
        }
    }

    #[test]
    fn the_first_matching_range_gives_the_limits() {
        let mut r = [
            range(-10.0, 0.0, -90.0, 90.0),
            range(-40.0, -10.0, -10.0, 10.0),
        ];
        let mut o = AxisLimits::default();
        assert_eq!(limit_axis(-5.0, &mut r, &mut o), 0);
        assert_eq!(
            (o.min_output, o.max_output, o.current_range),
            (-90.0, 90.0, 0)
        );
        limit_axis(-20.0, &mut r, &mut o);
        assert_eq!((o.min_output, o.current_range), (-10.0, 1));
        // -10 is in both: the first wins unless the current one is sticky.
        limit_axis(-10.0, &mut r, &mut o);
        assert_eq!(o.current_range, 0);
        limit_axis(-20.0, &mut r, &mut o);
        r[1].sticky = true;
        limit_axis(-10.0, &mut r, &mut o);
        assert_eq!(o.current_range, 1);
    }

    #[test]
    fn bad_ranges_and_no_match_raise_errors_once() {
        let mut r = [range(5.0, 1.0, 0.0, 1.0), range(0.0, 1.0, 2.0, 1.0)];
        let mut o = AxisLimits::default();
        assert_eq!(limit_axis(0.5, &mut r, &mut o), 1 | 2 | 4);
        assert!(r[0].error_range && r[1].error_limit && o.error_no_range);
        assert_eq!(limit_axis(0.5, &mut r, &mut o), 0, "reported once");
        r[1].max_limit = 3.0;
        limit_axis(0.5, &mut r, &mut o);
        assert!(!r[1].error_limit && !o.error_no_range);
        assert_eq!(o.max_output, 3.0);
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("limit-axis");
        h.load(&MODULE, &["names=la", "personality=1"]).unwrap();
        let mut want: Vec<String> = [
            "error-no-range bit out 0",
            "min-output float out 0",
            "max-output float out 0",
            "fb float in 0",
            "current-range u32 out 0",
        ]
        .map(String::from)
        .to_vec();
        for i in 0..2 {
            for p in [
                "min-limit float in 0",
                "max-limit float in 0",
                "min-range float in 0",
                "max-range float in 0",
                "enable bit in 0",
                "sticky bit in 0",
                "error-range bit out 1",
                "error-limit bit out 1",
            ] {
                let (name, rest) = p.split_once(' ').unwrap();
                want.push(format!("{name}-{i:02} {rest}"));
            }
        }
        let want: Vec<&str> = want.iter().map(String::as_str).collect();
        h.check_pins("la", &want);
        h.thread(&["la"]);
        h.set("la.max-range-01", Float(5.0));
        h.set("la.min-range-01", Float(1.0));
        h.set("la.max-limit-01", Float(7.0));
        h.expect(&[("la.fb", Float(2.0))], "la.current-range", U32(1));
        assert_eq!(h.get("la.max-output"), Float(7.0));
        assert_eq!(h.get("la.error-range-00"), Bit(false));
    }
}
