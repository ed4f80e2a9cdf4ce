//! configs/sim/spindle-vfd.hal, run as halrun runs it (a host serving the
//! instance, a halcmd session reading the file, `loadusr` starting the
//! real hy_vfd program): the simulated spindle comes up to speed.

use std::path::Path;
use std::time::{Duration, Instant};

use hal_core::{HostConfig, Instance, Value};

#[test]
fn the_spindle_vfd_config_runs_without_hardware() {
    let mut cfg = HostConfig::for_tests("vfd-config");
    cfg.shm_size = 8 << 20;
    let name = cfg.instance.clone();
    let (tx, rx) = std::sync::mpsc::channel();
    let host = std::thread::spawn(move || {
        hal_host::serve(cfg, move || {
            let _ = tx.send(());
        })
        .expect("the host serves");
    });
    rx.recv_timeout(Duration::from_secs(60))
        .expect("host ready");
    let inst = Instance::attach(&name).unwrap();

    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs/sim/spindle-vfd.hal");
    let text = std::fs::read_to_string(&path).unwrap();
    let (mut out, mut err) = (Vec::new(), Vec::new());
    {
        let mut session = hal_lang::Session::new(
            inst.clone(),
            hal_lang::Options::default(),
            &mut out,
            &mut err,
        );
        assert!(session.run_text(Some("spindle-vfd.hal"), &text));
        // The file waits a second; a loaded machine may need longer.
        let end = Instant::now() + Duration::from_secs(60);
        while inst.pin_value("spindle-vfd.spindle-at-speed").unwrap() != Value::Bit(true) {
            assert!(Instant::now() < end, "the spindle never reached its speed");
            std::thread::sleep(Duration::from_millis(10));
        }
        let fb = inst.pin_value("spindle-vfd.spindle-speed-fb").unwrap();
        assert!(
            matches!(fb, Value::Float(v) if (v - 12_000.0).abs() < 240.0),
            "{fb:?}"
        );
        assert_eq!(
            inst.pin_value("spindle-vfd.modbus-ok").unwrap(),
            Value::Bit(true)
        );
        assert_eq!(
            inst.pin_value("spindle-vfd.fault").unwrap(),
            Value::Bit(false)
        );
    }
    let out = String::from_utf8_lossy(&out);
    let err = String::from_utf8_lossy(&err);
    assert!(out.contains("spindle-vfd.OutF"), "{out}\n{err}");
    assert!(out.contains("spindle-rpm"), "{out}");
    assert!(out.contains("400  spindle-vfd.max-freq"), "{out}");
    assert!(out.contains("24000  spindle-vfd.rated-motor-rev"), "{out}");
    // As in LinuxCNC, a program loadusr started outlives the halcmd
    // session; the host stops it when the instance stops.
    assert!(inst.component("spindle-vfd").unwrap().is_some());
    drop(inst);
    hal_lang::host_process::stop_host(&name, Duration::from_secs(20)).unwrap();
    host.join().unwrap();
}

/// A HAL file written for LinuxCNC 2.10 nets hy_gt_vfd's
/// `fault-info-code` (u32) beside `fault-info` (float): it loads, and
/// both carry register 0x5000.
#[test]
fn a_hal_file_netting_the_gt_fault_code_loads() {
    let mut cfg = HostConfig::for_tests("gt-fault-code");
    cfg.shm_size = 8 << 20;
    let name = cfg.instance.clone();
    let (tx, rx) = std::sync::mpsc::channel();
    let host = std::thread::spawn(move || {
        hal_host::serve(cfg, move || {
            let _ = tx.send(());
        })
        .expect("the host serves");
    });
    rx.recv_timeout(Duration::from_secs(60))
        .expect("host ready");
    let inst = Instance::attach(&name).unwrap();
    let text = "\
loadusr -Wn gt hy_gt_vfd -n gt -d sim -S 24000 -F 400 -f 120
net vfd-fault-code gt.fault-info-code
net vfd-fault-info gt.fault-info
";
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let ok = {
        let mut session = hal_lang::Session::new(
            inst.clone(),
            hal_lang::Options::default(),
            &mut out,
            &mut err,
        );
        session.run_text(Some("gt.hal"), text)
    };
    assert!(ok, "{}", String::from_utf8_lossy(&err));
    assert_eq!(inst.signal_value("vfd-fault-code").unwrap(), Value::U32(0));
    drop(inst);
    hal_lang::host_process::stop_host(&name, Duration::from_secs(20)).unwrap();
    host.join().unwrap();
}
