//! The harness of the LinuxCNC tests: one HAL text run by LinuxCNC's own
//! `halrun` (Debian 12's linuxcnc-uspace, unpacked by
//! `scripts/linuxcnc-peer install`) with our `<module>.so` files laid
//! over its module directory, and by our host, both in script mode
//! (`halcmd -s`) and keeping going after a failed command (`-k`); then
//! the parts of the outputs the tests compare.
//!
//! The tests need the peer and root (its private mount namespace); the
//! build script sets cfg `linuxcnc_peer` when both are there, and the
//! tests are ignored otherwise.

use std::io::Read;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How long one LinuxCNC session may take.
const SESSION_LIMIT: Duration = Duration::from_secs(180);

/// What one session printed.
#[derive(Debug)]
pub struct Run {
    /// Whether every command succeeded.
    pub ok: bool,
    /// halcmd's output.
    pub stdout: String,
    /// Errors: halcmd's, and the modules' messages.
    pub stderr: String,
}

/// Our modules, staged under their `loadrt` names for LinuxCNC.
pub struct Modules {
    dir: tempfile::TempDir,
}

impl Modules {
    /// Stages each `(module, crate_lib)`: the `lib<crate_lib>.so` cargo
    /// built beside this test binary, as `<module>.so`.
    pub fn stage(list: &[(&str, &str)]) -> Modules {
        let dir = tempfile::tempdir().expect("temporary directory");
        let built = built_dir();
        for (module, lib) in list {
            let from = built.join(format!("lib{lib}.so"));
            std::fs::copy(&from, dir.path().join(format!("{module}.so")))
                .unwrap_or_else(|e| panic!("{}: {e} (is {lib} a dev-dependency?)", from.display()));
        }
        Modules { dir }
    }

    /// Where the staged modules are.
    pub fn path(&self) -> &Path {
        self.dir.path()
    }
}

/// Where cargo put the dependencies' libraries: this test binary's
/// directory (`target/<profile>/deps`).
fn built_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    exe.parent().expect("test binary directory").to_path_buf()
}

/// The peer script of this checkout.
fn peer_script() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/linuxcnc-peer")
}

