//! inivar as scripts run it (LinuxCNC's regression tests read their
//! machine's limits with it): the value on standard output, LinuxCNC's
//! messages and exit statuses otherwise.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::process::{Command, Output};

fn inivar(dir: &std::path::Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_inivar"))
        .args(args)
        .current_dir(dir)
        .env("HOME", "/home/someone")
        .output()
        .unwrap()
}

/// A directory of its own for one test, removed afterwards.
struct Scratch(std::path::PathBuf);

impl Scratch {
    fn new(tag: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }

    fn path(&self) -> &std::path::Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn text(b: &[u8]) -> &str {
    std::str::from_utf8(b).unwrap()
}

#[test]
fn prints_values_as_linuxcnc_scripts_read_them() {
    let dir = Scratch::new("inivar");
    std::fs::write(
        dir.path().join("machine.ini"),
        "[EMCMOT]\nSERVO_PERIOD = 1000000\n[HAL]\nHALFILE = a.hal\nHALFILE = b.hal\n\
         [DISPLAY]\nPROGRAM_PREFIX = ~/nc_files\n",
    )
    .unwrap();
    let ok = |args: &[&str], want: &str| {
        let o = inivar(dir.path(), args);
        assert_eq!(
            (o.status.code(), text(&o.stdout)),
            (Some(0), want),
            "{args:?}"
        );
    };
    ok(
        &[
            "-var",
            "SERVO_PERIOD",
            "-sec",
            "EMCMOT",
            "-ini",
            "machine.ini",
        ],
        "1000000\n",
    );
    ok(
        &[
            "-var",
            "HALFILE",
            "-sec",
            "HAL",
            "-num",
            "2",
            "-ini",
            "machine.ini",
        ],
        "b.hal\n",
    );
    ok(&["-var", "HALFILE", "-ini", "machine.ini"], "a.hal\n");
    ok(
        &[
            "-var",
            "PROGRAM_PREFIX",
            "-tildeexpand",
            "-ini",
            "machine.ini",
        ],
        "/home/someone/nc_files\n",
    );

    // A value that is not there: nothing on standard output, status 1.
    let o = inivar(
        dir.path(),
        &[
            "-var",
            "MAX_VELOCITY",
            "-sec",
            "AXIS_0",
            "-ini",
            "machine.ini",
        ],
    );
    assert_eq!((o.status.code(), text(&o.stdout)), (Some(1), ""));
    assert_eq!(
        text(&o.stderr),
        "Can not find -sec AXIS_0 -var MAX_VELOCITY -num 1 \n"
    );

    // The default file is emc.ini in the current directory.
    let o = inivar(dir.path(), &["-var", "X"]);
    assert_eq!(o.status.code(), Some(255));
    assert_eq!(text(&o.stderr), "inivar: can't open emc.ini\n");
}
