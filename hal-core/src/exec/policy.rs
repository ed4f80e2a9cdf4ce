//! What a thread does with a missed deadline.

/// What a thread does when a cycle ends after its next deadline (or wakes
/// up after it).
///
/// `Skip` keeps every cycle on the thread's time grid: the deadlines
/// already missed are skipped and counted as overruns, and the next cycle
/// runs at the next deadline still ahead. Components that assume one
/// period per cycle then lose the missed periods (a stepgen falls behind
/// its command for a moment and catches up within its own limits), but no
/// cycle ever runs early and a stall is never followed by a burst.
///
/// `CatchUp` is LinuxCNC's behaviour: every deadline gets its cycle, late
/// ones run back to back until the thread is on time again, and each late
/// cycle counts one overrun. The number of cycles always matches the time
/// elapsed (counters and integrators driven per cycle stay in step with
/// the clock), at the price of a burst of cycles closer together than a
/// period after every stall, which the hardware sees as a jump, and which
/// keeps slower threads waiting.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MissedDeadline {
    /// Skip missed deadlines and count them (the default).
    #[default]
    Skip,
    /// Run late cycles back to back (LinuxCNC's behaviour).
    CatchUp,
}

impl MissedDeadline {
    /// The word `setthread` takes and prints: `skip` or `catch-up`.
    pub fn name(self) -> &'static str {
        match self {
            MissedDeadline::Skip => "skip",
            MissedDeadline::CatchUp => "catch-up",
        }
    }

    /// Parses [`MissedDeadline::name`]'s words.
    pub fn from_name(s: &str) -> Option<MissedDeadline> {
        match s {
            "skip" => Some(MissedDeadline::Skip),
            "catch-up" => Some(MissedDeadline::CatchUp),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn policy_names_round_trip() {
        for p in [MissedDeadline::Skip, MissedDeadline::CatchUp] {
            assert_eq!(MissedDeadline::from_name(p.name()), Some(p));
        }
        assert_eq!(MissedDeadline::from_name("later"), None);
    }
}
