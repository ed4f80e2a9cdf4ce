//! A CiA 402 drive over CoE (`type="basic_cia402"`): its objects in the
//! process data, and the shared CiA 402 layer ([`hal_cia402`], as
//! canservo uses it) behind lcec's `srv-*` pins. The mode comes from
//! `<modParam name="mode" value="csp|csv|pv|pp"/>` (default csp);
//! `srv-pos-scale` is counts per user unit. EtherCAT's own supervision:
//! a slave that leaves OP or drops out of the working counter trips the
//! drive's latch; `srv-fault-reset` clears it and asks the master to
//! bring the slaves back to OP.

use std::sync::Arc;

use hal_cia402::objects::obj;
use hal_cia402::{DriveControl, DriveInputs, DriveShared, LinkSupervision, Mode};
use hal_core::HalHost;
use hal_driver::fault::Fault;
use hal_driver::LogSink;

use super::field::Field;
use super::slave::Named;
use crate::error::Error;
use crate::lcec::conf::Slave;
use crate::master::Layout;

/// The slave left OP or its data missed the working counter.
pub static SLAVE_LOST: Fault = Fault::new(20, "slave not in OP or working counter short");

/// EtherCAT's faults are all communication faults: a fault reset
/// supervises afresh (the master brings the slave back to OP).
fn needs_restart(f: &Fault) -> bool {
    std::ptr::eq(f, &SLAVE_LOST)
}

/// EtherCAT supervision has nothing to forget.
#[derive(Debug)]
struct EcatLink;

impl LinkSupervision for EcatLink {
    fn fresh(&mut self) {}
}

/// The drive's objects in the process data.
#[derive(Debug, Clone, Copy)]
struct Objects {
    statusword: Field,
    position: Field,
    velocity: Option<Field>,
    mode_display: Option<Field>,
    error_code: Option<Field>,
    controlword: Field,
    target_position: Option<Field>,
    target_velocity: Option<Field>,
    mode: Option<Field>,
}

/// The drive's `srv-*` pins, as indices into the slave's pins (found by
/// name once, at export).
struct DrivePins {
    pos_scale: Option<usize>,
    enable: Option<usize>,
    fault_reset: Option<usize>,
    target_position: Option<usize>,
    target_velocity: Option<usize>,
    home: Option<usize>,
    actual_position: Option<usize>,
    actual_velocity: Option<usize>,
    enabled: Option<usize>,
    fault: Option<usize>,
    fault_code: Option<usize>,
    error_code: Option<usize>,
    statusword: Option<usize>,
    opmode_display: Option<usize>,
    home_complete: Option<usize>,
    controlword: Option<usize>,
}

impl DrivePins {
    fn new<H: HalHost>(p: &Named<'_, H>) -> DrivePins {
        DrivePins {
            pos_scale: p.index("srv-pos-scale"),
            enable: p.index("srv-enable"),
            fault_reset: p.index("srv-fault-reset"),
            target_position: p.index("srv-target-position"),
            target_velocity: p.index("srv-target-velocity"),
            home: p.index("srv-home"),
            actual_position: p.index("srv-actual-position"),
            actual_velocity: p.index("srv-actual-velocity"),
            enabled: p.index("srv-enabled"),
            fault: p.index("srv-fault"),
            fault_code: p.index("srv-fault-code"),
            error_code: p.index("srv-error-code"),
            statusword: p.index("srv-cia-statusword"),
            opmode_display: p.index("srv-opmode-display"),
            home_complete: p.index("srv-home-complete"),
            controlword: p.index("srv-cia-controlword"),
        }
    }
}

/// One drive.
pub(crate) struct DriveRt {
    ctl: DriveControl<EcatLink>,
    at: Objects,
    pins: DrivePins,
    inputs: DriveInputs,
    reset_edge: bool,
    reset_prev: bool,
    /// The position actual and mode display last received.
    last_position: i32,
    last_mode: i8,
    /// The drive stopped exchanging data since its latch last tripped.
    link_lost: bool,
}

/// How long a tripped drive gets quick stop before disable voltage
/// (a drive fault or EMCY while the drive still hears the master).
const QUICK_STOP_NS: u64 = 1_000_000_000;

