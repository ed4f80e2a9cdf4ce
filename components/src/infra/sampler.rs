//! `sampler`: copies pin values into a FIFO every time its function runs;
//! `halsampler` prints them. One FIFO record is the sample number followed
//! by one word per column.

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, In, Io, Out, Pin, RawPin, Result, RingWriter};

use super::columns::{channels, fifo_name, pin_name, PARAMS};

/// The `sampler` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "sampler",
    params: PARAMS,
    help: "samples HAL pins into a realtime-to-user-space FIFO",
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let chans = channels("sampler", args.str_array("cfg"), args.int_array("depth"))?;
    let mut b = host.new_rt_component("sampler")?;
    for (n, (types, depth)) in chans.into_iter().enumerate() {
        let c = b.component();
        let pins: Vec<RawPin<In>> = types
            .iter()
            .enumerate()
            .map(|(m, t)| c.pin_raw(&pin_name("sampler", n, m), *t))
            .collect::<Result<_>>()?;
        let enable: Pin<bool, In> = c.pin_init(&format!("sampler.{n}.enable"), true)?;
        let full: Pin<bool, Out> = c.pin(&format!("sampler.{n}.full"))?;
        let curr_depth: Pin<i32, Out> = c.pin(&format!("sampler.{n}.curr-depth"))?;
        let overruns: Pin<i32, Io> = c.pin(&format!("sampler.{n}.overruns"))?;
        let _sample_num: Pin<i32, Io> = c.pin(&format!("sampler.{n}.sample-num"))?;
        let mut fifo = RingWriter::create_typed(c, &fifo_name("sampler", n), depth, &types)?;
        let mut row = vec![0u64; types.len() + 1];
        let mut sample: u32 = 0;
        b.funct(&format!("sampler.{n}"), false, move |_| {
            if !enable.get() {
                curr_depth.set(fifo.len() as i32);
                full.set(fifo.len() >= fifo.capacity());
                return;
            }
            for (slot, pin) in row[1..].iter_mut().zip(&pins) {
                *slot = pin.get_bits();
            }
            // The sample number counts records written, not attempts.
            row[0] = sample.wrapping_add(1) as u64;
            if fifo.push(&row) {
                sample = sample.wrapping_add(1);
                full.set(false);
                curr_depth.set(fifo.len() as i32);
            } else {
                overruns.set(overruns.get().wrapping_add(1));
                full.set(true);
                curr_depth.set(depth as i32);
            }
        })?;
    }
    b.ready()
}
