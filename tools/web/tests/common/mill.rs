//! The simulated mill (configs/sim/mill) run by the suite's `linuxcnc`
//! on an instance of its own. `linuxcnc` belongs to another package
//! (hal-tools): the tests run the one cargo built beside hal-web (`cargo
//! test --workspace` and scripts/test-all build every binary first) and
//! fail, saying so, when it is not there.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use hal_launcher::{request, TaskAnswer};

/// A program of the suite from cargo's output directory.
fn suite_bin(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap();
    let path = deps.parent().unwrap().join(name);
    assert!(
        path.exists(),
        "{} is not built: this test runs the suite's machine; build the suite's \
         programs first (cargo build -p hal-tools --bins)",
        path.display()
    );
    path
}

/// A running `linuxcnc mill.ini` in a scratch copy of configs/sim/mill.
pub struct Mill {
    pub instance: String,
    dir: PathBuf,
    child: Child,
}

impl Mill {
    /// Starts the mill and waits until task answers.
    pub fn start() -> Mill {
        Mill::start_with("")
    }

    /// Starts the mill with `hal_lines` added to its INI's `[HAL]`
    /// section, and waits until task answers.
    pub fn start_with(hal_lines: &str) -> Mill {
        // Its own instance and directory, also beside another mill of
        // the same test program.
        static STARTED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let n = STARTED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let instance = format!("t-web-mill-{}-{n}", std::process::id());
        let dir = std::env::temp_dir().join(format!("hal-web-{instance}"));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs/sim/mill");
        for entry in std::fs::read_dir(&src).unwrap().flatten() {
            let name = entry.file_name();
            if !name.to_string_lossy().starts_with("sim.var") {
                std::fs::copy(entry.path(), dir.join(&name)).unwrap();
            }
        }
        if !hal_lines.is_empty() {
            let ini = dir.join("mill.ini");
            let text = std::fs::read_to_string(&ini).unwrap();
            let text = text.replacen("[HAL]\n", &format!("[HAL]\n{hal_lines}\n"), 1);
            std::fs::write(&ini, text).unwrap();
        }
        // Its messages go to a file beside the copy, shown if it fails.
        let log = dir.join("linuxcnc.stderr");
        let child = Command::new(suite_bin("linuxcnc"))
            .arg(dir.join("mill.ini"))
            .env("HAL_INSTANCE", &instance)
            .env("HAL_NO_REALTIME", "1")
            .env("HAL_SHM_SIZE", (16u64 << 20).to_string())
            .stdout(Stdio::null())
            .stderr(std::fs::File::create(&log).unwrap())
            .spawn()
            .unwrap();
        let mill = Mill {
            instance,
            dir,
            child,
        };
        let end = Instant::now() + Duration::from_secs(90);
        while !matches!(mill.task("status"), Some(TaskAnswer::Done(_))) {
            assert!(
                Instant::now() < end,
                "the mill did not come up:\n{}",
                std::fs::read_to_string(&log).unwrap_or_default()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        mill
    }

    /// Task's answer to a one-word request.
    pub fn task(&self, word: &str) -> Option<TaskAnswer> {
        request(&self.instance, &[word.to_string()], Duration::from_secs(10)).ok()
    }
}

impl Drop for Mill {
    fn drop(&mut self) {
        super::stop(&mut self.child, Duration::from_secs(30));
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}