impl DriveRt {
    /// The drive of `slave`, its objects found in `layout`, its pins in
    /// `pins`.
    pub(crate) fn new<H: HalHost>(
        label: String,
        slave: &Slave,
        layout: &Layout,
        file: &std::path::Path,
        pins: &Named<'_, H>,
    ) -> hal_core::Result<DriveRt> {
        let missing = |what: &str| {
            hal_core::HalError::module_failed(
                crate::lcec::pins::MODULE,
                Error::Config {
                    file: file.to_path_buf(),
                    line: slave.line,
                    element: "slave".into(),
                    reason: format!("drive '{}' does not map {what}", slave.name),
                },
            )
        };
        let find = |index: u16, output: bool| {
            layout.find(index, 0, output).map(|m| Field {
                bit: m.bit,
                bits: m.bits,
            })
        };
        let at = Objects {
            statusword: find(obj::STATUSWORD, false)
                .ok_or_else(|| missing("the statusword 0x6041 in its inputs"))?,
            position: find(obj::POSITION_ACTUAL, false)
                .ok_or_else(|| missing("the position actual 0x6064 in its inputs"))?,
            velocity: find(obj::VELOCITY_ACTUAL, false),
            mode_display: find(0x6061, false),
            error_code: find(obj::ERROR_CODE, false),
            controlword: find(obj::CONTROLWORD, true)
                .ok_or_else(|| missing("the controlword 0x6040 in its outputs"))?,
            target_position: find(obj::TARGET_POSITION, true),
            target_velocity: find(obj::TARGET_VELOCITY, true),
            mode: find(obj::MODES_OF_OPERATION, true),
        };
        let mode_name = slave
            .mod_params
            .iter()
            .find(|(k, _)| k == "mode")
            .map_or("csp", |(_, v)| v.as_str());
        let mode = Mode::parse(mode_name).ok_or_else(|| {
            hal_core::HalError::module_failed(
                crate::lcec::pins::MODULE,
                Error::Config {
                    file: file.to_path_buf(),
                    line: slave.line,
                    element: "modParam".into(),
                    reason: format!("mode '{mode_name}' is not one of csp, csv, pv, pp"),
                },
            )
        })?;
        Ok(DriveRt {
            ctl: DriveControl::new(
                label,
                mode,
                Arc::new(DriveShared::default()),
                EcatLink,
                needs_restart,
            ),
            at,
            pins: DrivePins::new(pins),
            inputs: DriveInputs::default(),
            reset_edge: false,
            reset_prev: false,
            last_position: 0,
            last_mode: 0,
            link_lost: false,
        })
    }

    /// Whether `srv-fault-reset` rose this cycle.
    pub(crate) fn wants_reset(&self) -> bool {
        self.reset_edge
    }

    /// What `read`'s feedback uses of the inputs (the scale, and the
    /// position command a homing drive echoes): the rest are taken by
    /// `write`, which acts on them.
    fn take_feedback_inputs<H: HalHost>(&mut self, p: &Named<'_, H>) {
        let get = |i: Option<usize>| p.at(i).map_or(0.0, |x| x.get());
        self.inputs.scale = usable_scale(get(self.pins.pos_scale));
        self.inputs.position_cmd = get(self.pins.target_position);
    }

    fn take_inputs<H: HalHost>(&mut self, p: &Named<'_, H>) {
        let get = |i: Option<usize>| p.at(i).map_or(0.0, |x| x.get());
        let at = &self.pins;
        let scale = get(at.pos_scale);
        self.inputs = DriveInputs {
            enable: get(at.enable) != 0.0,
            fault_reset: get(at.fault_reset) != 0.0,
            position_cmd: get(at.target_position),
            velocity_cmd: get(at.target_velocity),
            home: get(at.home) != 0.0,
            scale: usable_scale(scale),
            command_tolerance: 0.01,
        };
    }

