//! Names of canonical pins, params and functions.
//!
//! Pins and params: `<device>.<num>.<io-type>.<chan>.<name>`, the channel
//! zero-padded to two digits when a device can have more than ten
//! channels of that type (so names sort in channel order). Functions:
//! `<device>.<num>[.<io-type>[-<range>]].read|write`. A driver whose users'
//! configs already use other names (parport's `pin-NN-out`) supplies its
//! own rule instead.

/// How one device names the channels of one io-type.
pub struct ChannelNames {
    rule: Rule,
}

enum Rule {
    Canonical { prefix: String, wide: bool },
    Custom(Box<NameRule>),
}

/// A driver's own naming rule: (channel, item) to full name.
type NameRule = dyn Fn(usize, &str) -> String + Send + Sync;

impl ChannelNames {
    /// Canonical names for `channels` channels of `io_type` on device
    /// `device` number `num`.
    pub fn canonical(device: &str, num: usize, io_type: &str, channels: usize) -> ChannelNames {
        ChannelNames {
            rule: Rule::Canonical {
                prefix: format!("{device}.{num}.{io_type}"),
                wide: channels > 10,
            },
        }
    }

    /// A driver's historic names: `rule(channel, name)` gives the full name.
    pub fn custom(rule: impl Fn(usize, &str) -> String + Send + Sync + 'static) -> ChannelNames {
        ChannelNames {
            rule: Rule::Custom(Box::new(rule)),
        }
    }

    /// The full name of item `name` of channel `chan`.
    pub fn item(&self, chan: usize, name: &str) -> String {
        match &self.rule {
            Rule::Canonical { prefix, wide: true } => format!("{prefix}.{chan:02}.{name}"),
            Rule::Canonical {
                prefix,
                wide: false,
            } => format!("{prefix}.{chan}.{name}"),
            Rule::Custom(f) => f(chan, name),
        }
    }
}

/// The name of a read or write function: `<device>.<num>.read`, or with
/// an io-type `<device>.<num>.<io-type>.read`, or with a channel range
/// `<device>.<num>.<io-type>-<first>-<last>.read`.
pub fn funct(
    device: &str,
    num: usize,
    io_type: Option<&str>,
    range: Option<(usize, usize)>,
    verb: &str,
) -> String {
    match (io_type, range) {
        (None, _) => format!("{device}.{num}.{verb}"),
        (Some(t), None) => format!("{device}.{num}.{t}.{verb}"),
        (Some(t), Some((a, b))) => format!("{device}.{num}.{t}-{a:02}-{b:02}.{verb}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn canonical_names_pad_channels_when_more_than_ten() {
        assert_eq!(
            ChannelNames::canonical("motenc", 0, "encoder", 8).item(2, "position"),
            "motenc.0.encoder.2.position"
        );
        assert_eq!(
            ChannelNames::canonical("stg", 0, "din", 32).item(3, "in"),
            "stg.0.din.03.in"
        );
        assert_eq!(
            ChannelNames::canonical("stg", 1, "din", 32).item(17, "in-not"),
            "stg.1.din.17.in-not"
        );
        let pp = ChannelNames::custom(|c, n| format!("parport.0.pin-{c:02}-{n}"));
        assert_eq!(pp.item(1, "out"), "parport.0.pin-01-out");
    }

    #[test]
    fn function_names() {
        assert_eq!(funct("motenc", 0, None, None, "read"), "motenc.0.read");
        assert_eq!(funct("stg", 0, Some("din"), None, "read"), "stg.0.din.read");
        assert_eq!(
            funct("generic8255", 0, Some("din"), Some((9, 15)), "read"),
            "generic8255.0.din-09-15.read"
        );
    }
}
