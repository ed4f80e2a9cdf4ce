//! What a host does with files planted at its runtime files' names (the
//! README's "Permissions and runtime files"): a link at the lock is
//! refused with an error naming the file and why, and nothing is done
//! through it; whatever sits at the segment's name in /dev/shm when a
//! host starts (a dead host's segment, a planted file or link) is
//! removed and a new segment made, never used or followed.
//!
//! Each test has its own runtime directory (HAL_RUNTIME_DIR, 0700) and
//! instance name.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::instance;

/// A private runtime directory, removed when dropped.
struct RuntimeDir(PathBuf);

impl RuntimeDir {
    fn new(tag: &str) -> RuntimeDir {
        let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
            .join(format!("planted-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        std::fs::set_permissions(&d, std::fs::Permissions::from_mode(0o700)).unwrap();
        RuntimeDir(d)
    }
}

impl Drop for RuntimeDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs tool `name` with `args` on `inst`, runtime files in `dir`.
fn tool(dir: &RuntimeDir, inst: &str, name: &str, args: &[&str]) -> Output {
    let bin = Path::new(env!("CARGO_BIN_EXE_halcmd"))
        .parent()
        .unwrap()
        .join(name);
    Command::new(bin)
        .args(args)
        .env("HAL_RUNTIME_DIR", &dir.0)
        .env("HAL_INSTANCE", inst)
        .env("HAL_NO_REALTIME", "1")
        .env("HAL_SHM_SIZE", (4u64 << 20).to_string())
        .output()
        .unwrap()
}

fn text(out: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

#[test]
fn a_link_at_the_lock_is_refused_naming_the_file_and_why() {
    let dir = RuntimeDir::new("lock");
    let inst = instance("planted-lock");
    let victim = dir.0.join("victim");
    std::fs::write(&victim, "precious\n").unwrap();
    let lock = dir.0.join(format!("hal-{inst}.lock"));
    std::os::unix::fs::symlink(&victim, &lock).unwrap();

    for (name, args) in [("realtime", &["start"][..]), ("halcmd", &["show"][..])] {
        let out = tool(&dir, &inst, name, args);
        let said = text(&out);
        assert!(!out.status.success(), "{name} went ahead: {said}");
        assert!(
            said.contains(&lock.display().to_string()) && said.contains("is a symbolic link"),
            "{name} does not name the lock and why it is refused: {said}"
        );
    }
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious\n");
    assert!(std::fs::symlink_metadata(&lock)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(!hal_core::paths::segment(&inst).exists());
}

#[test]
fn what_sits_at_the_segments_name_is_replaced_never_used() {
    let dir = RuntimeDir::new("segment");
    let victim = dir.0.join("victim");
    std::fs::write(&victim, "precious\n").unwrap();
    for planted in ["file", "link"] {
        let inst = instance(&format!("planted-seg-{planted}"));
        let segment = hal_core::paths::segment(&inst);
        let _ = std::fs::remove_file(&segment);
        if planted == "file" {
            std::fs::write(&segment, vec![0x55u8; 1 << 16]).unwrap();
        } else {
            std::os::unix::fs::symlink(&victim, &segment).unwrap();
        }

        let out = tool(&dir, &inst, "realtime", &["start"]);
        assert!(out.status.success(), "{planted}: {}", text(&out));
        let out = tool(&dir, &inst, "halcmd", &["loadrt", "and2"]);
        assert!(out.status.success(), "{planted}: {}", text(&out));
        let now = std::fs::symlink_metadata(&segment).unwrap();
        assert!(now.file_type().is_file(), "{planted}: not a fresh segment");
        // The planted file was 64 KiB; the host's segment is its own size.
        assert_eq!(now.len(), 4 << 20, "{planted}: the planted file was used");
        let out = tool(&dir, &inst, "realtime", &["stop"]);
        assert!(out.status.success(), "{planted}: {}", text(&out));
        assert!(!segment.exists(), "{planted}: segment left behind");
    }
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious\n");
}