    /// Reception and supervision; the `srv-*` outputs. `emcy`: the
    /// error code of an emergency the drive sent since the last cycle
    /// (read from its mailbox by the master's helper): it trips the
    /// drive as canservo's EMCY does, with its code in `srv-error-code`.
    pub(crate) fn read<H: HalHost>(
        &mut self,
        img: &[u8],
        healthy: bool,
        emcy: Option<u16>,
        p: &Named<'_, H>,
        log: Option<&LogSink>,
    ) {
        self.take_feedback_inputs(p);
        let rd = |f: Option<Field>| f.map_or(0, |f| f.read_signed(img));
        if healthy {
            self.last_position = self.at.position.read_signed(img) as i32;
            self.last_mode = rd(self.at.mode_display) as i8;
            self.ctl.observe_status(
                self.at.statusword.read(img) as u16,
                self.last_position,
                self.last_mode,
            );
            self.ctl
                .observe_velocity(rd(self.at.velocity) as i32, rd(self.at.error_code) as u16);
        } else {
            self.lost(log);
        }
        if let Some(code) = emcy {
            self.ctl.emcy(code, log);
        }
        self.ctl.poll_restart(log);
        self.ctl.after_restart(healthy);
        self.ctl.supervise_drive(log);
        let fb = self.ctl.feedback(&self.inputs);
        let set = |i: Option<usize>, v: f64| {
            if let Some(pin) = p.at(i) {
                pin.set(v);
            }
        };
        let at = &self.pins;
        set(at.actual_position, fb.position_fb);
        set(at.actual_velocity, fb.velocity_fb);
        set(at.enabled, f64::from(u8::from(fb.enabled)));
        set(at.fault, f64::from(u8::from(fb.amp_fault)));
        set(at.fault_code, f64::from(fb.fault_code));
        set(at.error_code, f64::from(fb.error_code));
        set(at.statusword, f64::from(fb.statusword));
        set(at.opmode_display, f64::from(fb.mode_display));
        set(at.home_complete, f64::from(u8::from(fb.home_complete)));
        if fb.home_clear {
            set(at.home, 0.0);
        }
    }

    /// The drive does not exchange data: the latch trips, and what the
    /// drive last said of its power state is forgotten (statusword 0):
    /// it is unknown until a status comes again, so the planner does not
    /// plan from a state of before the loss (a quick stop for a drive
    /// it still believes enabled) and one controlword, disable voltage,
    /// holds from the loss until the enable sequence starts again.
    fn lost(&mut self, log: Option<&LogSink>) {
        self.link_lost = true;
        self.ctl.trip(&SLAVE_LOST, log, 0);
        self.ctl
            .observe_status(0, self.last_position, self.last_mode);
    }

    /// Plans the controlword, target and mode into the outputs.
    pub(crate) fn write<H: HalHost>(&mut self, img: &mut [u8], now_ns: u64, p: &Named<'_, H>) {
        self.take_inputs(p);
        self.reset_edge = self.inputs.fault_reset && !self.reset_prev;
        self.reset_prev = self.inputs.fault_reset;
        self.plan_into(img, now_ns, p);
    }

    /// The outputs of a drive that does not exchange data (its slave
    /// left OP, the working counter is short, the link is down): the
    /// CiA 402 layer's plan with the latch tripped, so the controlword
    /// on the wire and `srv-cia-controlword` are the one the layer
    /// chose, and the first frame after the loss carries it. A fault
    /// reset given meanwhile is taken (its edge is not lost).
    pub(crate) fn write_lost<H: HalHost>(&mut self, img: &mut [u8], now_ns: u64, p: &Named<'_, H>) {
        self.lost(None);
        self.write(img, now_ns, p);
    }

    fn plan_into<H: HalHost>(&mut self, img: &mut [u8], now_ns: u64, p: &Named<'_, H>) {
        // A drive tripped by a lost slave could not hear a quick stop,
        // and when the link returns its state is whatever its own
        // watchdog made it: straight to disable voltage, so that no
        // quick stop reaches it late. Other faults (a drive fault, an
        // EMCY) get the quick stop first, as canservo's.
        // So does one that lost its link during a quick stop of another
        // fault: a quick stop that some frames reach and others not
        // would alternate with disable voltage.
        if !self.ctl.latch.is_tripped() {
            self.link_lost = false;
        }
        let comm_lost = self.link_lost || self.ctl.latch.fault().is_some_and(needs_restart);
        let quick_stop_ns = if comm_lost { 0 } else { QUICK_STOP_NS };
        let Some(plan) = self.ctl.plan(&self.inputs, now_ns, quick_stop_ns, false) else {
            return;
        };
        self.at.controlword.write(img, u64::from(plan.controlword));
        let target = if self.ctl.mode.is_position() {
            self.at.target_position
        } else {
            self.at.target_velocity
        };
        if let Some(f) = target {
            f.write(img, plan.target as i64 as u64);
        }
        if let Some(f) = self.at.mode {
            f.write(img, plan.mode as u8 as u64);
        }
        if let Some(pin) = p.at(self.pins.controlword) {
            pin.set(f64::from(plan.controlword));
        }
    }

    /// The safe state: controlword disable voltage.
    pub(crate) fn safe(&mut self, img: &mut [u8]) {
        self.at.controlword.write(img, 0);
    }
}

/// `position-scale` as used: 1 where it is zero, tiny or not finite.
fn usable_scale(scale: f64) -> f64 {
    if scale.is_finite() && scale.abs() > 1e-20 {
        scale
    } else {
        1.0
    }
}
