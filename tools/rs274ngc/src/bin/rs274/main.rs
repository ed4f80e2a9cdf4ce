//! rs274: the standalone G-code interpreter, as LinuxCNC's. It prints
//! the canonical calls a program makes, one per line.
//!
//! `rs274 [-p interp.so] [-t tool.tbl] [-v var-file.var] [-n 0|1|2]
//! [-b] [-s] [-g] [-i file.ini] [-T] [-l level] [input [output]]`

mod args;
mod ini_config;
mod menu;

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use rs274ngc::{tooltable, Config, Interp, InterpError, PrintCanon, Status};

use args::{Args, OnError};

/// LinuxCNC's default tool table for rs274 when -t is not given.
const DEFAULT_TOOL_TABLE: &str = "/usr/share/doc/linuxcnc/examples/sample-configs/common/tool.tbl";

fn main() -> ExitCode {
    let argv: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let program = argv
        .first()
        .map(|a| a.to_string_lossy().into_owned())
        .unwrap_or_default();
    match args::convention(&argv) {
        Some(args::Convention::Help) => {
            hal_core::out!("{}{}", args::usage(&program), args::SUITE_OPTIONS);
            return ExitCode::SUCCESS;
        }
        Some(args::Convention::Version) => {
            hal_core::outln!("rs274 {}", env!("CARGO_PKG_VERSION"));
            return ExitCode::SUCCESS;
        }
        Some(args::Convention::UnknownLong(word)) => {
            eprint!(
                "{program}: unrecognized option '{word}'\n{}",
                args::usage(&program)
            );
            return ExitCode::from(1);
        }
        None => {}
    }
    let mut args = match args::parse(&argv) {
        Ok(args) => args,
        Err(()) => {
            eprint!("{}", args::usage(&program));
            return ExitCode::from(1);
        }
    };
    if let Some(plugin) = &args.plugin {
        eprintln!("emcTaskInit: could not open interpreter '{plugin}': pluggable interpreters are not supported; using the built-in one");
    }
    if !args.go && !menu::run(&mut args) {
        return ExitCode::from(1);
    }
    eprintln!("executing");
    ExitCode::from(run(&args))
}

/// Print an interpreter error as rs274 does: its text, then the line.
fn report_error(error: &InterpError, interp: &Interp) {
    eprintln!("{error}");
    let mut stderr = std::io::stderr();
    let _ = stderr.write_all(interp.line_text());
    let _ = stderr.write_all(b"\n");
}

fn config_from(args: &Args) -> Config {
    let mut config = Config::default();
    if let Some(ini) = &args.ini {
        // As LinuxCNC: an INI file that cannot be opened is reported and
        // the run goes on without it.
        if !ini_config::apply(ini, &mut config) {
            eprintln!("Unable to open inifile:{}:", ini.display());
            config = Config::default();
        }
    }
    if let Some(var) = &args.parameter_file {
        config.parameter_file = Some(var.clone());
    }
    config
}

/// The tool table, as rs274 reads it: a `-t` file that cannot be read
/// gives an empty table (a bounded-read refusal is reported first), and
/// so does a missing default table (LinuxCNC's packaged rs274 would end
/// the run with no output there; an empty table lets programs without
/// tools run, as they do where LinuxCNC's examples are installed).
fn tool_entries(args: &Args) -> Vec<rs274ngc::ToolEntry> {
    let path = args
        .tool_table
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_TOOL_TABLE));
    match tooltable::load(&path) {
        Ok(table) => {
            for w in &table.warnings {
                eprint!("{w}");
            }
            table.entries
        }
        Err(_) if args.tool_table.is_none() => Vec::new(),
        Err(e) => {
            if !matches!(&e, InterpError::Io { .. }) {
                eprintln!("{e}");
            }
            Vec::new()
        }
    }
}

fn user_m_codes(args: &Args, config: &Config) -> Vec<i32> {
    if !args.task_init {
        return Vec::new();
    }
    let mut dirs = config.user_m_path.clone();
    if let Some(dir) = args.input.as_ref().and_then(|p| p.parent()) {
        dirs.push(dir.to_path_buf());
    }
    (100..200)
        .filter(|n| dirs.iter().any(|d| d.join(format!("M{n}")).is_file()))
        .collect()
}

