//! I2C chip drivers: NXP PCA9685 (16 PWM outputs), Microchip MCP23017
//! (16 digital inputs/outputs) and TI ADS1115 (4 analog inputs), through
//! Linux's i2c-dev (the `i2cdev` crate), with register models of each
//! chip for configurations and tests without hardware.
//!
//! ```text
//! loadrt pca9685 bus=1 address=0x40 freq=1000
//! loadrt mcp23017 bus=1 address=0x20,0x21 dir=0xff00,0x7f7f pullup=0x7f00,0x7f7f
//! loadrt ads1115 bus=1 address=0x48 range=4096 rate=860
//! addf mcp23017.0.read servo-thread
//! addf ads1115.0.read servo-thread
//! ...
//! addf pca9685.0.write servo-thread
//! addf mcp23017.0.write servo-thread
//! ```
//!
//! Module parameters, pins and functions: [`hal`] (common to all three),
//! [`hal::pca9685`], [`hal::mcp23017`], [`hal::ads1115`]. The pins are the
//! canonical pwm, digin, digout and adcin interfaces.
//!
//! # No I2C transfer in a realtime thread
//!
//! An I2C transfer takes hundreds of microseconds at 100 kHz and may
//! sleep in the kernel, so the realtime functions never make one. Each
//! bus has one non-realtime helper thread ([`worker`]) that, every
//! millisecond, services every chip on the bus: it takes the newest
//! command the chip's `write` function published, writes what changed,
//! reads the inputs, and publishes them for the chip's `read` function.
//! The two sides meet in lock-free hand-offs ([`handoff`]: a triple
//! buffer each way): `read` and `write` cost a few atomic operations and
//! some pin accesses (the benchmark, `cargo bench -p hal-i2c`, prints
//! the figures), never wait, and always see a whole value.
//!
//! ## Latency
//!
//! From a `write` to the chip's pins: until the helper's next cycle
//! starts (at most its 1 ms cycle, 0.5 ms on average), plus the
//! transfer. From a chip's pin to a HAL pin: until the helper's next
//! read (at most 1 ms plus the transfers before it), plus until the next
//! `read` (at most one period of its thread). An I2C byte is 9 bit
//! times (90 µs at 100 kHz, 22.5 µs at 400 kHz); the transfers:
//!
//! | chip | transfer each cycle | bytes on the wire | 100 kHz | 400 kHz |
//! |---|---|---|---|---|
//! | PCA9685 | one channel changed (block write, 4 data bytes) | 6 | 0.55 ms | 0.14 ms |
//! | PCA9685 | 8 channels changed (one block write) | 34 | 3.1 ms | 0.77 ms |
//! | MCP23017 | outputs changed (OLAT word write) | 4 | 0.37 ms | 0.09 ms |
//! | MCP23017 | inputs (GPIO word read, every cycle) | 5 | 0.46 ms | 0.12 ms |
//! | ADS1115 | one conversion: poll CONFIG, read CONVERSION, start the next (word transfers) | 14 | 1.3 ms | 0.32 ms |
//!
//! So at 100 kHz an output changes at the MCP23017's pin 0.4 to 1.4 ms
//! after `write`, a PCA9685 channel 0.6 to 1.6 ms after, and an input
//! edge reaches its HAL pin 0.5 to 1.5 ms plus one thread period after
//! it happened. An ADS1115 conversion is collected at the first helper
//! cycle at least 1 / rate after it started, and the next one starts in
//! the same cycle: at 860 samples/s every second cycle, so each of four
//! channels is new every 8 ms (at 128 samples/s, 8 ms per conversion and
//! 32 ms for four). Chips sharing a bus share its time: a cycle whose
//! transfers take longer than 1 ms is followed by the next at once.
//!
//! # Faults
//!
//! A transfer that fails (no answer, a bus error) or a chip found reset
//! never blocks or ends the helper thread: the chip's `fault` pin rises
//! and stays up, its `errors` pin counts, its inputs keep their last good
//! values, its outputs are held in their safe state (PWM off, outputs at
//! their `invert` level), the realtime log says why once, and the chip is
//! set up again every 100 ms until it answers. A rising edge on its
//! `fault-reset` pin then releases the outputs ([`worker`]). The
//! safe-state hook (a fault in any realtime function, unload, exit) puts
//! every output in its safe state and waits until the helper has written
//! it.
//!
//! # Backends
//!
//! `backend=dev` (default): `/dev/i2c-<bus>` (module `i2c-dev`; the udev
//! rule `SUBSYSTEM=="i2c-dev", KERNEL=="i2c-[0-9]*", GROUP="hal"` in
//! `udev/60-hal-suite.rules` gives the group `hal` access). Only SMBus
//! transfers are used (byte data, word data, I2C block data), which every
//! adapter and the kernel's i2c-stub support. An address a kernel driver
//! owns is refused at load (the error says so).
//!
//! `backend=sim`: a simulated bus per bus number with a register model
//! ([`sim`]) at each loaded chip's address; its time follows the helper
//! thread's clock. Tests and tools find a bus with [`hal::sim_bus`].
//!
//! # Crate layout
//!
//! * [`regs`]: the register maps.
//! * [`bus`]: the [`bus::I2cBus`] trait; [`linux`] and [`sim`] implement it.
//! * [`chips`]: what the helper thread does with each chip.
//! * [`handoff`], [`worker`]: the hand-offs and the helper thread.
//! * [`hal`]: the `loadrt` modules.
//! * `fuzzing` (feature `fuzzing`): the fuzz body (random replies from the bus).
//! * `error`: the error type, [`I2cError`].

#![forbid(unsafe_code)]

pub mod bus;
pub mod chips;
mod error;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
pub mod hal;
pub mod handoff;
pub mod linux;
pub mod regs;
pub mod sim;
pub mod worker;

pub use error::I2cError;

/// The modules this crate provides, for the host's registry.
pub fn modules() -> [&'static hal_core::ModuleDef; 3] {
    [
        &hal::pca9685::MODULE,
        &hal::mcp23017::MODULE,
        &hal::ads1115::MODULE,
    ]
}
