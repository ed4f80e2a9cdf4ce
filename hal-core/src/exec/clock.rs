//! The clocks of the executor: CLOCK_MONOTONIC for deadlines, and a cheap
//! timestamp counter for function timing (read once per function boundary).

/// Nanoseconds on CLOCK_MONOTONIC.
#[inline]
pub fn monotonic_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes into the timespec we pass.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// Sleeps until `deadline_ns` on CLOCK_MONOTONIC.
#[inline]
pub fn sleep_until(deadline_ns: u64) {
    let ts = libc::timespec {
        tv_sec: (deadline_ns / 1_000_000_000) as libc::time_t,
        tv_nsec: (deadline_ns % 1_000_000_000) as libc::c_long,
    };
    loop {
        // SAFETY: clock_nanosleep reads the timespec; no remainder is used
        // with TIMER_ABSTIME.
        let rc = unsafe {
            libc::clock_nanosleep(
                libc::CLOCK_MONOTONIC,
                libc::TIMER_ABSTIME,
                &ts,
                std::ptr::null_mut(),
            )
        };
        if rc != libc::EINTR {
            return;
        }
    }
}

/// A calibrated tick source: the TSC where the CPU says it is constant and
/// non-stop, else CLOCK_MONOTONIC.
#[derive(Clone, Copy, Debug)]
pub struct TickClock {
    use_tsc: bool,
    /// Nanoseconds per tick, as a 32.32 fixed-point number.
    mult: u64,
}

impl TickClock {
    /// Calibrates against CLOCK_MONOTONIC (takes about 10 ms with a TSC).
    pub fn calibrate() -> TickClock {
        if std::env::var_os("HAL_NO_TSC").is_some() || !tsc_usable() {
            return TickClock {
                use_tsc: false,
                mult: 1 << 32,
            };
        }
        let (t0, c0) = (monotonic_ns(), rdtsc());
        std::thread::sleep(std::time::Duration::from_millis(10));
        let (t1, c1) = (monotonic_ns(), rdtsc());
        let ticks = c1.wrapping_sub(c0);
        if ticks == 0 || c1 < c0 {
            return TickClock {
                use_tsc: false,
                mult: 1 << 32,
            };
        }
        TickClock {
            use_tsc: true,
            mult: (((t1 - t0) as u128) << 32).div_euclid(ticks as u128) as u64,
        }
    }

    /// Whether the TSC is in use.
    pub fn uses_tsc(&self) -> bool {
        self.use_tsc
    }

    /// The current tick count.
    #[inline(always)]
    pub fn now(&self) -> u64 {
        if self.use_tsc {
            rdtsc()
        } else {
            monotonic_ns()
        }
    }

    /// Converts a tick difference to nanoseconds.
    #[inline(always)]
    pub fn to_ns(&self, ticks: u64) -> u64 {
        ((ticks as u128 * self.mult as u128) >> 32) as u64
    }
}

/// The CPU's timestamp counter (CLOCK_MONOTONIC ns where there is none).
#[inline(always)]
pub(crate) fn rdtsc() -> u64 {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: rdtsc has no memory effects and exists on every x86_64 CPU.
        unsafe { core::arch::x86_64::_rdtsc() }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        monotonic_ns()
    }
}

fn tsc_usable() -> bool {
    if !cfg!(target_arch = "x86_64") {
        return false;
    }
    let Ok(info) = std::fs::read_to_string("/proc/cpuinfo") else {
        return false;
    };
    let flags = info
        .lines()
        .find(|l| l.starts_with("flags"))
        .unwrap_or_default();
    let has = |f: &str| flags.split_whitespace().any(|x| x == f);
    has("constant_tsc") && has("nonstop_tsc")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_clock_agrees_with_monotonic() {
        let c = TickClock::calibrate();
        let (t0, k0) = (monotonic_ns(), c.now());
        std::thread::sleep(std::time::Duration::from_millis(20));
        let (t1, k1) = (monotonic_ns(), c.now());
        let measured = c.to_ns(k1 - k0) as f64;
        let real = (t1 - t0) as f64;
        assert!((measured / real - 1.0).abs() < 0.05, "{measured} vs {real}");
    }
}
