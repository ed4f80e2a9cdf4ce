//! `output_buffer`: passes `personality` bits through while `enable` is
//! TRUE; otherwise every output shows `off-level`.

use hal_core::{In, Out, Pin, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Most channels.
pub const MAX_CHANNELS: usize = 32;

/// The `output_buffer` component.
pub struct OutputBuffer;
impl HalComp for OutputBuffer {
    const NAME: &'static str = "output_buffer";
    const PERSONALITY: bool = true;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let n = inst.array_len(MAX_CHANNELS, inst.personality)?;
        let enable = inst.pin_in::<bool>("enable")?;
        let off_level = inst.pin_in::<bool>("off-level")?;
        let ins: Vec<Pin<bool, In>> = (0..n)
            .map(|i| inst.pin_in(&format!("in-{i}")))
            .collect::<Result<_>>()?;
        let outs: Vec<Pin<bool, Out>> = (0..n)
            .map(|i| inst.pin_out(&format!("out-{i}")))
            .collect::<Result<_>>()?;
        inst.funct("_", true, move |_| {
            if enable.get() {
                for (o, i) in outs.iter().zip(&ins) {
                    o.set(i.get());
                }
            } else {
                let level = off_level.get();
                for o in &outs {
                    o.set(level);
                }
            }
        })
    }
}
halcomp_module!(pub MODULE, OutputBuffer, "feed through multiple bits when enable pin is set");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::Bit;

    #[test]
    fn passes_only_while_enabled() {
        let mut h = TestHost::new("outbuf");
        h.load(&MODULE, &["personality=2"]).unwrap();
        h.check_pins(
            "output-buffer.0",
            &[
                "enable bit in 0",
                "off-level bit in 0",
                "in-0 bit in 0",
                "in-1 bit in 0",
                "out-0 bit out 0",
                "out-1 bit out 0",
            ],
        );
        h.check_load_fails(&MODULE, &["names=x", "personality=33"]);
        h.thread(&["output-buffer.0"]);
        h.set("output-buffer.0.in-1", Bit(true));
        h.expect(&[], "output-buffer.0.out-1", Bit(false));
        h.expect(
            &[("output-buffer.0.enable", Bit(true))],
            "output-buffer.0.out-1",
            Bit(true),
        );
        assert_eq!(h.get("output-buffer.0.out-0"), Bit(false));
        h.set("output-buffer.0.enable", Bit(false));
        h.expect(
            &[("output-buffer.0.off-level", Bit(true))],
            "output-buffer.0.out-0",
            Bit(true),
        );
    }
}
