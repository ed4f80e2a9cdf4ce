//! halcmd's INI substitution, quit/exit and locks; halrun's trailing file,
//! .tcl and .ini files and -U; haltcl with INI arrays; a machine's HAL
//! files with #INCLUDE, LIB: names and TWOPASS.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use machine::{instance, root, text, tool, Scratch};

/// `halrun ARGS` in `dir`: (success, stdout, stderr).
fn halrun(dir: &std::path::Path, args: &[&str], tag: &str) -> (bool, String, String) {
    text(&tool(
        env!("CARGO_BIN_EXE_halrun"),
        args,
        &instance(tag),
        Some(dir),
    ))
}

#[test]
fn ini_values_with_spaces_become_several_words() {
    let s = Scratch::new("subst");
    s.write(
        "m.ini",
        "[KINS]\nKINEMATICS = trivkins coordinates=xz kinstype=both\nJOINTS = 2\n\
         [P]\nMOD = and2 count=2\nPERIOD = 1000000\n",
    );
    s.write(
        "f.hal",
        "loadrt [KINS]KINEMATICS\n\
         loadrt motmod num_joints=[KINS]JOINTS servo_period_nsec=[P]PERIOD\n\
         loadrt [P]MOD # a comment\n\
         list pin and2.1.out\n\
         list pin joint.1.motor-pos-cmd\n",
    );
    let (ok, out, err) = halrun(&s.0, &["-i", "m.ini", "f.hal"], "subst");
    assert!(ok, "{err}");
    assert_eq!(out, "and2.1.out \njoint.1.motor-pos-cmd \n");
    s.write("g.hal", "setp and2.0.in0 [P]NOPE\n");
    let (ok, _, err) = halrun(&s.0, &["-i", "m.ini", "g.hal"], "subst2");
    assert!(!ok);
    assert_eq!(err, "g.hal:1: Ini variable '[P]NOPE' not found.\n");
}

#[test]
fn quit_and_exit_end_a_file_successfully() {
    let s = Scratch::new("quit");
    for word in ["quit", "exit"] {
        s.write(
            "q.hal",
            &format!("loadrt and2\nlist pin and2.0.out\n{word}\nno such command\n"),
        );
        let (ok, out, err) = halrun(&s.0, &["q.hal"], "quit");
        assert!(ok, "{word}: {err}");
        assert_eq!(out, "and2.0.out \n");
        assert!(err.is_empty(), "{err}");
    }
}

