//! The realtime cost of `hal_gpio.read` and `hal_gpio.write` for 32 lines,
//! beside the cost of one GPIO value ioctl on the same chip.
//!
//! `cargo bench -p hal-gpio` measures on the simulated chip, and on a
//! real chip when one is there: `$VMRIG_GPIOCHIP` (the VM rig's gpio-sim
//! chip) or `$HAL_GPIO_BENCH_CHIP`, with at least 32 free lines. On the
//! build machine, which has no GPIO chip, run the bench binary through
//! the rig:
//!
//! ```text
//! cargo bench -p hal-gpio --no-run
//! ../shared/tools/vmrig/vmrig run -- target/release/deps/gpio_bench-<hash>
//! ```
//!
//! The target: a 32-line read or write costs at most twice one ioctl.
//! Both are one ioctl per request; the rest is moving 32 bits to or
//! from pins.

use std::hint::black_box;
use std::path::Path;
use std::sync::Arc;

use canonical::{ChannelNames, DigIn};
use hal_core::{Host, HostConfig, In, Pin};
use hal_driver::bench::per_call;
use hal_driver::sim::MonotonicClock;
use hal_gpio::cdev::CdevChips;
use hal_gpio::cfg::{Bias, Direction, Drive};
use hal_gpio::chip::{ChipInfo, ChipSet, LineSetting};
use hal_gpio::driver::{InputBank, OutputBank};
use hal_gpio::hal::{gather_outputs, publish_inputs};
use hal_gpio::sim::SimChips;

const LINES: usize = 32;
const N: u64 = 200_000;
/// Rounds each figure is measured in.
const ROUNDS: u64 = 4;

fn settings(direction: Direction) -> Vec<LineSetting> {
    (0..LINES as u32)
        .map(|offset| LineSetting {
            offset,
            direction,
            active_low: false,
            drive: Drive::PushPull,
            bias: Bias::AsIs,
        })
        .collect()
}

/// 32 `-in`/`-in-not` pairs and 32 `-out` pins on a component of `host`.
fn pins(host: &Host) -> (Vec<DigIn>, Vec<Pin<bool, In>>) {
    let b = host.new_rt_component("bench").expect("component");
    let c = b.component();
    let names = ChannelNames::custom(|l, item| format!("bench.L{l}-{item}"));
    let ins = (0..LINES)
        .map(|l| DigIn::export(c, &names, l).expect("pin"))
        .collect();
    let outs = (0..LINES)
        .map(|l| c.pin(&names.item(l, "out")).expect("pin"))
        .collect();
    b.ready().expect("ready");
    (ins, outs)
}

/// Times the raw ioctls and the driver's read and write on `chips`, in
/// [`ROUNDS`] rounds, ioctl and driver alternating on the same request;
/// the ratios use each one's best round (the least disturbed by other
/// load on the machine).
fn measure(
    label: &str,
    chips: &dyn ChipSet,
    chip: &ChipInfo,
    ins: &[DigIn],
    outs: &[Pin<bool, In>],
) {
    println!("{label}");
    let clock = MonotonicClock;
    let all = hal_gpio::regs::low_bits(LINES);
    let n = N / ROUNDS;
    let inputs = chips
        .request(chip, &settings(Direction::Input))
        .expect("request");
    let bank = InputBank::new(inputs, LINES);
    let (mut get, mut read) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..ROUNDS {
        get = get.min(per_call("one GET_VALUES ioctl, 32 lines", n, |_| {
            black_box(bank.request().get(black_box(all)).ok());
        }));
        read = read.min(per_call("hal_gpio.read body, 32 inputs", n, |_| {
            if let Ok(bits) = bank.read() {
                publish_inputs(bits, ins);
            }
        }));
    }
    drop(bank);
    let outputs = chips
        .request(chip, &settings(Direction::Output))
        .expect("request");
    let bank = OutputBank::new(outputs, LINES, 0);
    let (mut set, mut write) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..ROUNDS {
        // Both flip every line on every call, so the kernel does the
        // same work for each.
        set = set.min(per_call(
            "one SET_VALUES ioctl, 32 lines, all change",
            n,
            |i| {
                let bits = if i & 1 == 0 { all } else { 0 };
                black_box(bank.request().set(black_box(bits), all).ok());
            },
        ));
        write = write.min(per_call(
            "hal_gpio.write body, 32 outputs, all change",
            n,
            |i| {
                // The pins read FALSE; flipping every bit on alternate calls
                // makes every call write, as a step pattern would.
                let flip = if i & 1 == 0 { all } else { 0 };
                black_box(bank.write(gather_outputs(outs) ^ flip, &clock).ok());
            },
        ));
    }
    per_call("  of which: publish 32 inputs on their pins", n, |i| {
        publish_inputs(black_box(i), ins);
    });
    per_call("  of which: gather 32 output pins", n, |_| {
        black_box(gather_outputs(outs));
    });
    println!(
        "  best rounds: read {read:.0} ns / ioctl {get:.0} ns = {:.2}, write {write:.0} ns / ioctl {set:.0} ns = {:.2} (target: at most 2)",
        read / get,
        write / set
    );
}

fn main() {
    let host = Host::create(HostConfig::for_tests("gpio-bench")).expect("host");
    let (ins, outs) = pins(&host);
    let names: Vec<String> = (0..LINES).map(|l| format!("L{l}")).collect();
    let refs: Vec<&str> = names.iter().map(String::as_str).collect();
    let sim = SimChips::new(vec![Arc::new(hal_gpio::sim::SimChip::new(
        "gpiochip0",
        "bench",
        &refs,
        Arc::new(MonotonicClock),
    ))]);
    let info = sim.chips()[0].info().clone();
    measure("hal_gpio on the simulated chip", &sim, &info, &ins, &outs);

    let real = std::env::var("HAL_GPIO_BENCH_CHIP")
        .or_else(|_| std::env::var("VMRIG_GPIOCHIP"))
        .ok();
    match real {
        Some(path) if Path::new(&path).exists() => match CdevChips::info(Path::new(&path)) {
            Ok(info) if info.line_names.len() >= LINES => {
                measure(
                    &format!("hal_gpio on {info} ({path}, character device)"),
                    &CdevChips,
                    &info,
                    &ins,
                    &outs,
                );
            }
            Ok(info) => println!("{path}: {info} has fewer than {LINES} lines; not measured"),
            Err(e) => println!("{path}: {e}; not measured"),
        },
        _ => println!(
            "no GPIO chip (set HAL_GPIO_BENCH_CHIP, or run this binary through the VM rig): \
             the character device's ioctl was not measured"
        ),
    }
}
