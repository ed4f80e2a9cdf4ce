//! The figures of one thread (from its own counters and histogram),
//! percentiles read off the histogram, and LinuxCNC's verdict.

use hal_core::{latency_bucket_floor_us, ThreadInfo};

/// One thread's wake-up latency figures, as the thread recorded them.
#[derive(Debug, Clone, PartialEq)]
pub struct ThreadStats {
    /// The HAL thread's name.
    pub name: String,
    /// Its period in ns.
    pub period_ns: i64,
    /// Cycles run.
    pub cycles: u64,
    /// Deadlines missed because a cycle ran late.
    pub overruns: u64,
    /// Smallest latency seen (ns).
    pub min_ns: Option<u64>,
    /// Largest latency seen (ns).
    pub max_ns: Option<u64>,
    /// Wake-ups per histogram bucket ([`hal_core::latency_bucket`]).
    pub histogram: Vec<u64>,
}

impl ThreadStats {
    /// The figures of a thread snapshot.
    pub fn from_info(t: &ThreadInfo) -> ThreadStats {
        ThreadStats {
            name: t.name.clone(),
            period_ns: t.period,
            cycles: t.cycles,
            overruns: t.overruns,
            min_ns: t.latency_min_ns,
            max_ns: t.latency_max_ns,
            histogram: t.latency_histogram.clone(),
        }
    }

    /// Wake-ups counted in the histogram.
    pub fn samples(&self) -> u64 {
        self.histogram.iter().sum()
    }

    /// An upper bound of the `p`-quantile (0 < p <= 1) in ns: the upper
    /// edge of the histogram bucket the quantile falls in, never above
    /// the exact maximum nor below the exact minimum. `None` without
    /// samples.
    pub fn percentile_ns(&self, p: f64) -> Option<u64> {
        let total = self.samples();
        if total == 0 {
            return None;
        }
        let rank = ((p.clamp(0.0, 1.0) * total as f64).ceil() as u64).clamp(1, total);
        let mut seen = 0;
        let bucket = self.histogram.iter().position(|&n| {
            seen += n;
            seen >= rank
        })?;
        let upper = if bucket + 1 < self.histogram.len() {
            latency_bucket_floor_us(bucket + 1) * 1000
        } else {
            u64::MAX
        };
        let upper = self.max_ns.map_or(upper, |m| upper.min(m));
        Some(self.min_ns.map_or(upper, |m| upper.max(m)))
    }
}

/// The thresholds of LinuxCNC's latency-test documentation, on the
/// largest latency (its "max jitter").
pub const SOFTWARE_STEPPING_GOOD_NS: u64 = 20_000;
/// Above this, software stepping is out.
pub const SOFTWARE_STEPPING_MAX_NS: u64 = 50_000;
/// Above this, even a hardware step generator gives poor results.
pub const HARDWARE_STEPPING_MAX_NS: u64 = 500_000;

/// What the figures allow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Below 20 µs: software stepping gives very nice results.
    SoftwareStepping,
    /// 20 to 50 µs: software stepping works, at lower step rates.
    SoftwareSteppingSlow,
    /// 50 to 500 µs: no software stepping; a hardware card is fine.
    HardwareOnly,
    /// Above 500 µs: neither.
    Neither,
}

impl Verdict {
    /// The verdict for a largest latency of `max_ns`.
    pub fn for_max(max_ns: u64) -> Verdict {
        if max_ns < SOFTWARE_STEPPING_GOOD_NS {
            Verdict::SoftwareStepping
        } else if max_ns <= SOFTWARE_STEPPING_MAX_NS {
            Verdict::SoftwareSteppingSlow
        } else if max_ns <= HARDWARE_STEPPING_MAX_NS {
            Verdict::HardwareOnly
        } else {
            Verdict::Neither
        }
    }

    /// A few words for the plot's title.
    pub fn short(self) -> &'static str {
        match self {
            Verdict::SoftwareStepping => "SOFTWARE STEPPING OK",
            Verdict::SoftwareSteppingSlow => "SOFTWARE STEPPING AT LOW STEP RATES",
            Verdict::HardwareOnly => "HARDWARE STEPPING ONLY",
            Verdict::Neither => "NEITHER SOFTWARE NOR HARDWARE STEPPING",
        }
    }

    /// One plain sentence.
    pub fn sentence(self) -> &'static str {
        match self {
            Verdict::SoftwareStepping => {
                "software stepping: yes (max latency under 20 us); hardware stepping: yes"
            }
            Verdict::SoftwareSteppingSlow => {
                "software stepping: yes, at limited step rates (max latency 20-50 us); \
                 hardware stepping: yes"
            }
            Verdict::HardwareOnly => {
                "hardware stepping only (max latency 50-500 us): no software stepping"
            }
            Verdict::Neither => "neither software nor hardware stepping (max latency above 500 us)",
        }
    }
}

/// The verdict on the largest latency any thread saw; `None` before any
/// thread ran.
pub fn verdict(threads: &[ThreadStats]) -> Option<(Verdict, u64)> {
    let max = threads.iter().filter_map(|t| t.max_ns).max()?;
    Some((Verdict::for_max(max), max))
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_core::latency_bucket;

    fn stats(latencies_ns: &[u64]) -> ThreadStats {
        let mut histogram = vec![0u64; 64];
        for &l in latencies_ns {
            histogram[latency_bucket(l)] += 1;
        }
        ThreadStats {
            name: "t".into(),
            period_ns: 1_000_000,
            cycles: latencies_ns.len() as u64,
            overruns: 0,
            min_ns: latencies_ns.iter().copied().min(),
            max_ns: latencies_ns.iter().copied().max(),
            histogram,
        }
    }

    #[test]
    fn percentiles_are_bucket_upper_edges_within_min_and_max() {
        // 990 wake-ups at 2.5 us, 9 at 7.2 us, one at 40 us.
        let mut l = vec![2_500; 990];
        l.extend([7_200; 9]);
        l.push(40_000);
        let s = stats(&l);
        assert_eq!(s.samples(), 1000);
        assert_eq!(s.percentile_ns(0.5), Some(3_000));
        assert_eq!(s.percentile_ns(0.99), Some(3_000));
        assert_eq!(s.percentile_ns(0.999), Some(8_000));
        // The top bucket [40, 48) us is capped by the exact maximum.
        assert_eq!(s.percentile_ns(1.0), Some(40_000));
        // One sample: every percentile is that sample.
        let one = stats(&[2_300]);
        assert_eq!(one.percentile_ns(0.5), Some(2_300));
        assert_eq!(stats(&[]).percentile_ns(0.5), None);
    }

    #[test]
    fn linuxcnc_thresholds() {
        assert_eq!(Verdict::for_max(19_999), Verdict::SoftwareStepping);
        assert_eq!(Verdict::for_max(20_000), Verdict::SoftwareSteppingSlow);
        assert_eq!(Verdict::for_max(50_000), Verdict::SoftwareSteppingSlow);
        assert_eq!(Verdict::for_max(50_001), Verdict::HardwareOnly);
        assert_eq!(Verdict::for_max(500_000), Verdict::HardwareOnly);
        assert_eq!(Verdict::for_max(500_001), Verdict::Neither);
        let v = verdict(&[stats(&[3_000, 70_000]), stats(&[12_000])]);
        assert_eq!(v, Some((Verdict::HardwareOnly, 70_000)));
        assert_eq!(verdict(&[stats(&[])]), None);
    }
}
