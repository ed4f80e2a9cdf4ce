//! Every kind of bad HAL line gets its message, with the file and line,
//! and changes nothing.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use hal_host::testing::InProcessHost;

const SETUP: &str = "loadrt and2\nloadrt mult2\nloadrt threads name1=t period1=1000000\n";

#[test]
fn every_kind_of_bad_line_has_its_message() {
    let host = InProcessHost::start("badlines");
    let (ok, _, err) = host.run("setup.hal", SETUP, false);
    assert!(ok, "{err}");
    let cases: &[(&str, &str)] = &[
        ("frobnicate", "bad.hal:1: Unknown command 'frobnicate'\n"),
        // Argument counts, in LinuxCNC's words: "at least" for commands
        // that take more, "at most" for those that take fewer; arrows are
        // not counted where they are allowed.
        ("setp", "bad.hal:1: setp requires 2 arguments, 0 given\n"),
        ("setp and2.0.in0 1 2", "bad.hal:1: setp requires 2 arguments, 3 given\n"),
        ("and2.0.in0 = 1 2", "bad.hal:1: Unknown command 'and2.0.in0'\n"),
        ("net", "bad.hal:1: net requires at least 1 arguments, 0 given\n"),
        ("list", "bad.hal:1: list requires at least 1 arguments, 0 given\n"),
        ("delf and2.0 t x", "bad.hal:1: delf requires at most 2 arguments, 3 given\n"),
        ("start now", "bad.hal:1: start requires 0 arguments, 1 given\n"),
        ("getp a b", "bad.hal:1: getp requires 1 arguments, 2 given\n"),
        ("linkps and2.0.in0 =>", "bad.hal:1: linkps requires 2 arguments, 1 given\n"),
        ("linkps and2.0.in0 => x y", "bad.hal:1: linkps requires 2 arguments, 3 given\n"),
        ("linksp x <= and2.0.in0 and2.0.in1", "bad.hal:1: linksp requires 2 arguments, 3 given\n"),
        ("linkpp and2.0.in0 =>", "bad.hal:1: linkpp requires 2 arguments, 1 given\n"),
        ("alias pin and2.0.in0", "bad.hal:1: alias requires 3 arguments, 2 given\n"),
        ("show pin -tbogus", "bad.hal:1: unknown type 'bogus'\n"),
        ("list pin -t bogus", "bad.hal:1: unknown type 'bogus'\n"),
        ("newsig x double", "bad.hal:1: Unknown signal type 'double'\n"),
        ("newsig bad=name bit", "HAL: ERROR: bad signal name 'bad=name': names must not contain any of # = \" ' \\ < > $ ;\nbad.hal:1: newsig failed\n"),
        ("net x nope.pin", "bad.hal:1: Pin 'nope.pin' does not exist\n"),
        ("net y and2.0.out mult2.0.in0", "bad.hal:1: Signal 'y' of type 'bit' cannot add pin 'mult2.0.in0' of type 'float'\n"),
        ("addf nope t", "HAL: ERROR: function 'nope' not found\nbad.hal:1: addf failed\n"),
        ("addf and2.0 nope", "HAL: ERROR: thread 'nope' not found\nbad.hal:1: addf failed\n"),
        ("addf and2.0 t 5", "HAL: ERROR: position 5 is out of range for thread 't' with 0 functions\nbad.hal:1: addf failed\n"),
        ("delf and2.0 t", "HAL: ERROR: function 'and2.0' is not in thread 't'\nbad.hal:1: delf failed\n"),
        ("loadrt and2", "HAL: ERROR: module 'and2' is already loaded\nbad.hal:1: insmod for and2 failed, returned -1\n"),
        ("loadrt or2 count=x", "HAL: ERROR: or2: parameter 'count': 'x' is not a number\nbad.hal:1: insmod for or2 failed, returned -1\n"),
        ("loadrt or2 bogus=1", "HAL: ERROR: or2: parameter 'bogus': unknown parameter (or2 takes count, names)\nbad.hal:1: insmod for or2 failed, returned -1\n"),
        ("loadrt or2 count=1 names=a", "HAL: ERROR: or2: count= and names= are mutually exclusive\nbad.hal:1: insmod for or2 failed, returned -1\n"),
        ("loadrt nosuch", "HAL: ERROR: module 'nosuch' not found\nbad.hal:1: insmod for nosuch failed, returned -1\n"),
        ("loadrt sampler", "HAL: ERROR: sampler: no channels specified\nbad.hal:1: insmod for sampler failed, returned -1\n"),
        ("loadrt threads name1=t period1=1000000", "HAL: ERROR: module 'threads' is already loaded\nbad.hal:1: insmod for threads failed, returned -1\n"),
        ("setp and2.0.in0 2", "bad.hal:1: pin 'and2.0.in0': invalid argument\n"),
        ("setp and2.0.out 1", "bad.hal:1: pin 'and2.0.out': not writable\n"),
        ("setp mult2.0.in0 1e999", "bad.hal:1: pin 'mult2.0.in0': value out of range\n"),
        ("setp and2.0.tmax-increased 1", "bad.hal:1: parameter 'and2.0.tmax-increased': not writable\n"),
        ("setp nope 1", "bad.hal:1: parameter or pin 'nope': not found\n"),
        ("getp nope", "bad.hal:1: parameter or pin 'nope': not found\n"),
        ("ptype nope", "bad.hal:1: parameter or pin 'nope': not found\n"),
        ("sets nope 1", "bad.hal:1: signal 'nope': not found\n"),
        ("gets nope", "bad.hal:1: signal 'nope': not found\n"),
        ("stype nope", "bad.hal:1: signal 'nope': not found\n"),
        ("net q", "bad.hal:1: 'net' requires at least one pin, none given\n"),
        ("net and2.0.in0 and2.0.in1", "bad.hal:1: Signal name 'and2.0.in0' must not be the same as a pin.  Did you omit the signal name?\n"),
        ("waitusr and2", "bad.hal:1: waitusr: component 'and2' not found or not a user component\n"),
        ("delsig nope", "bad.hal:1: signal 'nope' not found\n"),
        ("linkps nope x", "HAL: ERROR: pin 'nope' not found\nbad.hal:1: link failed\n"),
        ("linksp x nope", "HAL: ERROR: pin 'nope' not found\nbad.hal:1: link failed\n"),
        ("unlinkp nope", "HAL: ERROR: pin 'nope' not found\nbad.hal:1: unlink failed\n"),
        ("alias thing a b", "bad.hal:1: alias: unknown type 'thing', use pin or param\n"),
        ("alias pin nope x", "HAL: ERROR: pin 'nope' not found\nbad.hal:1: alias failed\n"),
        ("unalias param nope", "HAL: ERROR: param 'nope' not found\nbad.hal:1: unalias failed\n"),
        ("unload nope", "bad.hal:1: component 'nope' is not loaded\n"),
        ("show things", "bad.hal:1: Unknown 'show' type 'things'\n"),
        ("list things", "bad.hal:1: Unknown 'list' type 'things'\n"),
        ("save things", "bad.hal:1: Unknown 'save' type 'things'\n"),
        ("loadusr", "bad.hal:1: loadusr: needs a program to run\n"),
        ("loadusr -x prog", "bad.hal:1: loadusr: unknown option '-x'\n"),
        ("loadusr -Wx prog", "bad.hal:1: loadusr: unknown option '-x'\n"),
        ("loadusr -Wn", "bad.hal:1: loadusr: -n needs a name\n"),
        ("waitusr nope", "bad.hal:1: waitusr: component 'nope' not found or not a user component\n"),
        ("unloadusr nope", "bad.hal:1: unloadusr: component 'nope' not found\n"),
        ("print \"unterminated", "bad.hal:1: unterminated quoted string\n"),
        ("setp x $NO_SUCH_VAR_HALCMD_TEST", "bad.hal:1: Environment variable 'NO_SUCH_VAR_HALCMD_TEST' not found.\n"),
        ("setp x [EMC]NAME", "bad.hal:1: Ini variable '[EMC]NAME' not found (no INI file given: use -i).\n"),
        ("source /no/such/file.hal", "bad.hal:1: source /no/such/file.hal: No such file or directory (os error 2)\n"),
        ("help nope", "bad.hal:1: No help for unknown command 'nope'\n"),
    ];
    let inst = host.instance();
    let snapshot = |i: &hal_core::Instance| {
        format!(
            "{:?}{:?}{:?}{:?}",
            i.pins().unwrap(),
            i.signals().unwrap(),
            i.params().unwrap(),
            i.functs().unwrap()
        )
    };
    let before = snapshot(&inst);
    let mut wrong = Vec::new();
    for (line, want) in cases {
        let (ok, out, err) = host.run("bad.hal", line, false);
        if ok || err != *want || !out.is_empty() {
            wrong.push(format!(
                "{line:?}\n  want {want:?}\n  got  {err:?} (ok {ok}, stdout {out:?})"
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    assert_eq!(
        before,
        snapshot(&inst),
        "a failed command changed the instance"
    );
}

#[test]
fn a_file_stops_at_the_first_error_unless_keep_going() {
    let host = InProcessHost::start("keepgoing");
    let text = "loadrt and2\nbogus 1\nsetp and2.0.in0 1\nbogus 2\ngetp and2.0.in0\n";
    let (ok, out, err) = host.run("f.hal", text, false);
    assert!(!ok);
    assert_eq!(out, "");
    assert_eq!(err, "f.hal:2: Unknown command 'bogus'\n");
    let (ok, out, err) = host.run(
        "g.hal",
        "setp and2.0.in0 0\nbogus 1\nsetp and2.0.in0 1\nbogus 2\ngetp and2.0.in0\n",
        true,
    );
    assert!(!ok, "a failure still fails the run with -k");
    assert_eq!(out, "TRUE\n");
    assert_eq!(
        err,
        "g.hal:2: Unknown command 'bogus'\ng.hal:4: Unknown command 'bogus'\n"
    );
}

#[test]
fn ini_and_environment_substitution() {
    let host = InProcessHost::start("subst");
    let dir = std::env::temp_dir().join(common::instance("ini"));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("m.ini"), "[AXIS_X]\nMAX = 2.5\n").unwrap();
    std::env::set_var("HALCMD_SUBST_TEST", "mult2");
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let opts = hal_lang::Options {
        ini: Some(hal_lang::ini::Ini::parse(
            &std::fs::read_to_string(dir.join("m.ini")).unwrap(),
        )),
        ..Default::default()
    };
    let ok = hal_lang::Session::new(host.instance(), opts, &mut out, &mut err).run_text(
        Some("s.hal"),
        "loadrt $HALCMD_SUBST_TEST\nsetp $(HALCMD_SUBST_TEST).0.in0 [AXIS_X]MAX\ngetp mult2.0.in0\n",
    );
    assert!(ok, "{}", String::from_utf8_lossy(&err));
    assert_eq!(String::from_utf8_lossy(&out), "2.5\n");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn script_mode_show_is_one_line_per_object_without_titles() {
    let host = InProcessHost::start("script");
    let (ok, _, err) = host.run(
        "s.hal",
        "loadrt threads name1=t period1=1000000\nloadrt and2\naddf and2.0 t\nnet x and2.0.out and2.0.in0\n",
        false,
    );
    assert!(ok, "{err}");
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let opts = hal_lang::Options {
        script: true,
        ..Default::default()
    };
    let mut s = hal_lang::Session::new(host.instance(), opts, &mut out, &mut err);
    let ok = s.run_text(
        None,
        "show sig\nshow thread\nshow pin and2.0.out\nlinkpp and2.0.in1 and2.0.out\n",
    );
    assert!(!ok, "linkpp onto a linked pin fails");
    drop(s);
    assert_eq!(
        String::from_utf8_lossy(&out),
        "bit FALSE x ==> and2.0.in0 <== and2.0.out\n1000000 YES t and2.0\nand2 bit OUT FALSE and2.0.out ==> x\n"
    );
    // linkpp failed: and2.0.out is already on x.
    assert!(
        String::from_utf8_lossy(&err).contains("Pin 'and2.0.out' was already linked to signal 'x'")
    );
}

#[test]
fn arrows_of_any_shape_are_ignored_and_show_filters_by_type() {
    let host = InProcessHost::start("arrows");
    let (ok, out, err) = host.run(
        "a.hal",
        "loadrt and2\nloadrt mult2\nnet x and2.0.out ==> and2.0.in0\nnet y mult2.0.out => mult2.0.in0\nshow sig -tfloat\nshow pin -t bit and2.0.in\n",
        false,
    );
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "Signals:\nType                  Value  Name     (linked to)\nfloat                     0  y\n                                 ==> mult2.0.in0\n                                 <== mult2.0.out\n\n\
         Component Pins:\nOwner   Type  Dir                 Value  Name\n     6  bit   IN                  FALSE  and2.0.in0 <== x\n     6  bit   IN                  FALSE  and2.0.in1\n\n"
    );
}

#[test]
fn a_halcmd_started_by_loadusr_talks_to_the_same_host() {
    let host = InProcessHost::start("nested");
    let halcmd = env!("CARGO_BIN_EXE_halcmd");
    let text = format!("loadrt or2\nloadusr -w {halcmd} loadrt and2\nlist comp and2\n");
    let (ok, out, err) = host.run("n.hal", &text, false);
    assert!(ok, "{err}");
    assert_eq!(out, "and2 \n");
}

#[test]
fn type_filters_work_in_script_mode_and_in_list() {
    let host = InProcessHost::start("tfilter");
    let (ok, out, err) = host.run(
        "t.hal",
        "loadrt and2\nloadrt mult2\nlist pin -t bit\nlist pin -tfloat mult2.0.in\n",
        false,
    );
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "and2.0.in0 and2.0.in1 and2.0.out \nmult2.0.in0 mult2.0.in1 \n"
    );
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let opts = hal_lang::Options {
        script: true,
        ..Default::default()
    };
    let mut s = hal_lang::Session::new(host.instance(), opts, &mut out, &mut err);
    let ok = s.run_text(None, "show pin -tbit\nshow pin -t float mult2.0.in\n");
    drop(s);
    assert!(ok, "{}", String::from_utf8_lossy(&err));
    assert_eq!(
        String::from_utf8_lossy(&out),
        "and2 bit IN FALSE and2.0.in0\nand2 bit IN FALSE and2.0.in1\nand2 bit OUT FALSE and2.0.out\n\
         mult2 float IN 0 mult2.0.in0\nmult2 float IN 0 mult2.0.in1\n"
    );
}

#[test]
fn a_param_wins_over_a_pin_of_the_same_name() {
    use hal_core::{ComponentKind, In, Param, Pin, Rw, Value};
    let host = InProcessHost::start("samename");
    let inst = host.instance();
    let c = inst.new_component("same", ComponentKind::User).unwrap();
    let _pin: Pin<f64, In> = c.pin("same.x").unwrap();
    let _param: Param<u32, Rw> = c.param("same.x", 7).unwrap();
    let _only_param: Param<u32, Rw> = c.param("same.p", 1).unwrap();
    let (ok, out, err) = host.run(
        "p.hal",
        "loadrt and2\ngetp same.x\nptype same.x\nsetp same.x 9\ngetp same.x\n\
         same.x = 11\ngetp same.x\nnet same.p and2.0.out\n",
        false,
    );
    assert!(ok, "{err}");
    assert_eq!(out, "7\nu32\n9\n11\n");
    assert_eq!(
        inst.pin_value("same.x").unwrap(),
        Value::Float(0.0),
        "the pin is untouched"
    );
    // A signal may take a param's name but not a pin's, even when a param
    // has that name too.
    let (ok, _, err) = host.run("q.hal", "net same.x and2.0.in0\n", false);
    assert!(!ok);
    assert_eq!(
        err,
        "q.hal:1: Signal name 'same.x' must not be the same as a pin.  Did you omit the signal name?\n"
    );
}

#[test]
fn loadusr_flags_combine_in_one_word() {
    let host = InProcessHost::start("usrflags");
    // -w and -i together: a failing program is waited for and forgiven.
    let (ok, _, err) = host.run("u.hal", "loadusr -wi false\n", false);
    assert!(ok, "{err}");
    let (ok, _, err) = host.run("u.hal", "loadusr -w false\n", false);
    assert!(!ok);
    assert!(err.starts_with("u.hal:1: false exited with "), "{err}");
    // -Wn NAME: the word after -Wn is the name, the next the program.
    let (ok, _, err) = host.run("u.hal", "loadusr -Wn spindle true\n", false);
    assert!(!ok);
    assert!(
        err.starts_with("u.hal:1: true exited (") && err.ends_with(") without becoming ready\n"),
        "{err}"
    );
}

#[test]
fn unload_finds_the_component_and_unloads_its_module() {
    let host = InProcessHost::start("unload");
    let (ok, out, err) = host.run(
        "u.hal",
        "loadrt or2\nloadrt and2\nunload or2\nlist comp or2\nlist comp and2\n",
        false,
    );
    assert!(ok, "{err}");
    assert_eq!(out, "\nand2 \n");
}

/// Bytes that are not UTF-8 (a Latin-1 comment in an old config) used to
/// fail the whole file, and on stdin to end it silently with success;
/// found by the halcmd fuzz targets. As in LinuxCNC, such a byte only
/// spoils the word it is in.
#[test]
fn bytes_that_are_not_utf8_spoil_only_their_word() {
    let dir = std::env::temp_dir().join(common::instance("latin1"));
    std::fs::create_dir_all(&dir).unwrap();
    let text = b"loadrt and2\n# Achse f\xfcr X\nsource inc.hal\nsetp and2.0.in\xff 1\nshow comp\n";
    std::fs::write(dir.join("l1.hal"), text).unwrap();
    std::fs::write(dir.join("inc.hal"), b"# \xe9t\xe9\nsetp and2.0.in0 1\n").unwrap();
    std::fs::write(dir.join("m.ini"), b"# \xb0C\n[X]\nK = 1\n").unwrap();
    let want_err = "l1.hal:4: parameter or pin 'and2.0.in\u{fffd}': not found\n";

    let out = common::halrun(&dir, &["-k", "-i", "m.ini", "-f", "l1.hal"], "latin1-file");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains(" and2 "), "{stdout}");
    assert_eq!(String::from_utf8_lossy(&out.stderr), want_err);
    assert_eq!(out.status.code(), Some(1));

    // Commands on standard input: halrun without a file reads them there.
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_halrun"))
        .args(["-k"])
        .current_dir(&dir)
        .env("HAL_INSTANCE", common::instance("latin1-stdin"))
        .env("HAL_NO_REALTIME", "1")
        .env("HAL_SHM_SIZE", (8u64 << 20).to_string())
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    use std::io::Write;
    child.stdin.take().unwrap().write_all(text).unwrap();
    let out = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains(" and2 "),
        "the lines after the bytes ran: {stdout}"
    );
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("'and2.0.in\u{fffd}': not found"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(out.status.code(), Some(1));
    let _ = std::fs::remove_dir_all(dir);
}

/// A word with the protocol's separator (0x1F) is refused before it is
/// sent; the session used to drop its link to the host for it, which a
/// session on an in-process host (the fuzz target's) could not get back.
#[test]
fn a_word_the_protocol_refuses_keeps_the_link_to_the_host() {
    let host = std::sync::Arc::new(
        hal_core::Host::create(hal_core::HostConfig::for_tests("sepword")).unwrap(),
    );
    let inst = hal_core::Instance::attach(host.instance().name()).unwrap();
    let link = hal_host::InProcess::new(host.clone(), hal_host::registry());
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let opts = hal_lang::Options {
        keep_going: true,
        ..Default::default()
    };
    let ok = hal_lang::Session::new(inst, opts, &mut out, &mut err)
        .with_host_link(Box::new(link))
        .run_text(
            Some("s.hal"),
            "loadrt and2 count=1\u{1f}\nloadrt or2\nshow comp or2\n",
        );
    let err = String::from_utf8_lossy(&err);
    assert!(!ok);
    assert!(err.contains("control separator"), "{err}");
    assert!(!err.contains("s.hal:2"), "the next request failed: {err}");
    assert!(String::from_utf8_lossy(&out).contains(" or2 "));
    host.shutdown();
}
