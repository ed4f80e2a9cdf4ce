//! hal_input's pins on simulated devices, in this process: names, types,
//! directions and starting values as LinuxCNC's; keys, wheels, sticks and
//! LEDs; inputspec look-up; and what a lost device leaves behind.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::Path;

use hal_core::{ComponentKind, HalType, Host, HostConfig, Instance, ParamDir, PinDir, Value};
use hal_input::regs::{Event, EV_ABS, EV_KEY, EV_LED, EV_MSC, EV_REL, EV_SYN, SYN_DROPPED};
use hal_input::run::{open, Bound};
use hal_input::sim::{parse, SimCatalogue};
use hal_input::spec::Parts;
use hal_input::InputError;

const DEVICES: &str = "\
device Sim Gamepad
phys usb-sim-1/input0
id 0003 046d c21d 0111
keys BTN_A BTN_B KEY_A
held BTN_B
abs ABS_X 0 255 2 10 128
abs ABS_HAT0X -1 1 0 0 0
rel REL_WHEEL REL_X REL_11
leds LED_NUML LED_CAPSL
device Sim Keyboard
phys isa0060/serio0/input0
id 0011 0001 0001 ab41
keys KEY_A KEY_B
leds LED_NUML
device Sim Keyboard
node /dev/input/event10
phys usb-sim-2/input0
id 0003 04d9 1603 0110
keys KEY_C
";

struct Rig {
    _host: Host,
    inst: Instance,
    comp: hal_core::Component,
    cat: SimCatalogue,
}

fn rig(tag: &str) -> Rig {
    let host = Host::create(HostConfig::for_tests(tag)).unwrap();
    let inst = host.instance().clone();
    let comp = inst
        .new_component("hal_input", ComponentKind::User)
        .unwrap();
    let cat = SimCatalogue::new(parse(DEVICES, "devices.txt", Path::new(".")).unwrap());
    Rig {
        _host: host,
        inst,
        comp,
        cat,
    }
}

impl Rig {
    fn bind(&self, index: usize, spec: &str, parts: Parts) -> Bound {
        let dev = open(&self.cat, spec).unwrap();
        Bound::new(&self.comp, index, dev, parts).unwrap()
    }

    fn get(&self, pin: &str) -> Value {
        self.inst
            .pin_value(pin)
            .unwrap_or_else(|e| panic!("{pin}: {e}"))
    }

    fn set(&self, pin: &str, v: Value) {
        self.inst.set_pin(pin, v).unwrap();
    }

    fn pin(&self, name: &str) -> (HalType, PinDir) {
        let p = self
            .inst
            .pin(name)
            .unwrap()
            .unwrap_or_else(|| panic!("no pin {name}"));
        (p.hal_type, p.dir)
    }
}

fn ev(kind: u16, code: u16, value: i32) -> Event {
    Event { kind, code, value }
}

fn syn() -> Event {
    ev(EV_SYN, 0, 0)
}

#[test]
fn pins_have_linuxcncs_names_types_and_defaults() {
    let r = rig("in-pins");
    let mut b = r.bind(0, "Gamepad", Parts::ALL);
    use HalType::*;
    use PinDir::{In, Out};
    for (name, want) in [
        ("input.0.btn-a", (Bit, Out)),
        ("input.0.btn-a-not", (Bit, Out)),
        ("input.0.key-a", (Bit, Out)),
        ("input.0.abs-x-counts", (S32, Out)),
        ("input.0.abs-x-position", (Float, Out)),
        ("input.0.abs-x-is-pos", (Bit, Out)),
        ("input.0.abs-x-is-neg", (Bit, Out)),
        ("input.0.abs-x-scale", (Float, In)),
        ("input.0.abs-x-offset", (Float, In)),
        ("input.0.abs-x-fuzz", (S32, In)),
        ("input.0.abs-x-flat", (S32, In)),
        ("input.0.abs-hat0x-counts", (S32, Out)),
        ("input.0.rel-wheel-counts", (S32, Out)),
        ("input.0.rel-wheel-position", (Float, Out)),
        ("input.0.rel-wheel-reset", (Bit, In)),
        ("input.0.rel-wheel-scale", (Float, In)),
        // REL_WHEEL_HI_RES, which LinuxCNC's tables do not name.
        ("input.0.rel-11-counts", (S32, Out)),
        ("input.0.led-numl", (Bit, In)),
        ("input.0.led-numl-invert", (Bit, In)),
        ("input.0.led-capsl", (Bit, In)),
    ] {
        assert_eq!(r.pin(name), want, "{name}");
    }
    for (name, want) in [("input.0.abs-x-min", 0), ("input.0.abs-x-max", 255)] {
        let p = r.inst.param(name).unwrap().unwrap();
        assert_eq!((p.hal_type, p.dir), (S32, ParamDir::Ro), "{name}");
        assert_eq!(p.value, Value::S32(want), "{name}");
    }
    // Starting values: keys released (-not true) except the one held,
    // the axis at its reported value, scale 1 for wheels, the axis range
    // mapped to [-1, 1].
    assert_eq!(r.get("input.0.btn-a"), Value::Bit(false));
    assert_eq!(r.get("input.0.btn-a-not"), Value::Bit(true));
    assert_eq!(r.get("input.0.btn-b"), Value::Bit(true), "held at start");
    assert_eq!(r.get("input.0.btn-b-not"), Value::Bit(false));
    assert_eq!(r.get("input.0.abs-x-counts"), Value::S32(128));
    assert_eq!(r.get("input.0.abs-x-scale"), Value::Float(127.5));
    assert_eq!(r.get("input.0.abs-x-offset"), Value::Float(127.5));
    assert_eq!(r.get("input.0.abs-x-fuzz"), Value::S32(2));
    assert_eq!(r.get("input.0.abs-x-flat"), Value::S32(10));
    assert_eq!(r.get("input.0.abs-x-position"), Value::Float(0.5 / 127.5));
    assert_eq!(r.get("input.0.rel-wheel-scale"), Value::Float(1.0));
    assert_eq!(r.get("input.0.abs-hat0x-scale"), Value::Float(1.0));
    // Every LED switched off at start.
    let h = r.cat.handle(0).unwrap();
    assert_eq!(
        h.written(),
        [ev(EV_LED, 0, 0), ev(EV_LED, 1, 0)],
        "LEDs off at start"
    );
    assert!(!h.grabbed());
    b.step().unwrap();
    assert_eq!(r.get("input.0.abs-x-is-pos"), Value::Bit(false));
}

