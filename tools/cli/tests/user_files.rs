//! Every reader of a file a user names refuses what is not a regular
//! file, at once and with a message naming the file and why: a character
//! device that never ends (`/dev/zero`), a FIFO nobody writes, a
//! directory. Each odd file is reached through a name with the extension
//! the reader expects (a link to /dev/zero, a FIFO called `x.hal`), as a
//! careless configuration would name it. Streams that are not files
//! (standard input) are read a bounded line at a time.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A refusal is expected within this; the readers before the fix never
/// ended (or filled memory) here.
const QUICK: Duration = Duration::from_secs(20);

/// A scratch directory with, for each extension, a link to /dev/zero, a
/// FIFO and a directory under names with that extension.
struct Odd {
    dir: PathBuf,
}

/// (name of the case, what the message must say)
const KINDS: [(&str, &str); 3] = [
    ("zero", "is a character device, not a regular file"),
    ("fifo", "is a FIFO, not a regular file"),
    ("dir", "is a directory, not a regular file"),
];

impl Odd {
    fn new(tag: &str) -> Odd {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
            .join(format!("user-files-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Odd { dir }
    }

    /// The odd file `kind` (`zero`, `fifo`, `dir`) named `kind.ext`.
    fn path(&self, kind: &str, ext: &str) -> PathBuf {
        let p = self.dir.join(format!("{kind}.{ext}"));
        if std::fs::symlink_metadata(&p).is_ok() {
            return p;
        }
        match kind {
            "zero" => std::os::unix::fs::symlink("/dev/zero", &p).unwrap(),
            "fifo" => {
                nix::unistd::mkfifo(&p, nix::sys::stat::Mode::from_bits_truncate(0o600)).unwrap()
            }
            _ => std::fs::create_dir(&p).unwrap(),
        }
        p
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for Odd {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// Runs `cmd` (stdin empty unless set) on an instance of its own; fails
/// the test if it runs past [`QUICK`] (then killed). Returns its exit
/// status and stderr.
fn run_quick(mut cmd: Command, what: &str) -> (Option<i32>, String) {
    cmd.env("HAL_INSTANCE", common::instance("userfiles"))
        .env("HAL_NO_REALTIME", "1")
        .env("HAL_SHM_SIZE", (8u64 << 20).to_string())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    let mut child = cmd.spawn().expect("starts");
    let mut err = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = err.read_to_string(&mut s);
        s
    });
    let began = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if began.elapsed() > QUICK {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: still running after {QUICK:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    (status.code(), reader.join().unwrap())
}

/// Checks that `cmd` failed naming `path` and `why`.
fn refuses(cmd: Command, what: &str, path: &Path, why: &str) {
    let (code, err) = run_quick(cmd, what);
    assert_ne!(code, Some(0), "{what}: succeeded\n{err}");
    assert!(
        err.contains(&path.display().to_string()) && err.contains(why),
        "{what}: the message should name {} and say {why:?}:\n{err}",
        path.display()
    );
    assert!(!err.contains("panicked"), "{what}: {err}");
}

fn bin(name: &str) -> Command {
    let dir = Path::new(env!("CARGO_BIN_EXE_halcmd")).parent().unwrap();
    Command::new(dir.join(name))
}

#[test]
fn hal_and_tcl_files_that_are_not_regular_are_refused() {
    let odd = Odd::new("hal");
    for (kind, why) in KINDS {
        let hal = odd.path(kind, "hal");
        let mut c = bin("halrun");
        c.args(["-f"]).arg(&hal);
        refuses(c, &format!("halrun -f {kind}.hal"), &hal, why);

        let tcl = odd.path(kind, "tcl");
        let mut c = bin("halrun");
        c.arg(&tcl);
        refuses(c, &format!("halrun {kind}.tcl"), &tcl, why);

        let src = odd.write(
            &format!("source-{kind}.hal"),
            &format!("source {}\n", hal.display()),
        );
        let mut c = bin("halrun");
        c.arg("-f").arg(&src);
        refuses(c, &format!("source {kind}.hal"), &hal, why);
    }
}

/// A machine whose INI file says `extra` (a `[HAL]`-less config of its
/// own otherwise), with a HAL file that loads nothing.
fn machine_ini(odd: &Odd, name: &str, extra: &str) -> PathBuf {
    odd.write(
        "empty.hal",
        "loadrt threads name1=servo-thread period1=1000000\n",
    );
    odd.write(
        name,
        &format!("[EMC]\nMACHINE = odd\n{extra}\n[HAL]\nHALFILE = empty.hal\n"),
    )
}

#[test]
fn machine_files_that_are_not_regular_are_refused() {
    let odd = Odd::new("ini");
    for (kind, why) in KINDS {
        let ini = odd.path(kind, "ini");
        let mut c = bin("linuxcnc");
        c.arg(&ini);
        refuses(c, &format!("linuxcnc {kind}.ini"), &ini, why);

        let inc = odd.path(kind, "inc");
        let m = machine_ini(
            &odd,
            &format!("inc-{kind}.ini"),
            &format!("#INCLUDE {}", inc.display()),
        );
        let mut c = bin("linuxcnc");
        c.arg(&m);
        refuses(c, &format!("#INCLUDE {kind}.inc"), &inc, why);

        let tbl = odd.path(kind, "tbl");
        let m = machine_ini(
            &odd,
            &format!("tbl-{kind}.ini"),
            &format!("[EMCIO]\nTOOL_TABLE = {}", tbl.display()),
        );
        let mut c = bin("linuxcnc");
        c.arg(&m);
        refuses(c, &format!("TOOL_TABLE = {kind}.tbl"), &tbl, why);

        for ext in ["hal", "tcl"] {
            let f = odd.path(kind, ext);
            let m = odd.write(
                &format!("halfile-{kind}-{ext}.ini"),
                &format!("[EMC]\nMACHINE = odd\n[HAL]\nHALFILE = {}\n", f.display()),
            );
            let mut c = bin("linuxcnc");
            c.arg(&m);
            refuses(c, &format!("HALFILE = {kind}.{ext}"), &f, why);
        }
    }
}

#[test]
fn programs_samples_and_drive_files_that_are_not_regular_are_refused() {
    let odd = Odd::new("prog");
    for (kind, why) in KINDS {
        let ngc = odd.path(kind, "ngc");
        let mut c = bin("gcode-run");
        c.arg("--check").arg(&ngc);
        refuses(c, &format!("gcode-run --check {kind}.ngc"), &ngc, why);

        let samples = odd.path(kind, "samples");
        let mut c = bin("motion-plot");
        c.arg(&samples);
        refuses(c, &format!("motion-plot {kind}.samples"), &samples, why);

        let sdo = odd.path(kind, "sdo");
        let hal = odd.write(
            &format!("canservo-{kind}.hal"),
            &format!(
                "loadrt canservo backend=sim nodes=1 drive_file={}\n",
                sdo.display()
            ),
        );
        let mut c = bin("halrun");
        c.arg("-f").arg(&hal);
        refuses(c, &format!("canservo drive_file={kind}.sdo"), &sdo, why);
    }
}

#[test]
fn a_file_past_its_limit_is_refused_with_the_limit_stated() {
    let odd = Odd::new("big");
    // Sparse: 4 MiB and one byte, one past an INI file's limit.
    let ini = odd.dir.join("big.ini");
    std::fs::File::create(&ini)
        .unwrap()
        .set_len((4 << 20) + 1)
        .unwrap();
    let mut c = bin("linuxcnc");
    c.arg(&ini);
    refuses(
        c,
        "linuxcnc big.ini",
        &ini,
        "larger than the limit of 4 MiB (4194304 bytes)",
    );
}

#[test]
fn standard_input_without_newlines_is_read_a_bounded_line_at_a_time() {
    let inst = common::instance("userfiles-stdin");
    let realtime = env!("CARGO_BIN_EXE_realtime");
    assert!(common::run(realtime, &["start"], &inst).status.success());
    common::halcmd(&["loadrt", "streamer", "depth=64", "cfg=f"], &inst);
    let zero = || Stdio::from(std::fs::File::open("/dev/zero").unwrap());
    let mut cases = Vec::new();
    for (name, args, why) in [
        (
            "halcmd",
            &["-f"][..],
            "a line longer than the limit of 1 MiB",
        ),
        (
            "halstreamer",
            &[][..],
            "a line longer than the limit of 64 KiB",
        ),
    ] {
        let mut c = bin(name);
        c.args(args).stdin(zero()).env("HAL_INSTANCE", &inst);
        let began = Instant::now();
        let out = c
            .stderr(Stdio::piped())
            .stdout(Stdio::null())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        cases.push((name, began.elapsed(), out.status.code(), err, why));
    }
    assert!(common::run(realtime, &["stop"], &inst).status.success());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
    for (name, took, code, err, why) in cases {
        assert!(took < QUICK, "{name}: took {took:?}");
        assert_ne!(code, Some(0), "{name}: {err}");
        assert!(err.contains(why), "{name}: {err}");
    }
}