#[test]
fn every_lock_is_enforced_and_reported() {
    let s = Scratch::new("lock");
    s.write(
        "l.hal",
        "loadrt threads name1=t period1=1000000\n\
         loadrt and2\n\
         status lock\n\
         lock tune\n\
         status lock\n\
         loadrt or2\n\
         loadusr -W true\n\
         net s and2.0.out\n\
         addf and2.0 t\n\
         setp and2.0.tmax 5\n\
         setp and2.0.in0 1\n\
         unlock tune\n\
         lock params\n\
         setp and2.0.tmax 6\n\
         lock run\n\
         start\n\
         status lock\n\
         unlock\n\
         net s and2.0.out\n\
         setp and2.0.tmax 7\n\
         start\n\
         lock bogus\n\
         status\n",
    );
    let (ok, out, err) = halrun(&s.0, &["-k", "l.hal"], "lock");
    assert!(!ok, "failed commands make -k fail");
    let want_err = "\
HAL: ERROR: loadrt called while HAL locked
l.hal:6: insmod for or2 failed, returned -1
l.hal:7: loadusr called while HAL locked
l.hal:8: signal_new called while HAL locked
HAL: ERROR: add_funct_to_thread called while HAL locked
l.hal:9: addf failed
l.hal:14: parameter 'and2.0.tmax': param_set called while HAL locked
l.hal:16: start_threads called while HAL locked
l.hal:22: Locking failed: unknown lock type 'bogus' (use all, none, tune, load, config, params or run)
";
    assert_eq!(err, want_err);
    assert!(out.starts_with(
        "HAL locking status:\n  current lock value 0 (00)\n  HAL_LOCK_NONE - nothing is locked\n\
         HAL locking status:\n  current lock value 3 (03)\n\
         \x20 HAL_LOCK_LOAD    - loading of new components is locked\n\
         \x20 HAL_LOCK_CONFIG  - link and addf is locked\n\
         HAL locking status:\n  current lock value 12 (0c)\n\
         \x20 HAL_LOCK_PARAMS  - setting params is locked\n\
         \x20 HAL_LOCK_RUN     - running/stopping HAL is locked\n\
         HAL locking status:\n  current lock value 0 (00)\n  HAL_LOCK_NONE - nothing is locked\n\
         HAL memory status\n  used/total shared memory:   "
    ), "{out}");
    assert!(out.contains("\n  active/recycled components: "), "{out}");
    assert!(
        out.contains("\n  active/recycled threads:    1/0\n"),
        "{out}"
    );

    // The lock holds for every process of the instance.
    let inst = instance("lock-x");
    let realtime = env!("CARGO_BIN_EXE_realtime");
    let halcmd = env!("CARGO_BIN_EXE_halcmd");
    assert!(tool(realtime, &["start"], &inst, None).status.success());
    // Stops the host even when an assertion below fails.
    struct StopHost<'a>(&'a str, &'a str);
    impl Drop for StopHost<'_> {
        fn drop(&mut self) {
            let _ = tool(self.0, &["stop"], self.1, None);
        }
    }
    let _stop = StopHost(realtime, &inst);
    assert!(tool(halcmd, &["loadrt", "and2"], &inst, None)
        .status
        .success());
    assert!(tool(halcmd, &["lock"], &inst, None).status.success());
    let (ok, _, err) = text(&tool(halcmd, &["net", "x", "and2.0.out"], &inst, None));
    assert!(
        !ok && err.contains("signal_new called while HAL locked"),
        "{err}"
    );
    let (_, out, _) = text(&tool(halcmd, &["status", "lock"], &inst, None));
    assert!(out.contains("current lock value 255 (ff)"), "{out}");
    assert!(tool(halcmd, &["unlock", "all"], &inst, None)
        .status
        .success());
    assert!(tool(halcmd, &["net", "x", "and2.0.out"], &inst, None)
        .status
        .success());
    // halrun -U stops a running instance.
    assert!(tool(env!("CARGO_BIN_EXE_halrun"), &["-U"], &inst, None)
        .status
        .success());
    assert!(hal_core::Instance::attach(&inst).is_err());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
}

#[test]
fn halrun_takes_its_file_as_the_last_argument() {
    let s = Scratch::new("trailing");
    s.write("a.hal", "loadrt and2\nsetp nope 1\nlist pin and2.0.in0\n");
    let (ok, out, err) = halrun(&s.0, &["a.hal"], "trail");
    assert!(!ok);
    assert_eq!(
        (out.as_str(), err.as_str()),
        ("", "a.hal:2: parameter or pin 'nope': not found\n")
    );
    let (ok, out, _) = halrun(&s.0, &["-k", "a.hal"], "trail-k");
    assert!(!ok);
    assert_eq!(out, "and2.0.in0 \n");
    let (ok, _, err) = halrun(&s.0, &["a.txt"], "trail-x");
    assert!(
        !ok && err.contains("Unknown file extension for filename=<a.txt>"),
        "{err}"
    );
    let (ok, _, err) = halrun(&s.0, &["a.hal", "b.hal"], "trail-2");
    assert!(!ok && err.contains("too many arguments"), "{err}");
}