/// Run the program (or the keyboard); the exit status.
fn run(args: &Args) -> u8 {
    let config = config_from(args);
    let tools = tool_entries(args);
    // Whole lines reach the output as they are made: a program that never
    // ends (an O-word loop) is stopped by a signal, and what it printed up
    // to then must not stay in a buffer.
    let out: Box<dyn Write> = match &args.output {
        Some(path) => match std::fs::File::create(path) {
            Ok(f) => Box::new(std::io::LineWriter::new(f)),
            Err(_) => {
                eprintln!("could not open output file {}", path.display());
                return 1;
            }
        },
        None => Box::new(std::io::LineWriter::new(std::io::stdout())),
    };
    let mut canon = PrintCanon::new(Some(out), tools);
    canon.block_delete = args.block_delete;
    canon.print_to_stdout = args.output.is_some();
    canon.user_m_codes = user_m_codes(args, &config);
    if config.random_toolchanger {
        canon.random_toolchanger_spindle();
    }
    let mut interp = Interp::new(config);
    if let Err(e) = interp.init(&mut canon) {
        canon.flush();
        report_error(&e, &interp);
        return 1;
    }
    let status = match &args.input {
        None => {
            interpret_from_keyboard(&mut interp, &mut canon);
            0
        }
        Some(input) => {
            if let Err(e) = interp.open(input, &mut canon) {
                canon.flush();
                report_error(&e, &interp);
                return 1;
            }
            let status = interpret_from_file(&mut interp, &mut canon, args.on_error);
            interp.close(&mut canon);
            status
        }
    };
    let saved = interp.exit(&mut canon);
    canon.flush();
    if let Err(e) = saved {
        eprintln!("{e}");
    }
    if canon.write_failed() {
        eprintln!("rs274: could not write the canonical calls to the output");
        return 1;
    }
    status
}

/// Run the open file; 1 if it stopped on an error.
fn interpret_from_file(interp: &mut Interp, canon: &mut PrintCanon, on_error: OnError) -> u8 {
    loop {
        match interp.read(canon) {
            Ok(Status::EndFile) => return 0,
            Ok(Status::ExecuteFinish) if canon.block_delete => continue,
            Ok(_) => {}
            Err(e) => {
                canon.flush();
                report_error(&e, interp);
                match on_error {
                    OnError::Stop => return 1,
                    OnError::Continue => continue,
                    OnError::Mdi => {
                        if !mdi_then_continue(interp, canon) {
                            return 1;
                        }
                        continue;
                    }
                }
            }
        }
        match interp.execute(canon) {
            Ok(Status::Exit) => return 0,
            Ok(_) => {}
            Err(e) => {
                canon.flush();
                report_error(&e, interp);
                match on_error {
                    OnError::Stop => return 1,
                    OnError::Continue => {}
                    OnError::Mdi => {
                        if !mdi_then_continue(interp, canon) {
                            return 1;
                        }
                    }
                }
            }
        }
    }
}

fn mdi_then_continue(interp: &mut Interp, canon: &mut PrintCanon) -> bool {
    eprintln!("starting MDI");
    interpret_from_keyboard(interp, canon);
    eprint!("continue program? y/n =>");
    menu::read_stdin_line().is_some_and(|answer| answer.starts_with(b"y"))
}

/// Read lines from standard input and run each, until `quit` or the end.
fn interpret_from_keyboard(interp: &mut Interp, canon: &mut PrintCanon) {
    let prompt = std::io::stdin().is_terminal();
    loop {
        if prompt {
            print!("READ => ");
            let _ = std::io::stdout().flush();
        }
        let Some(mut text) = menu::read_stdin_line() else {
            return;
        };
        if text.last() == Some(&b'\r') {
            text.pop();
        }
        if text == b"quit" {
            return;
        }
        match interp.read_mdi(&text, canon) {
            Ok(Status::ExecuteFinish) if canon.block_delete => {}
            Ok(Status::EndFile) => {}
            Ok(_) => {
                if let Err(e) = interp.execute(canon) {
                    canon.flush();
                    report_error(&e, interp);
                }
            }
            Err(e) => {
                canon.flush();
                report_error(&e, interp);
            }
        }
        canon.flush();
    }
}
