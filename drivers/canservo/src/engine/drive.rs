//! One drive's realtime side on CAN: what its TPDOs, EMCYs and heartbeats
//! say, the CAN supervision (TPDOs after SYNC, heartbeat age, NMT state)
//! that turns silence into a tripped latch, and its RPDO. The drive's
//! control itself (fault latch, power-state planner, fault reset, homing,
//! command tracking) is the shared CiA 402 layer's
//! [`DriveControl`](hal_cia402::DriveControl).

use std::sync::Arc;

use hal_cia402::{DriveControl, LinkSupervision, Restarting};
use hal_driver::fault::Fault;
use hal_driver::LogSink;

use super::faults;
use super::shared::DriveShared;
use super::{DriveInputs, DriveStatus};
use crate::frame::Frame;
use crate::power::PowerState;
use crate::regs::{cob, nmt};
use crate::startup::Mode;

/// What CAN supervision knows of a drive.
#[derive(Debug)]
pub(super) struct CanLink {
    nmt_state: u8,
    seen_tpdo1: bool,
    seen_tpdo2: bool,
    misses: u32,
    last_heartbeat_ns: Option<u64>,
}

impl LinkSupervision for CanLink {
    fn fresh(&mut self) {
        self.misses = 0;
        self.last_heartbeat_ns = None;
        self.nmt_state = nmt::STATE_OPERATIONAL;
        self.seen_tpdo1 = false;
        self.seen_tpdo2 = false;
    }
}

/// One drive.
#[derive(Debug)]
pub(super) struct DriveRt {
    pub node: u8,
    pub mode: Mode,
    ctl: DriveControl<CanLink>,
    pub bad_frames: u32,
    /// TPDO1s taken so far (wrapping): tells a fresh statusword.
    tpdo1_count: u32,
}

impl DriveRt {
    pub fn new(index: usize, node: u8, mode: Mode, shared: Arc<DriveShared>) -> DriveRt {
        let link = CanLink {
            nmt_state: nmt::STATE_OPERATIONAL,
            seen_tpdo1: false,
            seen_tpdo2: false,
            misses: 0,
            last_heartbeat_ns: None,
        };
        let label = format!("canservo.{index} (node {node})");
        DriveRt {
            node,
            mode,
            ctl: DriveControl::new(label, mode, shared, link, faults::needs_restart),
            bad_frames: 0,
            tpdo1_count: 0,
        }
    }

    /// The power state the last statusword showed.
    pub fn state_now(&self) -> Option<PowerState> {
        self.ctl.state_now()
    }

    /// TPDO1s (statuswords) taken so far, wrapping.
    pub fn tpdo1_count(&self) -> u32 {
        self.tpdo1_count
    }

    /// "canservo.0 (node 2)".
    pub fn label(&self) -> &str {
        self.ctl.label()
    }

    /// Trips the latch with `fault` and says so once, with the node and,
    /// for drive errors, the error code and its meaning.
    pub fn trip(&mut self, fault: &'static Fault, log: Option<&LogSink>, code: u16) {
        self.ctl.trip(fault, log, code);
    }

    /// Forgets what the TPDOs said before this cycle's reception.
    pub fn begin_cycle(&mut self) {
        self.ctl.link.seen_tpdo1 = false;
        self.ctl.link.seen_tpdo2 = false;
    }

    fn bad_frame(&mut self) {
        self.bad_frames = self.bad_frames.wrapping_add(1);
    }