#[test]
fn keys_wheels_and_sticks_drive_their_pins() {
    let r = rig("in-events");
    let mut b = r.bind(0, "Gamepad", Parts::ALL);
    let h = r.cat.handle(0).unwrap();
    h.push(&[ev(EV_KEY, 0x130, 1), ev(EV_MSC, 4, 9), syn()]);
    b.step().unwrap();
    assert_eq!(r.get("input.0.btn-a"), Value::Bit(true));
    assert_eq!(r.get("input.0.btn-a-not"), Value::Bit(false));
    // Autorepeat (2) is still held; 0 releases.
    h.push(&[ev(EV_KEY, 0x130, 2)]);
    b.step().unwrap();
    assert_eq!(r.get("input.0.btn-a"), Value::Bit(true));
    h.push(&[ev(EV_KEY, 0x130, 0)]);
    b.step().unwrap();
    assert_eq!(r.get("input.0.btn-a"), Value::Bit(false));
    assert_eq!(r.get("input.0.btn-a-not"), Value::Bit(true));

    // The wheel counts detents; position is counts / scale; reset holds
    // counts at zero.
    h.push(&[ev(EV_REL, 8, 1), ev(EV_REL, 8, 1), ev(EV_REL, 8, -5), syn()]);
    b.step().unwrap();
    assert_eq!(r.get("input.0.rel-wheel-counts"), Value::S32(-3));
    r.set("input.0.rel-wheel-scale", Value::Float(4.0));
    b.step().unwrap();
    assert_eq!(r.get("input.0.rel-wheel-position"), Value::Float(-0.75));
    r.set("input.0.rel-wheel-reset", Value::Bit(true));
    h.push(&[ev(EV_REL, 8, 7)]);
    b.step().unwrap();
    assert_eq!(r.get("input.0.rel-wheel-counts"), Value::S32(0));
    assert_eq!(r.get("input.0.rel-wheel-position"), Value::Float(0.0));
    r.set("input.0.rel-wheel-reset", Value::Bit(false));
    r.set("input.0.rel-wheel-scale", Value::Float(0.0));
    h.push(&[ev(EV_REL, 8, 2)]);
    b.step().unwrap();
    assert_eq!(
        r.get("input.0.rel-wheel-position"),
        Value::Float(2.0),
        "scale 0 is 1"
    );
    h.push(&[ev(EV_REL, 0, i32::MAX), ev(EV_REL, 0, 2)]);
    b.step().unwrap();
    assert_eq!(
        r.get("input.0.rel-x-counts"),
        Value::S32(i32::MIN + 1),
        "wraps"
    );

    // The stick: inside flat of the offset reads as the offset (int of
    // 127.5: 127); a change of no more than fuzz is ignored.
    h.push(&[ev(EV_ABS, 0, 255)]);
    b.step().unwrap();
    assert_eq!(r.get("input.0.abs-x-counts"), Value::S32(255));
    assert_eq!(r.get("input.0.abs-x-position"), Value::Float(1.0));
    assert_eq!(r.get("input.0.abs-x-is-pos"), Value::Bit(true));
    h.push(&[ev(EV_ABS, 0, 253)]);
    b.step().unwrap();
    assert_eq!(
        r.get("input.0.abs-x-counts"),
        Value::S32(255),
        "within fuzz"
    );
    h.push(&[ev(EV_ABS, 0, 135)]);
    b.step().unwrap();
    assert_eq!(
        r.get("input.0.abs-x-counts"),
        Value::S32(127),
        "within flat"
    );
    assert_eq!(r.get("input.0.abs-x-is-pos"), Value::Bit(false));
    assert_eq!(r.get("input.0.abs-x-is-neg"), Value::Bit(false));
    h.push(&[ev(EV_ABS, 0, 0)]);
    b.step().unwrap();
    assert_eq!(r.get("input.0.abs-x-position"), Value::Float(-1.0));
    assert_eq!(r.get("input.0.abs-x-is-neg"), Value::Bit(true));
    r.set("input.0.abs-x-scale", Value::Float(-127.5));
    b.step().unwrap();
    assert_eq!(
        r.get("input.0.abs-x-position"),
        Value::Float(1.0),
        "scale flips"
    );
}

