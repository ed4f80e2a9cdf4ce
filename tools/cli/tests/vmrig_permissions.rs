//! Permissions with real users, in the VM rig (`scripts/test-all` runs
//! this binary there as root, with `--include-ignored`, on a throw-away
//! root filesystem): the group `hal` lets its members use instances that
//! root or another member started, with every tool; anyone else is
//! refused with a message naming the group; files get the group and mode
//! 0660 whatever the umask; links planted in the runtime directory are
//! never followed; unsafe runtime directories are refused.
//!
//! The tests create users and groups, so they are ignored elsewhere (run
//! on purpose outside the rig, they fail saying so). They work whether or
//! not the group `hal` exists already (installing the package creates it,
//! and the rig shares the host's /etc): an existing group is used as it
//! is, a missing one is created and removed again. The users are the
//! test's own (named after the process) and removed at the end of each
//! test, whatever its outcome.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::{Mutex, MutexGuard};

/// Why the tests are ignored outside the rig.
const RIG_ONLY: &str = "creates users and groups: runs as root in the VM rig (scripts/test-all)";

/// Fails the test, saying why, unless it runs as root in the rig.
fn require_rig() {
    assert!(
        std::env::var_os("VMRIG_KERNEL").is_some() && nix::unistd::geteuid().is_root(),
        "{RIG_ONLY}; not in the rig (no VMRIG_KERNEL) or not root"
    );
}

/// Why a user-administration command failed.
#[derive(Debug, thiserror::Error)]
enum ShError {
    /// The command could not be started.
    #[error("{cmd}: {source}")]
    Start {
        cmd: String,
        #[source]
        source: std::io::Error,
    },
    /// It ran and failed; what it said on stderr.
    #[error("{cmd} {args:?}: {stderr}")]
    Failed {
        cmd: String,
        args: Vec<String>,
        stderr: String,
    },
}

/// Runs `cmd args`; its failure, with what it said.
fn try_sh(cmd: &str, args: &[&str]) -> Result<(), ShError> {
    let out = Command::new(cmd)
        .args(args)
        .output()
        .map_err(|source| ShError::Start {
            cmd: cmd.to_string(),
            source,
        })?;
    if out.status.success() {
        Ok(())
    } else {
        Err(ShError::Failed {
            cmd: cmd.to_string(),
            args: args.iter().map(|a| a.to_string()).collect(),
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        })
    }
}

fn sh(cmd: &str, args: &[&str]) {
    if let Err(e) = try_sh(cmd, args) {
        panic!("{e}");
    }
}

fn group_exists(name: &str) -> bool {
    nix::unistd::Group::from_name(name).ok().flatten().is_some()
}

/// The group `hal` (made if missing), two members and an outsider of this
/// test's own, for one test at a time (they share `/run/hal` and the
/// group). Dropping it removes the users, and the group if it made it.
struct Users {
    /// The member, the second member and the outsider.
    alice: String,
    carol: String,
    bob: String,
    made_group: bool,
    made: Vec<String>,
    _one_at_a_time: MutexGuard<'static, ()>,
}

impl Users {
    fn new(tag: &str) -> Users {
        static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());
        // A test that failed while holding it left nothing shared behind
        // (its users are gone): go on.
        let guard = ONE_AT_A_TIME
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let pid = std::process::id();
        let name = |role: &str| format!("h{pid}{tag}{role}");
        let mut users = Users {
            alice: name("a"),
            carol: name("c"),
            bob: name("b"),
            made_group: false,
            made: Vec::new(),
            _one_at_a_time: guard,
        };
        if !group_exists("hal") {
            sh("groupadd", &["--system", "hal"]);
            users.made_group = true;
        }
        for u in [users.alice.clone(), users.carol.clone(), users.bob.clone()] {
            sh("useradd", &["--no-create-home", "--shell", "/bin/sh", &u]);
            users.made.push(u);
        }
        sh("usermod", &["-aG", "hal", &users.alice]);
        sh("usermod", &["-aG", "hal", &users.carol]);
        users
    }
}

impl Drop for Users {
    fn drop(&mut self) {
        let mut failed = Vec::new();
        for u in &self.made {
            failed.extend(try_sh("userdel", &[u]).err().map(|e| e.to_string()));
        }
        if self.made_group {
            failed.extend(try_sh("groupdel", &["hal"]).err().map(|e| e.to_string()));
        }
        if !failed.is_empty() && !std::thread::panicking() {
            panic!("cleaning up: {}", failed.join("; "));
        }
    }
}

fn bin(name: &str) -> PathBuf {
    Path::new(env!("CARGO_BIN_EXE_halcmd"))
        .parent()
        .unwrap()
        .join(name)
}

