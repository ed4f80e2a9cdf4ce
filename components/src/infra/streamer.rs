//! `streamer`: the reverse of sampler. `halstreamer` fills a FIFO from text;
//! the function pops one record per call onto output pins.

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, In, Io, Out, Pin, RawPin, Result, RingReader};

use super::columns::{channels, fifo_name, pin_name, PARAMS};

/// The `streamer` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "streamer",
    params: PARAMS,
    help: "streams values from a user-space FIFO onto HAL pins",
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let chans = channels("streamer", args.str_array("cfg"), args.int_array("depth"))?;
    let mut b = host.new_rt_component("streamer")?;
    for (n, (types, depth)) in chans.into_iter().enumerate() {
        let c = b.component();
        let pins: Vec<RawPin<Out>> = types
            .iter()
            .enumerate()
            .map(|(m, t)| c.pin_raw(&pin_name("streamer", n, m), *t))
            .collect::<Result<_>>()?;
        let enable: Pin<bool, In> = c.pin_init(&format!("streamer.{n}.enable"), true)?;
        let empty: Pin<bool, Out> = c.pin_init(&format!("streamer.{n}.empty"), true)?;
        let curr_depth: Pin<i32, Out> = c.pin(&format!("streamer.{n}.curr-depth"))?;
        let underruns: Pin<i32, Io> = c.pin(&format!("streamer.{n}.underruns"))?;
        let clock: Pin<bool, In> = c.pin(&format!("streamer.{n}.clock"))?;
        let clock_mode: Pin<i32, In> = c.pin(&format!("streamer.{n}.clock-mode"))?;
        let mut fifo = RingReader::create_typed(c, &fifo_name("streamer", n), depth, &types)?;
        let mut row = vec![0u64; types.len() + 1];
        let mut edges: u8 = 0;
        b.funct(&format!("streamer.{n}"), false, move |_| {
            edges = ((edges << 1) | clock.get() as u8) & 3;
            let go = enable.get()
                && match clock_mode.get() {
                    1 => edges == 2,
                    2 => edges == 1,
                    3 => edges == 1 || edges == 2,
                    _ => true,
                };
            let n = fifo.len();
            curr_depth.set(n as i32);
            empty.set(n == 0);
            if !go {
                return;
            }
            if !fifo.pop(&mut row) {
                underruns.set(underruns.get().wrapping_add(1));
                return;
            }
            for (pin, bits) in pins.iter().zip(&row[1..]) {
                pin.set_bits(*bits);
            }
        })?;
    }
    b.ready()
}
