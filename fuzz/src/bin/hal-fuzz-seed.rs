//! Regenerates the seed files of the stored corpus (`fuzz/corpus/`):
//! from the golden HAL cases (`../shared/golden`, or the directory given
//! as the first argument), the shipped configs and end-to-end tests, and
//! the LinuxCNC-style inputs written below. Files a fuzzer found bugs
//! with (`regression-*`) are kept as they are.
//!
//!     cargo run -p hal-fuzz --bin hal-fuzz-seed -- --write [GOLDEN_DIR] [--corpus-dir DIR]
//!
//! It rewrites files in the source tree (or under `--corpus-dir`), so it
//! does nothing without `--write`. What it could not read or write is an
//! error with the file; a closed standard output only silences the
//! summary.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use hal_fuzz::corpus;
use hal_lang::lexer::logical_lines;

/// Prefixes of the files this tool writes (and so removes first).
const SEED_PREFIXES: &[&str] = &["golden-", "config-", "e2e-", "style-", "module-"];

/// HAL lines and files in the style of LinuxCNC configurations, written
/// for this corpus: stepper and servo machines on a parallel port, the
/// INI and environment substitutions real configs use, and the oddities
/// of the language (continuations, quotes, arrows, comments, `name =
/// value`).
const STYLE_HAL: &[&str] = &[
    "# stepper machine, base thread for step generation
loadrt [KINS]KINEMATICS
loadrt [EMCMOT]EMCMOT base_period_nsec=[EMCMOT]BASE_PERIOD servo_period_nsec=[EMCMOT]SERVO_PERIOD num_joints=[KINS]JOINTS
loadrt hal_parport cfg=\"0x378 out\"
setp parport.0.reset-time 5000
loadrt stepgen step_type=0,0,0
addf parport.0.read base-thread
addf stepgen.make-pulses base-thread
addf parport.0.write base-thread
addf parport.0.reset base-thread
addf stepgen.capture-position servo-thread
addf motion-command-handler servo-thread
addf motion-controller servo-thread
addf stepgen.update-freq servo-thread
net spindle-cmd-rpm <= spindle.0.speed-out
net estop-out <= iocontrol.0.user-enable-out
net estop-out => iocontrol.0.emc-enable-in
",
    "net xstep => parport.0.pin-03-out
setp parport.0.pin-03-out-reset 1
setp stepgen.0.steplen 1
setp stepgen.0.stepspace 0
setp stepgen.0.dirhold 35000
setp stepgen.0.dirsetup 35000
setp stepgen.0.maxaccel [JOINT_0]STEPGEN_MAXACCEL
net xpos-cmd joint.0.motor-pos-cmd => stepgen.0.position-cmd
net xpos-fb stepgen.0.position-fb => joint.0.motor-pos-fb
net xstep <= stepgen.0.step
net xdir <= stepgen.0.dir
net xenable joint.0.amp-enable-out => stepgen.0.enable
",
    "loadrt threads name1=servo-thread period1=1000000 fp1=1
loadrt pid names=pid.x,pid.y,pid.z
loadrt encoder num_chan=3
loadrt pwmgen output_type=1,1,1
setp pid.x.Pgain [JOINT_0]P
setp pid.x.Igain [JOINT_0]I
setp pid.x.Dgain [JOINT_0]D
setp pid.x.FF1 [JOINT_0]FF1
setp pid.x.deadband 0.000015
setp pid.x.maxoutput [JOINT_0]MAX_OUTPUT
net x-pos-cmd => pid.x.command
net x-pos-fb encoder.00.position => pid.x.feedback
net x-output pid.x.output => pwmgen.0.value
net x-enable => pid.x.enable pwmgen.0.enable
setp encoder.00.position-scale -2000
setp pwmgen.0.scale 10.0
addf encoder.capture-position servo-thread
addf pid.x.do-pid-calcs servo-thread
addf pwmgen.update servo-thread
",
    "# long line split with backslashes
loadrt mux_generic \\
    config=\"bf2,fu4\"
net jog-speed \\
    halui.axis.jog-speed \\
    <= mux4.0.out
show pin mux*
list sig
save all
",
    "loadrt and2 count=2
loadrt not names=inv.a,inv.b
and2.0.in0 = 1
setp and2.0.in1 TRUE
net a and2.0.out => inv.a.in
net b inv.a.out <=> and2.1.in0
linkps and2.1.in1 => b
linksp a <= and2.1.out
unlinkp and2.1.in1
alias pin and2.0.in0 first-input
alias param and2.0.tmax and2-tmax
unalias pin first-input
delsig b
getp and2.0.out
gets a
ptype and2.0.in0
stype a
show all
show funct
show thread
show comp
status
echo
print \"marker\"
unecho
",
    "loadrt threads name1=base period1=25000 name2=servo period2=1000000
loadrt siggen
loadrt lowpass count=1
loadrt ddt count=2
addf siggen.0.update servo 0
addf lowpass.0 servo -1
addf ddt.0 servo
delf ddt.0 servo
initf ddt.1 servo
setp siggen.0.frequency 2.5
setp siggen.0.amplitude $(AMPLITUDE)
setp lowpass.0.gain $GAIN
sets x 0x10
setexact_for_test_suite_only
unloadrt ddt
unload lowpass.0
",
    "loadrt sampler cfg=fbsuSUlk depth=1000
loadrt streamer cfg=ffb depth=0x40,8
loadrt conv_float_s32 count=1
loadrt bitslice count=1 personality=16
loadrt lincurve personality=4
loadrt select8 count=1
loadrt counter num_chan=1
loadrt charge_pump
loadrt estop_latch
loadrt toggle2nist names=spindle-toggle
list pin -t float
show param -t rw
show sig -t bit
",
];