#[test]
fn haltcl_runs_a_tcl_hal_file_with_ini_arrays() {
    let s = Scratch::new("tcl");
    s.write(
        "m.ini",
        "[KINS]\nKINEMATICS = trivkins coordinates=xz\nJOINTS = 2\n[HAL]\nHALFILE = a.hal\nHALFILE = b.tcl x\n",
    );
    s.write(
        "t.tcl",
        "puts \"joints=$::KINS(JOINTS) halfiles=[llength $::HAL(HALFILE)] kins=[lindex $::KINS(KINEMATICS) 0]\"\n\
         loadrt $::KINS(KINEMATICS)\n\
         loadrt motmod num_joints=$::KINS(JOINTS)\n\
         loadrt and2 count=$::KINS(JOINTS)\n\
         setp and2.1.in0 0x1\n\
         puts [getp and2.1.in0]\n\
         puts [hal list pin and2.1.in*]\n\
         net ok and2.0.out\n\
         puts [hal gets ok]\n\
         if {[catch {setp no.such 1} msg]} { puts \"caught: $msg\" }\n\
         package require Hal\n\
         proc load_missing {} {\n    loadrt no_such_module\n}\n\
         load_missing\n\
         puts unreachable\n",
    );
    let (ok, out, err) = halrun(&s.0, &["-i", "m.ini", "t.tcl"], "tcl");
    assert!(!ok);
    assert_eq!(
        out,
        "joints=2 halfiles=2 kins=trivkins coordinates=xz\nTRUE\nand2.1.in0 and2.1.in1 \nFALSE\n\
         caught: t.tcl:10: parameter or pin 'no.such': not found\n"
    );
    assert_eq!(
        err,
        "HAL: ERROR: module 'no_such_module' not found\n\
         t.tcl:13: insmod for no_such_module failed, returned -1\n"
    );
    // A Tcl error (not a HAL one) is reported with Tcl's file and line.
    s.write("bad.tcl", "set x 1\nno_such_command\n");
    let (ok, _, err) = halrun(&s.0, &["bad.tcl"], "tcl-bad");
    assert!(!ok);
    assert!(
        err.contains("invalid command name \"no_such_command\""),
        "{err}"
    );
    assert!(err.contains("bad.tcl\" line 2)"), "{err}");

    // haltcl -i INI FILE ARGS on a running instance.
    let inst = instance("tcl-x");
    let realtime = env!("CARGO_BIN_EXE_realtime");
    assert!(tool(realtime, &["start"], &inst, None).status.success());
    s.write(
        "args.tcl",
        "loadrt and2 count=[llength $::argv]\nputs \"$::argv [hal list pin and2.*.out]\"\n",
    );
    let (ok, out, err) = text(&tool(
        env!("CARGO_BIN_EXE_haltcl"),
        &["-i", "m.ini", "args.tcl", "p", "q"],
        &inst,
        Some(&s.0),
    ));
    assert!(ok, "{err}");
    assert_eq!(out, "p q and2.0.out and2.1.out \n");
    assert!(tool(realtime, &["stop"], &inst, None).status.success());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
}

#[test]
fn includes_expand_in_place() {
    let s = Scratch::new("include");
    s.write(
        "m.ini",
        "[EMC]\nMACHINE = inc\n#INCLUDE hal.inc\n[P]\n#INCLUDE sub/vals.inc\nAFTER = 3\n",
    );
    s.write(
        "hal.inc",
        "[HAL]\nTWOPASS = on\nHALFILE = f.hal\nHALFILE = g.hal\n",
    );
    s.write("sub/vals.inc", "COUNT = 2\nLAST = 1\n");
    s.write("f.hal", "loadrt and2 count=[P]COUNT\n");
    s.write("g.hal", "list pin and2.[P](LAST).out\n");
    let (ok, out, err) = halrun(&s.0, &["m.ini"], "include");
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "twopass:invoked with <> options\ntwopass:found ./f.hal\ntwopass:found ./g.hal\n\
         and2.1.out \n"
    );
    s.write("loop.ini", "[A]\n#INCLUDE loop.inc\n");
    s.write("loop.inc", "X = 1\n#INCLUDE loop.inc\n");
    let (ok, _, err) = halrun(&s.0, &["loop.ini"], "include-loop");
    assert!(!ok);
    assert!(err.contains("loop.inc:2: recursive #INCLUDE of"), "{err}");
}

