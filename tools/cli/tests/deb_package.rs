//! The Debian package's definition (`[package.metadata.deb]` of
//! tools/cli/Cargo.toml and packaging/deb/) checked against the tree: every
//! binary, the udev rules, /run/hal, the limits of the group hal, the
//! maintainer scripts; no setuid or setgid bit anywhere; and the postinst
//! run against recording stand-ins for the system commands it calls.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::Command;

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn deb_table() -> toml::Table {
    let text = std::fs::read_to_string(crate_dir().join("Cargo.toml")).unwrap();
    let manifest: toml::Table = text.parse().unwrap();
    manifest["package"]["metadata"]["deb"]
        .as_table()
        .expect("[package.metadata.deb]")
        .clone()
}

/// (source, destination, mode) of every asset.
fn assets(deb: &toml::Table) -> Vec<(String, String, u32)> {
    deb["assets"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| {
            let a = a.as_array().expect("asset as [source, destination, mode]");
            let s = |i: usize| a[i].as_str().unwrap().to_string();
            (s(0), s(1), u32::from_str_radix(&s(2), 8).unwrap())
        })
        .collect()
}

fn maintainer_script(deb: &toml::Table, name: &str) -> PathBuf {
    let dir = crate_dir().join(deb["maintainer-scripts"].as_str().unwrap());
    dir.join(name)
}

/// Every file under `dir`, recursively.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(files_under(&path));
        } else {
            files.push(path);
        }
    }
    files
}

#[test]
fn every_binary_is_packaged_and_nothing_is_setuid() {
    let deb = deb_table();
    assert_eq!(deb["name"].as_str(), Some("hal-suite"));
    let assets = assets(&deb);
    // The tools' own programs and the drivers' user-space programs
    // (hy_vfd, canservo-sim, ...).
    let mut bin_dirs = Vec::new();
    for group in ["../../tools", "../../drivers"] {
        for krate in std::fs::read_dir(crate_dir().join(group)).unwrap() {
            let dir = krate.unwrap().path().join("src/bin");
            if dir.is_dir() {
                bin_dirs.push(dir);
            }
        }
    }
    let bins = bin_dirs
        .iter()
        .flat_map(|d| std::fs::read_dir(d).unwrap())
        .collect::<Vec<_>>();
    assert!(bins.len() > 20, "found only {} programs", bins.len());
    for entry in bins {
        let file = entry.unwrap().file_name().into_string().unwrap();
        let bin = file.trim_end_matches(".rs");
        // Benchmarks (rs274-bench) are for developers: not installed.
        if bin.ends_with("-bench") {
            continue;
        }
        let src = format!("target/release/{bin}");
        assert!(
            assets.iter().any(|(s, d, _)| *s == src && d == "usr/bin/"),
            "binary {bin} is not in the package: add [\"{src}\", \"usr/bin/\", \"755\"] to \
             [package.metadata.deb] assets"
        );
    }
    for (src, dest, mode) in &assets {
        assert_eq!(
            mode & 0o7000,
            0,
            "{src}: setuid, setgid or sticky bit in mode {mode:o}"
        );
        assert_eq!(
            mode & 0o022,
            0,
            "{src}: writable by group or others ({mode:o})"
        );
        if src == "target/release/hal-host" {
            // The host gets capabilities: only root and the group run it.
            assert_eq!(*mode, 0o750, "hal-host mode");
        }
        // Built before packaging (binaries, and the Python module that
        // packaging/python-wheel makes): not in a fresh checkout.
        if src.starts_with("target/") || src.starts_with("../../target/") {
            continue;
        }
        let pattern = crate_dir().join(src);
        let pattern = pattern.to_str().unwrap();
        if pattern.contains('*') {
            let base = Path::new(pattern.split('*').next().unwrap());
            assert!(
                base.is_dir(),
                "{src}: {} is not a directory",
                base.display()
            );
            let suffix = pattern.rsplit('*').next().unwrap();
            assert!(
                files_under(base)
                    .iter()
                    .any(|f| f.to_str().unwrap().ends_with(suffix)),
                "{src} matches nothing"
            );
        } else {
            assert!(Path::new(pattern).is_file(), "{src} does not exist");
        }
        assert!(
            !dest.starts_with('/'),
            "{dest}: destinations are relative to /"
        );
    }
}