/// `loadrt` argument lines in LinuxCNC's style, for the parameter target.
const STYLE_LOADRT: &[&str] = &[
    "trivkins coordinates=XYZ\nmotmod base_period_nsec=50000 servo_period_nsec=1000000 num_joints=3",
    "trivkins coordinates=XYZZ kinstype=BOTH\nmotmod servo_period_nsec=1000000 num_joints=4 num_dio=8 num_aio=4",
    "trivkins coordinates=XYYZ kinstype=B\nmotmod num_joints=4 unlock_joints_mask=0x1",
    "hal_parport cfg=\"0x378 out 0x278 in\"",
    "hal_parport cfg=\"0 in sim 1 x simloop\"",
    "hal_parport cfg=378_x",
    "stepgen step_type=0,0,2 ctrl_type=p,p,v",
    "stepgen step_type=15,14,13,12,11,10,9,8",
    "pwmgen output_type=0,1,2 dither_pwm=1",
    "encoder num_chan=8",
    "encoder names=x-enc,y-enc",
    "pid num_chan=3 debug=1",
    "siggen names=sg.a,sg.b",
    "threads name1=base period1=25000 fp1=0 name2=servo period2=1000000 fp2=1",
    "sampler cfg=ff,bb depth=100,200",
    "streamer cfg=sSlLkK depth=512",
    "mux_generic config=\"bb8,ff2,ss4\"",
    "lincurve count=2 personality=4,16",
    "bitslice personality=32,1",
    "logic personality=0x104,0x208,0x1000",
    "counter num_chan=2",
    "and2 count=2 names=a,b",
    "conv_s64_u64 names=c1",
];

/// halstreamer inputs in LinuxCNC's style: cfg line, then the stream.
const STYLE_STREAM: &[&str] = &[
    "ffb\n# time x y probe\n0.0 0.0 0\n0.001 0.0025 0\n0.002 0.005 1\n",
    "su\n-1 4294967295\n2147483648 -1\n0x10 010\n+7 +8\n",
    "lk\n-9223372036854775808 18446744073709551615\n99999999999999999999 -1\n",
    "f\n1e308\n-1e-320\nnan\n-inf\n0x1f\n.5\n5.\n",
    "b\n0\n1\n2\n # indented comment\n1 trailing words\n",
];

