//! mesambccc: LinuxCNC's XML command sources compiled into files
//! hm2_modbus loads, the names and types of the pins they make, the
//! automatic timeouts, and refusals that name their line; then the
//! compiled file run against the simulated Modbus slave.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use hostmot2::modbus::encode::encode;
use hostmot2::modbus::mbccb::{self, flags, format, HalType, Init, ModbusType};
use hostmot2::modbus::mbccs::compile;
use hostmot2::Hm2Error;

const SOURCE: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<mesamodbus baudrate="19200" parity="E" suspend="false" writeflush="false">
  <devices>
    <device address="0x01" name="relays" />
    <device address="0x02" name="vfd"><description>spindle</description></device>
  </devices>
  <initlist>
    <command device="vfd" function="W_REGISTER" address="0x0034">
      <data value="1" />
    </command>
    <command delay="20000" />
    <command device="relays" function="W_COILS" address="0">
      <data value="0" /><data value="1" /><data value="1" /><data value="0" />
    </command>
    <command device="vfd" function="W_REGISTERS" address="0xcafe">
      <data modbustype="F_ABCD" value="0.53" />
    </command>
  </initlist>
  <commands>
    <command device="relays" function="R_COILS" address="0" count="4" name="state" />
    <command device="vfd" function="R_REGISTERS" address="0x28" modbustype="F_ABCD" haltype="HAL_FLOAT">
      <pin name="freq" />
      <pin name="ok" haltype="HAL_BIT" modbustype="U_AB" />
      <pin skip="1" />
      <pin name="load" scale="0" />
    </command>
    <command delay="1000" />
    <command device="vfd" function="W_REGISTER" address="0x1ee7" haltype="HAL_U32" modbustype="U_AB" resend="1" noanswer="1" name="watch" />
    <command device="relays" function="W_COILS" address="8" count="2" name="out" interval="once" />
  </commands>
</mesamodbus>
"#;

#[test]
fn a_source_compiles_to_what_hm2_modbus_loads() {
    let (f, warnings) = compile(SOURCE).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(f.baudrate, 19_200);
    assert_eq!(f.format, format::PARITY_EN);
    assert_eq!(f.inits.len(), 4);
    match &f.inits[0] {
        Init::Packet {
            pdu,
            mbid: 2,
            func: 6,
            ..
        } => assert_eq!(pdu, &[2, 6, 0, 0x34, 0, 1]),
        other => panic!("{other:?}"),
    }
    assert_eq!(f.inits[1], Init::Delay { us: 20_000 });
    match &f.inits[2] {
        Init::Packet { pdu, .. } => assert_eq!(pdu, &[1, 15, 0, 0, 0, 4, 1, 0b0110]),
        other => panic!("{other:?}"),
    }
    match &f.inits[3] {
        Init::Packet { pdu, .. } => {
            assert_eq!(pdu, &[2, 16, 0xca, 0xfe, 0, 2, 4, 0x3f, 0x07, 0xae, 0x14])
        }
        other => panic!("{other:?}"),
    }
    let c = &f.commands;
    assert_eq!(c.len(), 5);
    let names: Vec<&str> = c[0].pins.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "relays.state-00",
            "relays.state-01",
            "relays.state-02",
            "relays.state-03"
        ]
    );
    let p = &c[1].pins;
    assert_eq!(
        (p[0].name.as_str(), p[0].htype, p[0].mtype, p[0].regofs),
        ("vfd.freq", HalType::Float, ModbusType(0x22), 0)
    );
    assert_eq!((p[1].htype, p[1].regofs), (HalType::Bit, 2));
    assert_eq!((p[2].name.as_str(), p[2].regofs), ("vfd.load", 4));
    assert_eq!(p[0].flags, 3, "float pins scale and clamp by default");
    assert_eq!(p[2].flags, 2, "scale=0 turns scaling off");
    assert_eq!(c[1].regcnt, 6);
    // Auto timeout: (8 + 3 + 6*2) bytes of 12 bits, x2.5 (690 bits),
    // doubled, rounded up to us, plus 16 ms: 87875 us.
    assert_eq!(
        c[1].timeout_us,
        (2 * 690 * 1_000_000u32).div_ceil(19_200) + 16_000
    );
    assert_eq!(c[2].func, 0);
    assert_eq!(c[2].timeout_us, 1000);
    assert_eq!(c[3].flags, flags::RESEND | flags::NOANSWER);
    assert_eq!(c[3].pins[0].name, "vfd.watch-00");
    assert_eq!(c[4].interval_us, u32::MAX);
    let back = mbccb::parse(&encode(&f)).unwrap();
    assert_eq!(back.commands, f.commands);
}

#[test]
fn refusals_name_their_line() {
    let line_of = |src: &str| match compile(src).unwrap_err() {
        Hm2Error::Mbccs { line, what, .. } => (line, what),
        e => panic!("{e}"),
    };
    let bad_dev = SOURCE.replace(
        r#"device="relays" function="R_COILS""#,
        r#"device="nosuch" function="R_COILS""#,
    );
    let (line, what) = line_of(&bad_dev);
    assert_eq!(line, 20);
    assert!(what.contains("'nosuch'"), "{what}");
    let bad_fn = SOURCE.replace(r#"function="R_COILS""#, r#"function="R_FOO""#);
    assert_eq!(line_of(&bad_fn).0, 20);
    let bad_xml = SOURCE.replace("</commands>", "</command>");
    assert!(line_of(&bad_xml).0 >= 28);
    let order = SOURCE.replace("<devices>", "<initlist/><devices>");
    assert!(line_of(&order).1.contains("<devices> tag must come first"));
    let dup = SOURCE.replace(r#"name="load""#, r#"name="freq""#);
    let (line, what) = line_of(&dup);
    assert_eq!(line, 25);
    assert!(what.contains("already in use"), "{what}");
    let range = SOURCE.replace(r#"baudrate="19200""#, r#"baudrate="300""#);
    assert!(line_of(&range).1.contains("1200..=1000000"));
    // Found by the fuzzer: a skip before the first pin compiled to a file
    // hm2_modbus refuses (its first pin must be at the first register).
    let lead = SOURCE.replace(
        "      <pin name=\"freq\" />\n",
        "      <pin skip=\"2\" />\n      <pin name=\"freq\" />\n",
    );
    let (line, what) = line_of(&lead);
    assert_eq!(line, 22);
    assert!(what.contains("before the first pin"), "{what}");
}

#[test]
fn the_command_line_tool_writes_the_file_and_refuses_with_status_1() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("x.mbccs");
    std::fs::write(&src, SOURCE).unwrap();
    let out = dir.path().join("x.mbccb");
    let st = std::process::Command::new(env!("CARGO_BIN_EXE_mesambccc"))
        .arg("-o")
        .arg(&out)
        .arg(&src)
        .status()
        .unwrap();
    assert!(st.success());
    assert!(mbccb::parse(&std::fs::read(&out).unwrap()).is_ok());
    std::fs::write(&src, SOURCE.replace("R_COILS", "R_NOPE")).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_mesambccc"))
        .arg("-o")
        .arg(dir.path().join("y.mbccb"))
        .arg(&src)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("x.mbccs: error: line 20"), "{err}");
    assert!(!dir.path().join("y.mbccb").exists());
}
