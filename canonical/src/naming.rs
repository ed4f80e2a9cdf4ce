//! Names of canonical pins and params.
//!
//! `<device>.<num>.<io-type>.<chan>.<name>`, the io-type being the
//! interface's own ([`Interface::IO_TYPE`]) and the channel zero-padded to
//! two digits when a device can have more than ten channels of that type
//! (so names sort in channel order). A driver whose users' configs
//! already use other names (parport's `pin-NN-out`) supplies its own rule
//! instead.

/// A canonical interface: the io-type field of its names.
pub trait Interface {
    /// The io-type field (`digin`, `adcout`, `encoder`, ...).
    const IO_TYPE: &'static str;
}

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
    /// Canonical names for `channels` channels of interface `I` on device
    /// `device` number `num`.
    pub fn canonical<I: Interface>(device: &str, num: usize, channels: usize) -> ChannelNames {
        ChannelNames {
            rule: Rule::Canonical {
                prefix: format!("{device}.{num}.{}", I::IO_TYPE),
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{DigIn, Encoder};

    #[test]
    fn canonical_names_pad_channels_when_more_than_ten() {
        assert_eq!(
            ChannelNames::canonical::<Encoder>("motenc", 0, 8).item(2, "position"),
            "motenc.0.encoder.2.position"
        );
        assert_eq!(
            ChannelNames::canonical::<DigIn>("stg", 0, 32).item(3, "in"),
            "stg.0.digin.03.in"
        );
        assert_eq!(
            ChannelNames::canonical::<DigIn>("stg", 1, 32).item(17, "in-not"),
            "stg.1.digin.17.in-not"
        );
        let pp = ChannelNames::custom(|c, n| format!("parport.0.pin-{c:02}-{n}"));
        assert_eq!(pp.item(1, "out"), "parport.0.pin-01-out");
    }
}