const USAGE: &str = "usage: hal-fuzz-seed --write [GOLDEN_DIR] [--corpus-dir DIR]
rewrites the seed files of fuzz/corpus/ in the source tree (or under DIR)
(GOLDEN_DIR: ../shared/golden beside the checkout)";

/// Seeds per target: file name and bytes.
type Seeds = BTreeMap<&'static str, BTreeMap<String, Vec<u8>>>;

/// What stopped the seeds from being written.
#[derive(Debug, thiserror::Error)]
enum SeedError {
    #[error("no golden cases under {} (give their directory as the argument)", .0.display())]
    NoGoldenCases(PathBuf),
    #[error("{action} {}", path.display())]
    File {
        action: &'static str,
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl SeedError {
    fn file(action: &'static str, path: &Path) -> impl FnOnce(std::io::Error) -> Self {
        let path = path.to_path_buf();
        move |source| Self::File {
            action,
            path,
            source,
        }
    }
}

/// What the command line asks for.
struct Request {
    golden: PathBuf,
    corpus: Option<PathBuf>,
}

fn parse_args(root: &Path) -> Option<Request> {
    let mut args = std::env::args_os().skip(1);
    if args.next().is_none_or(|a| a != "--write") {
        return None;
    }
    let mut golden = None;
    let mut corpus = None;
    while let Some(a) = args.next() {
        if a == "--corpus-dir" {
            corpus = Some(PathBuf::from(args.next()?));
        } else if golden.is_none() && !a.to_string_lossy().starts_with('-') {
            golden = Some(PathBuf::from(a));
        } else {
            return None;
        }
    }
    Some(Request {
        golden: golden.unwrap_or_else(|| root.join("../shared/golden")),
        corpus,
    })
}

fn main() -> ExitCode {
    let Some(root) = Path::new(env!("CARGO_MANIFEST_DIR")).parent() else {
        eprintln!(
            "hal-fuzz-seed: no workspace root above {}",
            env!("CARGO_MANIFEST_DIR")
        );
        return ExitCode::from(1);
    };
    let Some(req) = parse_args(root) else {
        eprintln!("{USAGE}");
        return ExitCode::from(2);
    };
    let written =
        gather(root, &req.golden).and_then(|seeds| write_seeds(&seeds, req.corpus.as_deref()));
    let counts = match written {
        Ok(c) => c,
        Err(e) => {
            match std::error::Error::source(&e) {
                Some(cause) => eprintln!("hal-fuzz-seed: {e}: {cause}"),
                None => eprintln!("hal-fuzz-seed: {e}"),
            }
            return ExitCode::from(1);
        }
    };
    // The summary is only for reading: a closed stdout ends it quietly.
    let mut out = std::io::stdout().lock();
    for (target, n) in counts {
        if writeln!(out, "{target}: {n} seeds").is_err() {
            break;
        }
    }
    ExitCode::SUCCESS
}

/// Rewrites each target's seed files (those with a seed prefix) in its
/// corpus directory (under `corpus_root`, else the crate's); the number
/// written per target.
fn write_seeds(
    seeds: &Seeds,
    corpus_root: Option<&Path>,
) -> Result<Vec<(String, usize)>, SeedError> {
    let mut counts = Vec::new();
    for (target, files) in seeds {
        let dir = match corpus_root {
            Some(r) => r.join(target),
            None => corpus::dir(target),
        };
        std::fs::create_dir_all(&dir).map_err(SeedError::file("creating", &dir))?;
        let old = std::fs::read_dir(&dir).map_err(SeedError::file("listing", &dir))?;
        for old in old.flatten() {
            let n = old.file_name().to_string_lossy().into_owned();
            if SEED_PREFIXES.iter().any(|p| n.starts_with(p)) {
                let path = old.path();
                std::fs::remove_file(&path).map_err(SeedError::file("removing", &path))?;
            }
        }
        for (name, bytes) in files {
            let p = dir.join(name);
            std::fs::write(&p, bytes).map_err(SeedError::file("writing", &p))?;
        }
        counts.push((target.to_string(), files.len()));
    }
    Ok(counts)
}

// Long on purpose: gathers every target's seeds (HAL files, their lines,
// loadrt words, streamer inputs) into one map; the gathering blocks share
// that map.
fn gather(root: &Path, golden: &Path) -> Result<Seeds, SeedError> {
    let mut seeds: Seeds = BTreeMap::new();
    let mut add = |target: &'static str, name: String, bytes: Vec<u8>| {
        let files = seeds.entry(target).or_default();
        if !files.values().any(|b| *b == bytes) {
            files.insert(name, bytes);
        }
    };

    // (corpus name, text, the streamer input beside it)
    let mut hal_files: Vec<(String, String, Option<Vec<u8>>)> = Vec::new();
    for (prefix, dir) in [
        ("golden", golden.to_path_buf()),
        ("e2e", root.join("tests")),
        ("config", root.join("configs")),
    ] {
        for path in hal_files_under(&dir) {
            let rel = path.strip_prefix(&dir).unwrap_or(&path);
            let name = format!(
                "{prefix}-{}",
                rel.with_extension("").to_string_lossy().replace('/', "-")
            );
            let text = std::fs::read_to_string(&path).map_err(SeedError::file("reading", &path))?;
            let input = std::fs::read(path.with_file_name("input")).ok();
            hal_files.push((name, text, input));
        }
    }
    if !hal_files.iter().any(|(n, _, _)| n.starts_with("golden-")) {
        return Err(SeedError::NoGoldenCases(golden.to_path_buf()));
    }
    for (i, text) in STYLE_HAL.iter().enumerate() {
        hal_files.push((format!("style-{i}"), text.to_string(), None));
    }

    for (name, text, input) in &hal_files {
        add("halcmd_dispatch", name.clone(), text.as_bytes().to_vec());
        for line in logical_lines(text) {
            let t = line.text.trim();
            if t.is_empty() || t.starts_with('#') {
                continue;
            }
            add(
                "halcmd_lexer",
                format!("{name}-{}", line.number),
                line.text.clone().into_bytes(),
            );
            if let Some(args) = t.strip_prefix("loadrt ") {
                add(
                    "loadrt_params",
                    format!("{name}-{}", line.number),
                    args.as_bytes().to_vec(),
                );
            }
        }
        // The streamer's columns and the stream it was given.
        if let Some(stream) = input {
            let cfg = text
                .lines()
                .filter_map(|l| l.strip_prefix("loadrt streamer "))
                .flat_map(str::split_whitespace)
                .find_map(|w| w.strip_prefix("cfg="))
                .and_then(|c| c.split(',').next());
            if let Some(cfg) = cfg {
                let mut bytes = format!("{cfg}\n").into_bytes();
                bytes.extend(stream);
                add("halstreamer_input", name.clone(), bytes);
            }
        }
    }
    for (i, text) in STYLE_LOADRT.iter().enumerate() {
        add(
            "loadrt_params",
            format!("style-{i}"),
            text.as_bytes().to_vec(),
        );
    }
    for name in hal_host::registry().names() {
        add(
            "loadrt_params",
            format!("module-{name}"),
            name.as_bytes().to_vec(),
        );
    }
    for (i, text) in STYLE_STREAM.iter().enumerate() {
        add(
            "halstreamer_input",
            format!("style-{i}"),
            text.as_bytes().to_vec(),
        );
    }

    Ok(seeds)
}

/// `*.hal` files under `dir`, sorted, at any depth.
fn hal_files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "hal") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}
