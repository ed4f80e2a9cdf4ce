//! The menu rs274 shows without -g (on standard error, answers from
//! standard input), as LinuxCNC's.

use std::io::BufRead;
use std::os::unix::ffi::OsStringExt;
use std::path::PathBuf;

use crate::args::{Args, OnError};

/// Most bytes of a line of standard input kept (the rest of a longer
/// line is read and dropped: memory stays bounded whatever arrives).
pub const MAX_INPUT_LINE: usize = 4096;

/// One line of standard input, without its newline, at most
/// [`MAX_INPUT_LINE`] bytes of it; `None` at the end of input.
pub fn read_stdin_line() -> Option<Vec<u8>> {
    let stdin = std::io::stdin();
    let mut input = stdin.lock();
    let mut line = Vec::new();
    let mut any = false;
    loop {
        let chunk = match input.fill_buf() {
            Ok([]) => return any.then_some(line),
            Ok(c) => c,
            Err(_) => return any.then_some(line),
        };
        any = true;
        let (part, done) = match chunk.iter().position(|&b| b == b'\n') {
            Some(i) => (&chunk[..i], Some(i + 1)),
            None => (chunk, None),
        };
        let room = MAX_INPUT_LINE.saturating_sub(line.len());
        line.extend_from_slice(&part[..part.len().min(room)]);
        let used = done.unwrap_or(chunk.len());
        input.consume(used);
        if done.is_some() {
            return Some(line);
        }
    }
}

/// A file name typed on standard input (any bytes).
fn read_path() -> Option<PathBuf> {
    read_stdin_line().map(|l| PathBuf::from(std::ffi::OsString::from_vec(l)))
}

fn read_line() -> Option<String> {
    read_stdin_line().map(|l| String::from_utf8_lossy(&l).into_owned())
}

fn choice(line: &str) -> Option<i64> {
    let t = line.trim_start();
    let len = t
        .char_indices()
        .take_while(|(i, c)| c.is_ascii_digit() || (*i == 0 && (*c == '-' || *c == '+')))
        .count();
    t[..len].parse().ok()
}

/// Run the menu until "1 = start interpreting"; false to exit with 1.
pub fn run(args: &mut Args) -> bool {
    loop {
        eprintln!("enter a number:");
        eprintln!("1 = start interpreting");
        eprintln!("2 = choose parameter file ...");
        eprintln!("3 = read tool file ...");
        eprintln!(
            "4 = turn block delete switch {}",
            if args.block_delete { "OFF" } else { "ON" }
        );
        eprintln!("5 = adjust error handling...");
        eprint!("enter choice => ");
        // The end of the input starts interpreting, as in LinuxCNC.
        let Some(line) = read_line() else {
            return true;
        };
        match choice(&line) {
            Some(1) => return true,
            Some(2) => {
                eprint!("name of parameter file => ");
                let Some(path) = read_path() else {
                    return false;
                };
                if std::fs::File::open(&path).is_err() {
                    eprintln!("Cannot open {}", path.display());
                    return false;
                }
                args.parameter_file = Some(path);
            }
            Some(3) => {
                eprint!("name of tool file => ");
                let Some(path) = read_path() else {
                    return false;
                };
                // LinuxCNC says nothing here when the table cannot be read.
                if std::fs::File::open(&path).is_err() {
                    return false;
                }
                args.tool_table = Some(path);
            }
            Some(4) => args.block_delete = !args.block_delete,
            Some(5) => adjust_error_handling(args),
            _ => {}
        }
    }
}

fn adjust_error_handling(args: &mut Args) {
    let with_output = args.output.is_some();
    loop {
        eprintln!("enter a number:");
        eprintln!("1 = done with error handling");
        eprintln!(
            "2 = {}print stack on error",
            if args.print_stack { "do not " } else { "" }
        );
        let third = match (with_output, args.on_error) {
            (true, OnError::Continue) => "3 = stop on error (do not continue)",
            (true, _) => "3 = continue on error (do not stop)",
            (false, OnError::Continue) => "3 = mdi on error (do not continue or stop)",
            (false, OnError::Mdi) => "3 = stop on error (do not mdi or continue)",
            (false, OnError::Stop) => "3 = continue on error (do not stop or mdi)",
        };
        eprintln!("{third}");
        eprint!("enter choice => ");
        let Some(line) = read_line() else {
            return;
        };
        match choice(&line) {
            Some(1) => return,
            Some(2) => args.print_stack = !args.print_stack,
            Some(3) => {
                args.on_error = match (with_output, args.on_error) {
                    (true, OnError::Continue) => OnError::Stop,
                    (true, _) => OnError::Continue,
                    (false, OnError::Continue) => OnError::Mdi,
                    (false, OnError::Mdi) => OnError::Stop,
                    (false, OnError::Stop) => OnError::Continue,
                }
            }
            _ => {}
        }
    }
}
