//! A configuration whose `[DISPLAY]DISPLAY` is a program of its own (as
//! LinuxCNC's regression tests have): the launcher runs it as `PROGRAM
//! -ini INIFILE ARGS` in the configuration's directory while task runs,
//! then stops the machine and exits with the program's status.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use std::os::unix::fs::PermissionsExt;

use machine::{mill_copy, Machine, Scratch};

/// The simulated mill with `script` as its display program `./ui.sh`
/// (words after it: `args`).
fn mill_with_display(s: &Scratch, script: &str, args: &str) -> std::path::PathBuf {
    let ini = mill_copy(s);
    let text = std::fs::read_to_string(&ini).unwrap();
    assert!(text.contains("\nDISPLAY = axis\n"));
    let text = text.replace(
        "\nDISPLAY = axis\n",
        &format!("\nDISPLAY = ./ui.sh {args}\n"),
    );
    std::fs::write(&ini, text).unwrap();
    let ui = s.write("ui.sh", script);
    std::fs::set_permissions(&ui, std::fs::Permissions::from_mode(0o755)).unwrap();
    ini
}

#[test]
fn the_display_program_drives_task_and_its_status_is_linuxcncs() {
    let s = Scratch::new("display-status");
    let task_cmd = env!("CARGO_BIN_EXE_task-cmd");
    // The launcher's own directory is on the display's PATH.
    let bin_dir = std::path::Path::new(env!("CARGO_BIN_EXE_linuxcnc"))
        .parent()
        .unwrap()
        .display()
        .to_string();
    let script = format!(
        "#!/bin/sh\n\
         [ \"$1\" = -ini ] && [ \"$2\" = \"$INI_FILE_NAME\" ] && [ \"$3\" = --flag ] || exit 9\n\
         [ \"$(pwd)\" = \"$CONFIG_DIR\" ] || exit 10\n\
         [ \"$(command -v halcmd)\" = \"{bin_dir}/halcmd\" ] || exit 15\n\
         {task_cmd} estop-reset && {task_cmd} machine-on || exit 11\n\
         {task_cmd} stat > stat.txt || exit 12\n\
         {task_cmd} message display from the ui || exit 13\n\
         {task_cmd} messages 0 > messages.txt || exit 14\n\
         exit 7\n"
    );
    let ini = mill_with_display(&s, &script, "--flag");
    let m = Machine::spawn(&ini, "display-status", &[]);
    let (status, err) = m.wait_exit();
    assert_eq!(status.code(), Some(7), "{err}");
    assert!(err.contains("the display program exited"), "{err}");
    assert!(
        err.contains("POSTGUI_HALFILE is left to the display program"),
        "{err}"
    );
    assert!(!err.contains("GUI './ui.sh"), "{err}");
    let stat = std::fs::read_to_string(s.0.join("stat.txt")).unwrap();
    for line in ["task_state=i:4", "estop=i:0", "enabled=i:1", "joints=i:3"] {
        assert!(stat.lines().any(|l| l == line), "{line} in:\n{stat}");
    }
    assert!(stat.contains("\nposition=F:"), "{stat}");
    assert!(stat.contains("\njoint.2.homed=i:"), "{stat}");
    let messages = std::fs::read_to_string(s.0.join("messages.txt")).unwrap();
    assert!(messages.contains(" 13 from the ui\n"), "{messages}");
}

#[test]
fn a_display_ended_by_a_signal_gives_128_plus_it() {
    let s = Scratch::new("display-signal");
    let ini = mill_with_display(&s, "#!/bin/sh\nkill -TERM $$\nsleep 5\n", "");
    let (status, err) = Machine::spawn(&ini, "display-signal", &[]).wait_exit();
    assert_eq!(status.code(), Some(128 + 15), "{err}");
}

#[test]
fn sigterm_while_the_display_runs_stops_both_with_status_0() {
    let s = Scratch::new("display-sigterm");
    let ini = mill_with_display(&s, "#!/bin/sh\nexec sleep 60\n", "");
    let m = Machine::start(&ini, "display-sigterm");
    let err = m.stderr_with("starting the display program");
    assert!(err.contains("starting the display program"), "{err}");
    let (status, err) = m.stop_with(nix::sys::signal::Signal::SIGTERM);
    assert_eq!(status.code(), Some(0), "{err}");
}