/// Runs `text` as a HAL file in LinuxCNC's `halrun -s -k`, with
/// `modules` laid over its module directory.
pub fn linuxcnc(modules: &Modules, text: &str) -> Run {
    let file = tempfile::Builder::new()
        .suffix(".hal")
        .tempfile()
        .expect("HAL file");
    std::fs::write(file.path(), text).expect("write HAL file");
    let mut child = Command::new(peer_script())
        .arg("run")
        .arg("-m")
        .arg(modules.path())
        .args(["halrun", "-s", "-k", "-f"])
        .arg(file.path())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .process_group(0)
        .spawn()
        .expect("scripts/linuxcnc-peer runs");
    // Both pipes are read by threads, so that a session that hangs is
    // caught by the limit below instead of holding this read forever.
    let stdout = read_in_thread(child.stdout.take());
    let stderr = read_in_thread(child.stderr.take());
    let end = Instant::now() + SESSION_LIMIT;
    let status = loop {
        if let Some(st) = child.try_wait().expect("wait for halrun") {
            break st;
        }
        if Instant::now() > end {
            // The peer script leads its own process group: killing the
            // group kills the PID namespace's first process, and with it
            // everything LinuxCNC started there, so both pipes close.
            let group = nix::unistd::Pid::from_raw(child.id() as i32);
            let _ = nix::sys::signal::killpg(group, nix::sys::signal::Signal::SIGKILL);
            let _ = child.wait();
            let stdout = stdout.join().expect("stdout reader");
            let stderr = stderr.join().expect("stderr reader");
            panic!(
                "LinuxCNC's halrun did not finish within {SESSION_LIMIT:?}:\n{stdout}\n{stderr}"
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Run {
        ok: status.success(),
        stdout: stdout.join().expect("stdout reader"),
        stderr: stderr.join().expect("stderr reader"),
    }
}

/// Reads a child's pipe to its end on a thread of its own.
fn read_in_thread<R: Read + Send + 'static>(pipe: Option<R>) -> std::thread::JoinHandle<String> {
    std::thread::spawn(move || {
        let mut s = String::new();
        if let Some(mut p) = pipe {
            let _ = p.read_to_string(&mut s);
        }
        s
    })
}

/// Runs `text` in our host (served in this process, instance named
/// after `tag`), as `halrun -s -k` would.
pub fn ours(tag: &str, text: &str) -> Run {
    let host = hal_host::testing::InProcessHost::start(tag);
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let opts = hal_lang::Options {
        keep_going: true,
        script: true,
        ..Default::default()
    };
    let ok = hal_lang::Session::new(host.instance(), opts, &mut out, &mut err)
        .run_text(Some("test.hal"), text);
    Run {
        ok,
        stdout: String::from_utf8_lossy(&out).into_owned(),
        stderr: String::from_utf8_lossy(&err).into_owned(),
    }
}

/// The `show pin`, `show param` and `show funct` rows of component
/// `owner` in script-mode output, fields joined by one space. Two things
/// differ by LinuxCNC version rather than by driver and are evened out:
/// LinuxCNC's function rows carry the code and argument addresses (in
/// our host code lives in the host, so it has none), and LinuxCNC 2.9
/// prints u32 values in decimal where 2.10 and ours print hex.
pub fn listing(stdout: &str, owner: &str) -> Vec<String> {
    stdout
        .lines()
        .map(|l| l.split_whitespace().map(str::to_string).collect::<Vec<_>>())
        .filter(|f| f.first().map(String::as_str) == Some(owner) && f.len() >= 4)
        .map(|mut f| {
            let is_funct_with_addresses = f.len() == 6 && matches!(f[3].as_str(), "YES" | "NO");
            if is_funct_with_addresses {
                f.drain(1..3);
            }
            if f.len() >= 5 && f[1] == "u32" {
                if let Some(v) = f[3]
                    .strip_prefix("0x")
                    .and_then(|h| u32::from_str_radix(h, 16).ok())
                {
                    f[3] = v.to_string();
                }
            }
            f.join(" ")
        })
        .collect()
}

/// What each `getp` printed: the lines that are one word.
pub fn getp_values(stdout: &str) -> Vec<String> {
    stdout
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.contains(char::is_whitespace))
        .map(str::to_string)
        .collect()
}

/// The bytes of HAL shared memory in use at each `status`.
pub fn shm_used(stdout: &str) -> Vec<u64> {
    stdout
        .lines()
        .filter_map(|l| l.trim().strip_prefix("used/total shared memory:"))
        .filter_map(|v| v.trim().split('/').next()?.parse().ok())
        .collect()
}

/// What LinuxCNC's halcmd itself keeps in HAL shared memory for each
/// successful `loadrt`, and never frees: a copy of the argument words
/// (each followed by a space, plus the NUL), for `save`. On LinuxCNC 2.9
/// `hal_malloc` hands it out in 16-byte steps. `args` is the argument
/// text as written in the HAL file, words separated by single spaces.
pub fn halcmd_args_record(args: &str) -> u64 {
    (args.len() + 2).next_multiple_of(16) as u64
}

/// One driver's check in LinuxCNC beside our host.
#[derive(Default)]
pub struct Case<'a> {
    /// The module's `loadrt` name.
    pub module: &'a str,
    /// The library cargo builds it as (`lcnc_<module>`).
    pub lib: &'a str,
    /// The arguments of the `loadrt` that is listed, run and cycled.
    pub args: &'a str,
    /// The components whose pins, parameters and functions are compared.
    pub owners: &'a [&'a str],
    /// HAL commands that wire and run the module's functions in thread
    /// `t` (1 ms, created before the module) and `getp` what the test
    /// checks; they end with the threads stopped.
    pub run: &'a str,
    /// Arguments of loads that must be refused, with the same message in
    /// both hosts and nothing left behind.
    pub refused: &'a [&'a str],
    /// Modules the module needs loaded first, `(module, lib)` as
    /// [`Modules::stage`] takes them (hostmot2 for hm2_pci); each is
    /// loaded once, before anything else, with no arguments.
    pub needs: &'a [(&'a str, &'a str)],
}

/// What a [`Case`] leaves for the driver's own judgement: the values the
/// `run` commands' `getp`s printed in each host.
#[derive(Debug)]
pub struct Outcome {
    /// In LinuxCNC.
    pub theirs: Vec<String>,
    /// In our host.
    pub ours: Vec<String>,
}

impl Outcome {
    /// Checks, in each host, that the first value read is a position
    /// within 0.01 of `want` and the second is `then` (`what` names it in
    /// the failure).
    pub fn assert_axis_at(&self, want: f64, then: &str, what: &str) {
        for (host, values) in [("LinuxCNC", &self.theirs), ("ours", &self.ours)] {
            let pos: f64 = values
                .first()
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| panic!("{host}: no position in {values:?}"));
            assert!(
                (pos - want).abs() < 0.01,
                "{host}: the axis stands at {pos}, not {want}"
            );
            assert_eq!(
                values.get(1).map(String::as_str),
                Some(then),
                "{host}: {what}"
            );
        }
    }
}

/// Loads and unloads after the first round in [`check`].
pub const CYCLES: u64 = 100;

/// The marks `gets mark` prints between the parts of a session.
const MARKS: [&str; 2] = ["31415", "27182"];

/// The session both hosts run for `case`.
fn session(case: &Case<'_>) -> String {
    let (m, args) = (case.module, case.args);
    let needs: String = case
        .needs
        .iter()
        .map(|(n, _)| format!("loadrt {n}\n"))
        .collect();
    let mut s = format!(
        "{needs}loadrt threads name1=t period1=1000000\nnewsig mark s32\nloadrt {m} {args}\n\
         show pin\nshow param\nshow funct\nsets mark {}\ngets mark\n{}\nunloadrt {m}\n",
        MARKS[0], case.run
    );
    for bad in case.refused {
        s.push_str(&format!("loadrt {m} {bad}\n"));
    }
    s.push_str(&format!(
        "show pin\nshow param\nshow funct\nsets mark {}\ngets mark\n",
        MARKS[1]
    ));
    s
}