#[test]
fn leds_follow_their_pins_and_invert() {
    let r = rig("in-leds");
    let mut b = r.bind(0, "Gamepad", Parts::ALL);
    let h = r.cat.handle(0).unwrap();
    b.step().unwrap();
    assert_eq!(h.written().len(), 2, "nothing new while unchanged");
    r.set("input.0.led-numl", Value::Bit(true));
    b.step().unwrap();
    b.step().unwrap();
    r.set("input.0.led-capsl-invert", Value::Bit(true));
    b.step().unwrap();
    r.set("input.0.led-numl-invert", Value::Bit(true));
    b.step().unwrap();
    assert_eq!(
        h.written()[2..],
        [ev(EV_LED, 0, 1), ev(EV_LED, 1, 1), ev(EV_LED, 0, 0)]
    );
}

#[test]
fn subsets_make_only_their_pins_and_ignore_other_events() {
    let r = rig("in-parts");
    let parts = Parts {
        keys: true,
        rel: true,
        abs: false,
        leds: false,
    };
    let mut b = r.bind(0, "Gamepad", parts);
    assert!(r.inst.pin("input.0.btn-a").unwrap().is_some());
    assert!(r.inst.pin("input.0.rel-x-counts").unwrap().is_some());
    assert!(r.inst.pin("input.0.abs-x-counts").unwrap().is_none());
    assert!(r.inst.pin("input.0.led-numl").unwrap().is_none());
    let h = r.cat.handle(0).unwrap();
    assert!(h.written().is_empty(), "no LED touched without L");
    h.push(&[ev(EV_ABS, 0, 3)]);
    assert!(
        b.step().unwrap().is_empty(),
        "an axis left out is no surprise"
    );
    // A code the device did not announce is reported, once.
    h.push(&[
        ev(EV_KEY, 0x132, 1),
        ev(EV_KEY, 0x132, 0),
        ev(EV_REL, 12, 120),
    ]);
    let notes = b.step().unwrap();
    assert_eq!(notes.len(), 2, "{notes:?}");
    assert!(notes[0].contains("EV_KEY BTN_C"), "{notes:?}");
    assert!(notes[1].contains("EV_REL REL_12"), "{notes:?}");
}

#[test]
fn a_lost_sync_reads_the_held_keys_and_axes_again() {
    let r = rig("in-dropped");
    let mut b = r.bind(0, "Gamepad", Parts::ALL);
    let h = r.cat.handle(0).unwrap();
    h.push(&[ev(EV_KEY, 0x131, 0), ev(EV_KEY, 0x130, 1)]);
    b.step().unwrap();
    assert_eq!(r.get("input.0.btn-b"), Value::Bit(false));
    h.push(&[ev(EV_ABS, 0, 0)]);
    b.step().unwrap();
    assert_eq!(r.get("input.0.abs-x-counts"), Value::S32(0));
    // The simulated kernel says BTN_B is held and ABS_X at 128: a
    // SYN_DROPPED reads both again.
    h.push(&[ev(EV_SYN, SYN_DROPPED, 0)]);
    b.step().unwrap();
    assert_eq!(r.get("input.0.btn-b"), Value::Bit(true));
    assert_eq!(r.get("input.0.btn-a"), Value::Bit(false));
    assert_eq!(
        r.get("input.0.abs-x-counts"),
        Value::S32(127),
        "128 is within flat"
    );
}