/// Runs tool `name` as `user` (None: root) on `instance`, with `umask`.
fn as_user(user: Option<&str>, umask: &str, instance: &str, name: &str, args: &[&str]) -> Output {
    // runuser sets the user's groups from the group database, as a login
    // would; env sets the instance; the shell sets the umask, then becomes
    // the tool. No XDG_RUNTIME_DIR: the users have no session.
    let mut cmd = Command::new("runuser");
    cmd.args([
        "-u",
        user.unwrap_or("root"),
        "--",
        "env",
        "-u",
        "XDG_RUNTIME_DIR",
    ])
    .args(["-u", "HAL_RUNTIME_DIR", "-u", "HAL_GROUP"])
    .arg(format!("HAL_INSTANCE={instance}"))
    .arg("HAL_NO_REALTIME=1")
    .arg(format!("HAL_SHM_SIZE={}", 4u64 << 20))
    .args(["sh", "-c", &format!("umask {umask}; exec \"$0\" \"$@\"")])
    .arg(bin(name))
    .args(args)
    .stdin(Stdio::null());
    cmd.output().expect("runs")
}

fn ok(out: &Output, what: &str) -> String {
    assert!(
        out.status.success(),
        "{what}: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn refused(out: &Output, what: &str) -> String {
    assert!(!out.status.success(), "{what} was allowed");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn gid_of(group: &str) -> u32 {
    nix::unistd::Group::from_name(group)
        .unwrap()
        .unwrap()
        .gid
        .as_raw()
}

fn uid_of(user: &str) -> u32 {
    nix::unistd::User::from_name(user)
        .unwrap()
        .unwrap()
        .uid
        .as_raw()
}

/// Owner, group and mode of `path` (not following a link).
fn owner(path: &Path) -> (u32, u32, u32) {
    let m = std::fs::symlink_metadata(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    (m.uid(), m.gid(), m.mode() & 0o7777)
}

fn runtime_files(instance: &str) -> Vec<PathBuf> {
    ["lock", "sock", "log"]
        .iter()
        .map(|ext| PathBuf::from(format!("/run/hal/hal-{instance}.{ext}")))
        .chain([PathBuf::from(format!("/dev/shm/hal-{instance}"))])
        .collect()
}

#[test]
#[ignore = "creates users and groups: runs as root in the VM rig (scripts/test-all)"]
fn members_share_instances_and_others_are_told_how_to_join() {
    require_rig();
    let users = Users::new("m");
    let (alice, carol, bob) = (
        Some(users.alice.as_str()),
        Some(users.carol.as_str()),
        Some(users.bob.as_str()),
    );
    let hal = gid_of("hal");

    // Root starts an instance under a tight umask: everything is root:hal
    // 0660 anyway, in /run/hal (0770 root:hal).
    let root_inst = "perm-root";
    ok(
        &as_user(None, "077", root_inst, "realtime", &["start"]),
        "root start",
    );
    assert_eq!(owner(Path::new("/run/hal")), (0, hal, 0o770));
    for f in runtime_files(root_inst) {
        assert_eq!(owner(&f), (0, hal, 0o660), "{}", f.display());
    }
    ok(
        &as_user(None, "022", root_inst, "halcmd", &["loadrt", "and2"]),
        "root loadrt",
    );

    // A member uses it with every tool.
    let show = ok(
        &as_user(alice, "022", root_inst, "halcmd", &["show", "pin"]),
        "member show",
    );
    assert!(show.contains("and2.0.out"), "{show}");
    ok(
        &as_user(
            alice,
            "022",
            root_inst,
            "halcmd",
            &["setp", "and2.0.in0", "1"],
        ),
        "member setp",
    );
    ok(
        &as_user(alice, "022", root_inst, "halcmd", &["loadrt", "or2"]),
        "member loadrt (through the socket)",
    );
    let meter = ok(
        &as_user(
            alice,
            "022",
            root_inst,
            "halmeter",
            &["-n", "1", "pin", "and2.0.in0"],
        ),
        "member halmeter",
    );
    assert_eq!(meter, "and2.0.in0 = TRUE\n");
    ok(
        &as_user(alice, "022", root_inst, "realtime", &["status"]),
        "member status",
    );

    // An outsider is refused, and told which group and how to join.
    for (tool, args) in [
        ("halcmd", &["show"][..]),
        ("halmeter", &["-n", "1", "pin", "and2.0.in0"][..]),
        ("realtime", &["stop"][..]),
    ] {
        let err = refused(&as_user(bob, "022", root_inst, tool, args), tool);
        assert!(
            err.contains("group 'hal'") && err.contains(&format!("usermod -aG hal {}", users.bob)),
            "{tool}: {err}"
        );
    }

    // A member stops root's instance; everything is released.
    ok(
        &as_user(alice, "022", root_inst, "realtime", &["stop"]),
        "member stop",
    );
    // (The log stays, for what the host said.)
    for f in runtime_files(root_inst)
        .iter()
        .filter(|f| f.extension().is_none_or(|e| e != "log"))
    {
        assert!(!f.exists(), "{} left behind", f.display());
    }

    // A member starts an instance of their own (umask 077): alice:hal
    // 0660 in /run/hal, so root and the other member use it.
    let member_inst = "perm-alice";
    ok(
        &as_user(alice, "077", member_inst, "realtime", &["start"]),
        "member start",
    );
    for f in runtime_files(member_inst) {
        assert_eq!(
            owner(&f),
            (uid_of(&users.alice), hal, 0o660),
            "{}",
            f.display()
        );
    }
    ok(
        &as_user(carol, "022", member_inst, "halcmd", &["loadrt", "not"]),
        "other member loadrt",
    );
    ok(
        &as_user(None, "022", member_inst, "halcmd", &["show"]),
        "root show",
    );
    let err = refused(
        &as_user(bob, "022", member_inst, "halcmd", &["show"]),
        "outsider on a member's instance",
    );
    assert!(err.contains("group 'hal'"), "{err}");
    ok(
        &as_user(carol, "022", member_inst, "realtime", &["stop"]),
        "other member stop",
    );
}

#[test]
#[ignore = "creates users and groups: runs as root in the VM rig (scripts/test-all)"]
fn planted_links_are_not_followed_and_unsafe_directories_are_refused() {
    require_rig();
    let users = Users::new("p");
    // Make sure /run/hal exists (a root host creates it).
    ok(
        &as_user(None, "022", "perm-warm", "realtime", &["restart"]),
        "warm start",
    );
    ok(
        &as_user(None, "022", "perm-warm", "realtime", &["stop"]),
        "warm stop",
    );

    // A member plants links where root's host will put its log and lock.
    let victim = Path::new("/root/hal-victim");
    std::fs::write(victim, "precious\n").unwrap();
    let victim_owner = owner(victim);
    let log_inst = "perm-link-log";
    let plant = |name: &str| {
        sh(
            "runuser",
            &[
                "-u",
                &users.alice,
                "--",
                "ln",
                "-s",
                "/root/hal-victim",
                name,
            ],
        )
    };
    plant(&format!("/run/hal/hal-{log_inst}.log"));
    ok(
        &as_user(None, "022", log_inst, "realtime", &["start"]),
        "start past a planted log link",
    );
    let log = PathBuf::from(format!("/run/hal/hal-{log_inst}.log"));
    assert!(!std::fs::symlink_metadata(&log)
        .unwrap()
        .file_type()
        .is_symlink());
    ok(
        &as_user(None, "022", log_inst, "realtime", &["stop"]),
        "stop",
    );

    let lock_inst = "perm-link-lock";
    plant(&format!("/run/hal/hal-{lock_inst}.lock"));
    let err = refused(
        &as_user(None, "022", lock_inst, "realtime", &["start"]),
        "start through a planted lock link",
    );
    let lock = format!("/run/hal/hal-{lock_inst}.lock");
    assert!(
        err.contains(&lock) && err.contains("symbolic link"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(victim).unwrap(), "precious\n");
    assert_eq!(
        owner(victim),
        victim_owner,
        "the victim's owner or mode changed"
    );

    // A world-writable runtime directory is refused with the reason.
    let open = Path::new("/run/hal-open");
    std::fs::create_dir_all(open).unwrap();
    std::fs::set_permissions(open, std::fs::Permissions::from_mode(0o777)).unwrap();
    let out = Command::new(bin("realtime"))
        .arg("start")
        .env("HAL_INSTANCE", "perm-open")
        .env("HAL_RUNTIME_DIR", open)
        .env("HAL_NO_REALTIME", "1")
        .output()
        .unwrap();
    let err = refused(&out, "a world-writable runtime directory");
    assert!(err.contains("every user may write into it"), "{err}");

    // Without the group an instance is its owner's alone (its runtime
    // directory too: /run/hal lets a group in that this host does not
    // know, so it would be refused).
    let private = Path::new("/run/hal-private");
    std::fs::create_dir_all(private).unwrap();
    std::fs::set_permissions(private, std::fs::Permissions::from_mode(0o700)).unwrap();
    let start = |cmd: &str| {
        Command::new(bin("realtime"))
            .arg(cmd)
            .env("HAL_INSTANCE", "perm-nogroup")
            .env("HAL_GROUP", "no-such-group")
            .env("HAL_RUNTIME_DIR", private)
            .env("HAL_NO_REALTIME", "1")
            .env("HAL_SHM_SIZE", (4u64 << 20).to_string())
            .output()
            .unwrap()
    };
    let out = start("start");
    ok(&out, "start without the group");
    assert_eq!(owner(Path::new("/dev/shm/hal-perm-nogroup")).2, 0o600);
    let err = refused(
        &as_user(
            Some(users.alice.as_str()),
            "022",
            "perm-nogroup",
            "halcmd",
            &["show"],
        ),
        "a member on a private instance",
    );
    assert!(err.contains("not to the group 'hal'"), "{err}");
    ok(&start("stop"), "stop");

    for f in [victim, Path::new(&lock)] {
        std::fs::remove_file(f).unwrap();
    }
    for d in [open, private] {
        std::fs::remove_dir_all(d).unwrap();
    }
}