/// LinuxCNC only: a first load and unload, `status`, [`CYCLES`] more,
/// `status`.
fn cycles(case: &Case<'_>) -> String {
    let once = format!(
        "loadrt {} {}\nunloadrt {}\n",
        case.module, case.args, case.module
    );
    format!("{once}status\n{}status\n", once.repeat(CYCLES as usize))
}

/// Splits script-mode output at the marks.
fn parts(stdout: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    for l in stdout.lines() {
        if MARKS.contains(&l.trim()) {
            out.push(String::new());
        } else if let Some(last) = out.last_mut() {
            last.push_str(l);
            last.push('\n');
        }
    }
    out
}

/// Runs `case` in one LinuxCNC session and one of our host, and checks
/// what does not depend on the driver: the same listing, the same
/// refusals with nothing left of them, and no HAL shared memory taken by
/// [`CYCLES`] loads and unloads beyond halcmd's own record of each
/// `loadrt` line. Returns the `run` part's values.
pub fn check(case: &Case<'_>) -> Outcome {
    let mut staged = vec![(case.module, case.lib)];
    staged.extend_from_slice(case.needs);
    let modules = Modules::stage(&staged);
    let theirs = linuxcnc(&modules, &(session(case) + &cycles(case)));
    let mine = ours(&format!("lcnc-{}", case.module), &session(case));
    let (t, m) = (parts(&theirs.stdout), parts(&mine.stdout));
    assert!(
        t.len() == 3 && m.len() == 3,
        "marks missing:\nLinuxCNC:\n{}\n{}\nours:\n{}\n{}",
        theirs.stdout,
        theirs.stderr,
        mine.stdout,
        mine.stderr
    );

    for owner in case.owners {
        let (lt, lm) = (listing(&t[0], owner), listing(&m[0], owner));
        assert!(
            !lm.is_empty(),
            "our host lists nothing of {owner}:\n{}",
            mine.stderr
        );
        assert_eq!(
            lt, lm,
            "LinuxCNC lists {owner} otherwise than our host:\n{}",
            theirs.stderr
        );
    }

    for owner in case.owners {
        assert!(
            listing(&t[1], owner).is_empty(),
            "LinuxCNC kept {owner}:\n{}",
            t[1]
        );
        assert!(
            listing(&m[1], owner).is_empty(),
            "our host kept {owner}:\n{}",
            m[1]
        );
    }
    let refusals: Vec<&str> = mine
        .stderr
        .lines()
        .filter_map(|l| l.find(&format!("{}: ", case.module)).map(|i| &l[i..]))
        .collect();
    assert_eq!(
        refusals.len(),
        case.refused.len(),
        "our host said: {}",
        mine.stderr
    );
    for r in refusals {
        assert!(
            theirs.stderr.contains(r),
            "LinuxCNC did not say {r:?}:\n{}",
            theirs.stderr
        );
    }

    let used = shm_used(&t[2]);
    assert_eq!(used.len(), 2, "{}", t[2]);
    assert_eq!(
        used[1] - used[0],
        CYCLES * halcmd_args_record(case.args),
        "HAL shared memory grew by more than halcmd's records of the loadrt lines"
    );
    Outcome {
        theirs: getp_values(&t[1]),
        ours: getp_values(&m[1]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn listings_drop_linuxcncs_addresses_and_other_owners() {
        let lcnc = "hal_parport bit   IN FALSE parport.0.pin-01-out\n\
                    t s32 OUT 0 t.time\n\n\
                    hal_parport 7efe4f242610 55b745ed00f0 NO   0 parport.0.read\n";
        let ours =
            "hal_parport bit IN FALSE parport.0.pin-01-out\nhal_parport NO 0 parport.0.read\n";
        assert_eq!(listing(lcnc, "hal_parport"), listing(ours, "hal_parport"));
        assert_eq!(listing(ours, "hal_parport").len(), 2);
        assert_eq!(
            listing("m u32 RW 0x0000000A m.x\n", "m"),
            listing("m u32   RW 10 m.x\n", "m")
        );
        assert_eq!(
            getp_values("TRUE\nhal_parport bit IN FALSE x\n 17 \n"),
            ["TRUE", "17"]
        );
        assert_eq!(
            shm_used("  used/total shared memory:   8881/1048576\n"),
            [8881]
        );
        assert_eq!(halcmd_args_record("cfg=\"0 sim\""), 16);
        assert_eq!(
            halcmd_args_record("cfg=\"0 sim 1 sim 2 sim 3 sim 4 sim 5 sim 6 sim\""),
            64
        );
    }
}