#[test]
fn a_lost_device_leaves_keys_released_and_sticks_centred() {
    let r = rig("in-lost");
    let mut b = r.bind(0, "Gamepad", Parts::ALL);
    let h = r.cat.handle(0).unwrap();
    r.inst.newsig("jog", HalType::Bit).unwrap();
    r.inst.link("input.0.btn-a", "jog").unwrap();
    h.push(&[ev(EV_KEY, 0x130, 1), ev(EV_ABS, 0, 255), ev(EV_REL, 8, 4)]);
    b.step().unwrap();
    assert_eq!(r.inst.signal_value("jog").unwrap(), Value::Bit(true));
    h.unplug();
    let e = b.step().unwrap_err();
    assert!(matches!(e, InputError::Gone { .. }), "{e}");
    assert!(e.to_string().contains("Sim Gamepad"), "{e}");
    b.pins.safe_state();
    assert_eq!(r.inst.signal_value("jog").unwrap(), Value::Bit(false));
    assert_eq!(r.get("input.0.btn-a-not"), Value::Bit(true));
    assert_eq!(r.get("input.0.abs-x-counts"), Value::S32(127));
    assert_eq!(r.get("input.0.abs-x-is-pos"), Value::Bit(false));
    assert_eq!(r.get("input.0.rel-wheel-counts"), Value::S32(4), "kept");
    // The component gone, the signal keeps the released state.
    drop(b);
    drop(r.comp);
    assert_eq!(r.inst.signal_value("jog").unwrap(), Value::Bit(false));
}

#[test]
fn inputspecs_pick_devices_as_linuxcncs() {
    let r = rig("in-find");
    let name = |spec: &str| match open(&r.cat, spec) {
        Ok(d) => format!("{} {}", d.identity().name, d.identity().path.display()),
        Err(e) => format!("error: {e}"),
    };
    assert_eq!(name("Gamepad"), "Sim Gamepad /dev/input/event0");
    assert_eq!(name("0"), "Sim Gamepad /dev/input/event0");
    assert_eq!(name("/dev/input/event1"), "Sim Keyboard /dev/input/event1");
    assert_eq!(name("Keyboard"), "Sim Keyboard /dev/input/event1");
    assert_eq!(name("Keyboard:0"), "Sim Keyboard /dev/input/event1");
    assert_eq!(name("Keyboard:1"), "Sim Keyboard /dev/input/event10");
    assert!(name("Keyboard:2").starts_with("error: no input device matching 'Keyboard'"));
    assert_eq!(name("10"), "Sim Keyboard /dev/input/event10");
    assert_eq!(name("*serio0*"), "Sim Keyboard /dev/input/event1");
    assert_eq!(name("serio0"), "Sim Keyboard /dev/input/event1");
    assert_eq!(name("Vendor=04d9"), "Sim Keyboard /dev/input/event10");
    assert_eq!(name("Bus=BUS_I8042"), "Sim Keyboard /dev/input/event1");
    assert_eq!(name("046d:c21d"), "Sim Gamepad /dev/input/event0");
    assert_eq!(name("Sim ?amepad"), "Sim Gamepad /dev/input/event0");
    assert!(name("Sim:x").contains("no input device matching 'Sim:x'"));
    assert_eq!(
        name("usb-sim-2/input0:0"),
        "Sim Keyboard /dev/input/event10"
    );
    let e = name("Joystick");
    assert!(
        e.contains("no input device matching 'Joystick' was found (3 devices checked)"),
        "{e}"
    );
    // `+` takes the device alone.
    let _d = open(&r.cat, "+Gamepad").unwrap();
    assert!(r.cat.handle(0).unwrap().grabbed());
    let none = SimCatalogue::new(Vec::new());
    let e = open(&none, "x").err().unwrap().to_string();
    assert!(
        e.contains("no input devices: the --sim description has no event nodes"),
        "{e}"
    );
    let text = "device Broken\nevents /nonexistent/pad.fifo\n";
    let broken = SimCatalogue::new(parse(text, "b.txt", Path::new(".")).unwrap());
    let e = open(&broken, "Broken").err().unwrap().to_string();
    assert!(
        e.contains("none of the 1 input devices in the --sim description could be opened")
            && e.contains("/nonexistent/pad.fifo")
            && e.contains("read and write access"),
        "{e}"
    );
}

#[test]
fn two_devices_number_their_pins_in_order() {
    let r = rig("in-two");
    let _a = r.bind(0, "Keyboard:1", Parts::ALL);
    let _b = r.bind(1, "Gamepad", Parts::ALL);
    assert!(r.inst.pin("input.0.key-c").unwrap().is_some());
    assert!(r.inst.pin("input.1.btn-a").unwrap().is_some());
    assert!(r.inst.pin("input.0.btn-a").unwrap().is_none());
}