#[test]
fn rules_runtime_directory_and_limits_are_installed() {
    let deb = deb_table();
    let assets = assets(&deb);
    let dest_of = |src: &str| {
        assets
            .iter()
            .find(|(s, _, _)| s == src)
            .map(|(_, d, _)| d.clone())
            .unwrap_or_else(|| panic!("{src} is not packaged"))
    };
    assert_eq!(
        dest_of("../../udev/60-hal-suite.rules"),
        "usr/lib/udev/rules.d/"
    );
    assert_eq!(
        dest_of("../../packaging/tmpfiles.d/hal.conf"),
        "usr/lib/tmpfiles.d/hal.conf"
    );
    assert_eq!(
        dest_of("../../packaging/limits.d/hal.conf"),
        "etc/security/limits.d/hal.conf"
    );
    let conf: Vec<&str> = deb["conf-files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(conf, ["/etc/security/limits.d/hal.conf"]);
    let read = |p: &str| std::fs::read_to_string(crate_dir().join(p)).unwrap();
    let lines = |text: String| -> Vec<String> {
        text.lines()
            .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
            .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
            .collect()
    };
    assert_eq!(
        lines(read("../../packaging/tmpfiles.d/hal.conf")),
        ["d /run/hal 0770 root hal -"]
    );
    assert_eq!(
        lines(read("../../packaging/limits.d/hal.conf")),
        ["@hal - rtprio 99", "@hal - memlock unlimited"]
    );
    assert!(read("../../udev/60-hal-suite.rules").contains("GROUP=\"hal\""));
    assert_eq!(dest_of("../../packaging/man/*.1"), "usr/share/man/man1/");
    assert_eq!(dest_of("../../packaging/man9/*.9"), "usr/share/man/man9/");
    // The launcher finds the standard HAL files at ../share/hal/hallib
    // from its own directory.
    assert_eq!(dest_of("../../lib/hallib/*"), "usr/share/hal/hallib/");
    let depends = deb["depends"].as_str().unwrap();
    assert!(
        depends.contains("libcap2-bin") && depends.contains("adduser"),
        "{depends}"
    );
}

/// The names of a relation field's packages ("libc6 (>= 2.35), adduser"
/// gives libc6 and adduser).
fn relation_names(field: &str) -> Vec<&str> {
    field
        .split(',')
        .filter_map(|r| r.split_whitespace().next())
        .collect()
}

#[test]
fn depends_lists_each_package_once_and_linuxcnc_is_a_conflict() {
    let deb = deb_table();
    let depends = relation_names(deb["depends"].as_str().unwrap());
    for (i, name) in depends.iter().enumerate() {
        assert!(!depends[..i].contains(name), "{name} twice in {depends:?}");
    }
    assert!(depends.contains(&"libc6"), "{depends:?}");
    // halcmd, halrun, linuxcnc, rs274 and lcec_conf have LinuxCNC's
    // names: the packages that ship LinuxCNC's own cannot be beside ours.
    for field in ["conflicts", "replaces"] {
        let names = relation_names(deb[field].as_str().unwrap());
        for pkg in ["linuxcnc-uspace", "linuxcnc"] {
            assert!(names.contains(&pkg), "{field} lacks {pkg}: {names:?}");
        }
    }
}

/// A directory of stand-ins for the commands the postinst calls: each
/// appends its name and arguments to `log`; `getent` finds no group.
fn stand_ins(dir: &Path, log: &Path) {
    std::fs::create_dir_all(dir).unwrap();
    for cmd in [
        "getent",
        "addgroup",
        "dpkg-statoverride",
        "setcap",
        "systemd-tmpfiles",
        "udevadm",
    ] {
        let status = if cmd == "getent" || cmd == "dpkg-statoverride" {
            2
        } else {
            0
        };
        let script = format!(
            "#!/bin/sh\necho \"{cmd} $*\" >> '{}'\n\
             case \"{cmd} $1\" in 'dpkg-statoverride --update') exit 0;; esac\nexit {status}\n",
            log.display()
        );
        let path = dir.join(cmd);
        std::fs::write(&path, script).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
}

#[test]
fn postinst_makes_the_group_then_restricts_and_gives_capabilities_to_the_host() {
    let deb = deb_table();
    let postinst = maintainer_script(&deb, "postinst");
    let postrm = maintainer_script(&deb, "postrm");
    for script in [&postinst, &postrm] {
        let mode = std::fs::metadata(script).unwrap().permissions().mode();
        assert_eq!(
            mode & 0o111,
            0o111,
            "{} is not executable",
            script.display()
        );
        let check = Command::new("sh").arg("-n").arg(script).status().unwrap();
        assert!(check.success(), "{}: shell syntax", script.display());
        let text = std::fs::read_to_string(script).unwrap();
        assert!(
            !text.contains("u+s") && !text.contains("4755") && !text.contains("g+s"),
            "{}",
            script.display()
        );
    }
    let tmp = std::env::temp_dir().join(format!("hal-deb-postinst-{}", std::process::id()));
    let log = tmp.join("log");
    stand_ins(&tmp.join("bin"), &log);
    let path = format!("{}:/usr/bin:/bin", tmp.join("bin").display());
    let out = Command::new("sh")
        .arg(&postinst)
        .arg("configure")
        .env("PATH", &path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let calls: Vec<String> = std::fs::read_to_string(&log)
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect();
    let at = |prefix: &str| {
        calls
            .iter()
            .position(|c| c.starts_with(prefix))
            .unwrap_or_else(|| panic!("postinst did not call '{prefix}': {calls:#?}"))
    };
    let group = at("addgroup --system hal");
    let mode = at("dpkg-statoverride --update --add root hal 0750 /usr/bin/hal-host");
    let caps =
        at("setcap cap_sys_nice,cap_ipc_lock,cap_sys_rawio,cap_net_raw+ep /usr/bin/hal-host");
    // ethercat-tool's raw socket: restricted to the group, then the
    // capability.
    let tool_mode = at("dpkg-statoverride --update --add root hal 0750 /usr/bin/ethercat-tool");
    let tool_caps = at("setcap cap_net_raw+ep /usr/bin/ethercat-tool");
    assert!(tool_mode < tool_caps, "{calls:#?}");
    let runtime = at("systemd-tmpfiles --create /usr/lib/tmpfiles.d/hal.conf");
    assert!(group < mode && mode < caps && caps < runtime, "{calls:#?}");
    // Any other maintainer action does nothing.
    std::fs::remove_file(&log).unwrap();
    let out = Command::new("sh")
        .arg(&postinst)
        .arg("abort-upgrade")
        .env("PATH", &path)
        .output()
        .unwrap();
    assert!(out.status.success());
    assert!(!log.exists(), "abort-upgrade ran commands");
    let _ = std::fs::remove_dir_all(&tmp);
}