    /// A frame for this node; returns false if it is not one of its
    /// COB-IDs.
    pub fn take(&mut self, base: u16, f: &Frame, now_ns: u64, log: Option<&LogSink>) -> bool {
        let d = &f.data;
        match base {
            b if b == cob::TPDO[0] => {
                if f.len == 7 {
                    let statusword = u16::from_le_bytes([d[0], d[1]]);
                    let position = i32::from_le_bytes([d[2], d[3], d[4], d[5]]);
                    self.ctl.observe_status(statusword, position, d[6] as i8);
                    self.ctl.link.seen_tpdo1 = true;
                    self.tpdo1_count = self.tpdo1_count.wrapping_add(1);
                } else {
                    self.bad_frame();
                }
            }
            b if b == cob::TPDO[1] => {
                if f.len == 6 {
                    let velocity = i32::from_le_bytes([d[0], d[1], d[2], d[3]]);
                    self.ctl
                        .observe_velocity(velocity, u16::from_le_bytes([d[4], d[5]]));
                    self.ctl.link.seen_tpdo2 = true;
                } else {
                    self.bad_frame();
                }
            }
            cob::EMCY => {
                if f.len >= 2 {
                    self.ctl.emcy(u16::from_le_bytes([d[0], d[1]]), log);
                } else {
                    self.bad_frame();
                }
            }
            cob::HEARTBEAT => {
                if f.len >= 1 {
                    self.ctl.link.nmt_state = d[0];
                    self.ctl.link.last_heartbeat_ns = Some(now_ns);
                } else {
                    self.bad_frame();
                }
            }
            _ => return false,
        }
        true
    }

    /// Supervision after this cycle's frames are in: TPDOs after the last
    /// SYNC, heartbeat age and state, the drive's own Fault.
    pub fn supervise(
        &mut self,
        now_ns: u64,
        expect_tpdo: bool,
        miss_limit: u32,
        hb_timeout_ns: u64,
        log: Option<&LogSink>,
    ) {
        if self.ctl.poll_restart(log) != Restarting::No {
            return;
        }
        self.ctl.after_restart(self.ctl.link.seen_tpdo1);
        if expect_tpdo {
            let link = &mut self.ctl.link;
            if link.seen_tpdo1 && link.seen_tpdo2 {
                link.misses = 0;
            } else {
                link.misses += 1;
                if link.misses >= miss_limit.max(1) {
                    self.ctl.trip(&faults::TPDO_MISSING, log, 0);
                }
            }
        }
        if hb_timeout_ns > 0 {
            match self.ctl.link.last_heartbeat_ns {
                None => self.ctl.link.last_heartbeat_ns = Some(now_ns),
                Some(t) if now_ns.saturating_sub(t) > hb_timeout_ns => {
                    self.ctl.trip(&faults::HEARTBEAT, log, 0)
                }
                Some(_) => {}
            }
        }
        if self.ctl.link.nmt_state != nmt::STATE_OPERATIONAL {
            self.ctl.trip(&faults::NMT_STATE, log, 0);
        }
        self.ctl.supervise_drive(log);
    }

    /// This cycle's outputs: the feedback after reception.
    pub fn status(&mut self, inp: &DriveInputs) -> DriveStatus {
        let fb = self.ctl.feedback(inp);
        DriveStatus {
            position_fb: fb.position_fb,
            velocity_fb: fb.velocity_fb,
            statusword: fb.statusword,
            state: fb.state,
            mode_display: fb.mode_display,
            error_code: fb.error_code,
            amp_fault: fb.amp_fault,
            fault_code: fb.fault_code,
            enabled: fb.enabled,
            home_clear: fb.home_clear,
            homing: fb.homing,
            home_complete: fb.home_complete,
            nmt_state: self.ctl.link.nmt_state,
            error_register: self
                .ctl
                .shared
                .error_register
                .load(std::sync::atomic::Ordering::Relaxed),
            bad_frames: self.bad_frames,
        }
    }

    /// Plans this cycle's controlword, mode and target, and makes the
    /// RPDO. None while the node is being brought up again.
    pub fn rpdo(
        &mut self,
        inp: &DriveInputs,
        now_ns: u64,
        quick_stop_ns: u64,
        helper: bool,
    ) -> Option<Frame> {
        let plan = self.ctl.plan(inp, now_ns, quick_stop_ns, helper)?;
        let t = plan.target.to_le_bytes();
        let c = plan.controlword.to_le_bytes();
        Some(Frame::new(
            cob::RPDO[0] + u16::from(self.node),
            &[c[0], c[1], t[0], t[1], t[2], t[3], plan.mode as u8],
        ))
    }

    /// The last controlword sent.
    pub fn controlword(&self) -> u16 {
        self.ctl.controlword()
    }

    /// The last target sent.
    pub fn target(&self) -> i32 {
        self.ctl.target()
    }
}