#[test]
fn lib_names_come_from_the_library_and_bare_names_from_the_ini_dir_first() {
    let s = Scratch::new("lib");
    s.write(
        "m.ini",
        "[EMCMOT]\nEMCMOT = motmod\nBASE_PERIOD = 0\nSERVO_PERIOD = 1000000\n\
         [KINS]\nKINEMATICS = trivkins\nJOINTS = 3\n\
         [HAL]\nTWOPASS = on\nHALFILE = LIB:core_sim.hal\nHALFILE = simulated_home.hal\n\
         HALFILE = LIB:check_xyz_constraints.hal\nHALFILE = show.hal\n",
    );
    // A file beside the INI file wins over the library's of that name.
    s.write("simulated_home.hal", "loadrt and2 names=beside\n");
    s.write("show.hal", "list pin beside.out\nshow sig Xpos\n");
    // halrun runs only the HAL files, as LinuxCNC's: task's pins are not
    // there, so core_sim.hal's iocontrol line fails; -k goes on.
    let (ok, out, err) = halrun(&s.0, &["-k", "m.ini"], "lib");
    assert!(!ok);
    assert!(
        err.contains("core_sim.hal:37: Pin 'iocontrol.0.user-enable-out' does not exist"),
        "{err}"
    );
    let lib = std::fs::canonicalize(root().join("lib/hallib")).unwrap();
    assert!(
        out.starts_with(&format!(
            "twopass:invoked with <> options\ntwopass:found {}/core_sim.hal\n\
             twopass:found ./simulated_home.hal\n",
            lib.display()
        )),
        "{out}"
    );
    assert!(out.contains("\nbeside.out \n"), "{out}");
    assert!(out.contains("<== joint.0.motor-pos-cmd"), "{out}");
    assert!(
        out.contains("==> wcomp_xvel.in") || out.contains("==> ddt_x.in"),
        "{out}"
    );
    assert!(
        !out.contains("comp_x"),
        "the library's simulated_home.hal did not run"
    );
}

#[test]
fn twopass_joins_loadrt_across_files_and_keeps_the_order_of_the_rest() {
    let s = Scratch::new("twopass");
    s.write(
        "m.ini",
        "[HAL]\nTWOPASS = on\nHALFILE = a.hal\nHALFILE = b.tcl\nHALFILE = c.hal\n\
         HALFILE = d.hal\n",
    );
    s.write(
        "d.hal",
        "list pin and2.*.out\nlist pin *.Pgain\ngetp p2.Pgain\nsave thread\nlist pin or2.0.out\n",
    );
    // a.hal uses and2.2, which only exists once b.tcl's and2 is counted in.
    s.write(
        "a.hal",
        "loadrt and2 count=1\nloadrt pid names=p1\nnet late and2.2.out => p1.enable\naddf and2.2 t\n",
    );
    s.write(
        "b.tcl",
        "loadrt and2 count=2\nloadrt pid names=p2\nsetp p2.Pgain 3\naddf and2.0 t\naddf p2.do-pid-calcs t\n",
    );
    // c.hal runs whole in pass 0 (#NOTWOPASS), so its thread is there
    // for the addf lines of pass 1.
    s.write(
        "c.hal",
        "# notwopass\nloadrt threads name1=t period1=1000000\nloadrt or2\naddf or2.0 t\n",
    );
    let (ok, out, err) = halrun(&s.0, &["m.ini"], "twopass");
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "twopass:invoked with <> options\ntwopass:found ./a.hal\ntwopass:found ./b.tcl\n\
         twopass:found ./c.hal\ntwopass:Sourcing ./c.hal WITHOUT twopass processing\n\
         twopass:found ./d.hal\n\
         and2.0.out and2.1.out and2.2.out \np1.Pgain p2.Pgain \n3\n\
         # realtime thread/function links\naddf or2.0 t\naddf and2.2 t\naddf and2.0 t\naddf p2.do-pid-calcs t\n\
         or2.0.out \n"
    );
    // Without TWOPASS, LinuxCNC's halrun runs nothing of an INI file.
    s.write("n.ini", "[HAL]\nHALFILE = a.hal\n");
    let (ok, out, _) = halrun(&s.0, &["n.ini"], "onepass");
    assert!(!ok);
    assert_eq!(
        out,
        "halrun: An INI file may only be used if it specifies [HAL]TWOPASS\n"
    );
    // Forms may not mix.
    s.write("x.ini", "[HAL]\nTWOPASS = on\nHALFILE = x.hal\n");
    s.write("x.hal", "loadrt and2 count=1\nloadrt and2 names=q\n");
    let (ok, _, err) = halrun(&s.0, &["x.ini"], "twopass-mix");
    assert!(!ok);
    assert!(
        err.contains(
            "x.hal:2: twopass: loadrt and2: cannot mix count=, num_chan= and names= forms"
        ),
        "{err}"
    );
}

