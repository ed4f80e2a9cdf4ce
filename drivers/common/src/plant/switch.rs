//! [`Switch`]: a home or limit switch actuated over a range of axis
//! positions, with normally-open or normally-closed contacts.

/// A switch on an axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Switch {
    /// Lowest actuating position.
    pub from: f64,
    /// Highest actuating position.
    pub to: f64,
    /// Whether the contacts open when actuated (the usual wiring of
    /// limit switches, so a broken wire reads as a tripped limit).
    pub normally_closed: bool,
}

impl Switch {
    /// Actuated at `position` and beyond (a positive limit).
    pub fn at_or_above(position: f64) -> Switch {
        Switch::between(position, f64::INFINITY)
    }

    /// Actuated at `position` and below (a negative limit).
    pub fn at_or_below(position: f64) -> Switch {
        Switch::between(f64::NEG_INFINITY, position)
    }

    /// Actuated from `from` to `to` (a home switch with a cam); the
    /// bounds may come in either order.
    pub fn between(from: f64, to: f64) -> Switch {
        Switch {
            from: from.min(to),
            to: from.max(to),
            normally_closed: false,
        }
    }

    /// The same with normally-closed contacts.
    pub fn normally_closed(self) -> Switch {
        Switch {
            normally_closed: true,
            ..self
        }
    }

    /// Whether the axis at `position` actuates the switch.
    pub fn is_actuated(&self, position: f64) -> bool {
        (self.from..=self.to).contains(&position)
    }

    /// Whether the contacts are closed (conducting) at `position`: what
    /// an input wired to the switch sees.
    pub fn is_closed(&self, position: f64) -> bool {
        self.is_actuated(position) != self.normally_closed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_and_contacts() {
        let home = Switch::between(10.0, 9.5);
        assert!(!home.is_actuated(9.4) && home.is_actuated(9.5) && home.is_actuated(10.0));
        assert!(!home.is_actuated(10.01));
        assert!(home.is_closed(9.7) && !home.is_closed(0.0));
        let limit = Switch::at_or_above(100.0).normally_closed();
        assert!(limit.is_closed(99.9) && !limit.is_closed(100.0) && !limit.is_closed(1e9));
        let neg = Switch::at_or_below(-5.0);
        assert!(neg.is_actuated(-5.0) && neg.is_actuated(-1e9) && !neg.is_actuated(-4.9));
    }
}
