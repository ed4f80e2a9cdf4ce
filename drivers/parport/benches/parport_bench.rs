//! Prints ns per parport read and write on the simulated backend.
//!
//! `cargo bench -p hal-parport` runs the driver algorithm directly
//! (read in each mode; write with nothing changed, which touches no
//! register; write that changes the data byte every call) and then the
//! HAL functions `parport.0.read`/`.write` in a thread, reporting the
//! executor's own per-function timing.

use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

use hal_core::{Host, HostConfig, Value};
use hal_driver::bench::run_cases;
use hal_parport::cfg::Mode;
use hal_parport::clock::MonotonicClock;
use hal_parport::driver::{Outputs, PortDriver};
use hal_parport::sim::{SimConfig, SimPort};

const N: u64 = 2_000_000;

fn per_call(what: &str, f: impl FnMut(u64)) {
    hal_driver::bench::per_call(what, N, f);
}

fn driver(mode: Mode) -> PortDriver {
    let clock = Arc::new(MonotonicClock);
    let sim = Arc::new(SimPort::new(
        SimConfig::new(0x378).with_loopback(),
        clock.clone(),
    ));
    let d = PortDriver::new(mode, sim, clock);
    d.init().expect("sim init");
    d
}

fn main() -> std::process::ExitCode {
    println!("hal_parport on the simulator ({N} calls each)");
    let out = driver(Mode::Out);
    per_call("read, out mode (status)", |_| {
        black_box(out.read());
    });
    let inp = driver(Mode::In);
    per_call("read, in mode (status + data)", |_| {
        black_box(inp.read());
    });
    let x = driver(Mode::X);
    per_call("read, x mode (status + control)", |_| {
        black_box(x.read());
    });
    let o = Outputs::default();
    out.write(&o);
    per_call("write, unchanged (no register access)", |_| {
        out.write(black_box(&o));
    });
    per_call("write, data changes every call", |i| {
        out.write(black_box(&Outputs { data: i as u8, ..o }));
    });
    per_call("write + reset (reset-time 0, one reset pin)", |i| {
        out.write(black_box(&Outputs {
            data: (i & 1) as u8,
            data_reset_mask: 1,
            ..o
        }));
        out.reset(0, 1_000_000);
    });
    run_cases([("HAL function timing".to_string(), ())], |_, ()| {
        hal_functions()
    })
}

/// Runs `parport.0.read` and `.write` in a 100 us thread and prints the
/// executor's measurement of each.
fn hal_functions() -> hal_core::Result<()> {
    let name = format!("ppbench-{}", std::process::id());
    let host = Host::create(HostConfig::new(&name))?;
    host.loadrt(&hal_parport::MODULE, &["cfg=0 simloop".to_string()])?;
    host.create_thread("t", 100_000, false, None)?;
    host.addf("parport.0.read", "t", -1)?;
    host.addf("parport.0.write", "t", -1)?;
    host.start()?;
    std::thread::sleep(Duration::from_millis(500));
    host.stop();
    println!(
        "HAL functions in a 100 us thread (realtime: {}):",
        host.is_realtime()
    );
    for f in ["read", "write"] {
        let last = host.instance().pin_value(&format!("parport.0.{f}.time"))?;
        let max = host
            .instance()
            .param_value(&format!("parport.0.{f}.tmax"))?;
        let show = |v: Value| match v {
            Value::S32(n) => n.to_string(),
            v => format!("{v:?}"),
        };
        println!(
            "  parport.0.{f:<40} last {:>6} ns, max {:>6} ns",
            show(last),
            show(max)
        );
    }
    Ok(())
}