#[test]
fn twopass_pass_0_hides_bare_commands_but_runs_hal_ones() {
    // As LinuxCNC's sim_lib.tcl does: `hal save` in pass 0 writes its
    // file (and the script reads it back); bare commands do nothing.
    let s = Scratch::new("twopass-hal");
    s.write("m.ini", "[HAL]\nTWOPASS = on\nHALFILE = s.tcl\n");
    s.write(
        "s.tcl",
        "set pass [::tp::passnumber]\nloadrt and2 names=g1\n\
         set f [open saved_$pass.hal w]\nputs $f [hal save comp]\nclose $f\n\
         set f [open saved_$pass.hal r]\nclose $f\n\
         net n1 g1.in0\nsetp g1.in1 1\nputs \"pass $pass: [hal list sig] [getp g1.in1]\"\n",
    );
    let (ok, out, err) = halrun(&s.0, &["m.ini"], "twopass-hal");
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "twopass:invoked with <> options\ntwopass:found ./s.tcl\npass 0:  \npass 1: n1  TRUE\n"
    );
    let saved = |n: u8| std::fs::read_to_string(s.0.join(format!("saved_{n}.hal"))).unwrap();
    assert!(!saved(0).contains("and2"), "{}", saved(0));
    assert!(saved(1).contains("loadrt and2 names=g1"), "{}", saved(1));
}

#[test]
fn hookup_moveoff_waits_for_pass_1_and_names_an_unconnected_joint() {
    let s = Scratch::new("moveoff-hookup");
    s.write(
        "m.ini",
        "[KINS]\nJOINTS = 1\n[JOINT_0]\nTYPE = LINEAR\n\
         [HAL]\nTWOPASS = on\nHALFILE = a.hal\nHALFILE = LIB:hookup_moveoff.tcl\n",
    );
    s.write(
        "a.hal",
        "loadrt trivkins\nloadrt motmod servo_period_nsec=1000000 num_joints=1\n\
         addf motion-command-handler servo-thread\naddf motion-controller servo-thread\n",
    );
    let (ok, _, err) = halrun(&s.0, &["m.ini"], "moveoff-hookup");
    assert!(!ok);
    assert!(
        err.contains(
            "hookup_moveoff.tcl: joint.0.motor-pos-cmd is on no signal: \
             a HAL file before hookup_moveoff.tcl must connect it"
        ),
        "{err}"
    );
    // Connected, the joint is hooked up (in pass 1: nothing in pass 0).
    s.write(
        "a.hal",
        "loadrt trivkins\nloadrt motmod servo_period_nsec=1000000 num_joints=1\n\
         addf motion-command-handler servo-thread\naddf motion-controller servo-thread\n\
         net J0:loop joint.0.motor-pos-cmd => joint.0.motor-pos-fb\n",
    );
    s.write("b.hal", "show sig hu:shortcircuit-0\n");
    s.write(
        "m.ini",
        "[KINS]\nJOINTS = 1\n[JOINT_0]\nTYPE = LINEAR\n\
         [HAL]\nTWOPASS = on\nHALFILE = a.hal\nHALFILE = LIB:hookup_moveoff.tcl\nHALFILE = b.hal\n",
    );
    let (ok, out, err) = halrun(&s.0, &["m.ini"], "moveoff-hookup-2");
    assert!(ok, "{err}");
    assert!(
        out.contains("<== mv.pos-plusoffset-0") && out.contains("==> mv.fb-0"),
        "{out}"
    );
}
