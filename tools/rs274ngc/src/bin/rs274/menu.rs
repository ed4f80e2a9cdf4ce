//! The menu rs274 shows without -g (on standard error, answers from
//! standard input), as LinuxCNC's.

use std::io::BufRead;
use std::path::PathBuf;

use crate::args::{Args, OnError};

fn read_line() -> Option<String> {
    let mut line = String::new();
    match std::io::stdin().lock().read_line(&mut line) {
        Ok(0) | Err(_) => None,
        Ok(_) => Some(line),
    }
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
        let Some(line) = read_line() else {
            return false;
        };
        match choice(&line) {
            Some(1) => return true,
            Some(2) => {
                eprint!("name of parameter file => ");
                let name = read_line().unwrap_or_default();
                let name = name.trim_end_matches('\n');
                if std::fs::File::open(name).is_err() {
                    eprintln!("Cannot open {name}");
                    return false;
                }
                args.parameter_file = Some(PathBuf::from(name));
            }
            Some(3) => {
                eprint!("name of tool file => ");
                let name = read_line().unwrap_or_default();
                let name = name.trim_end_matches('\n');
                if std::fs::File::open(name).is_err() {
                    eprintln!("Cannot open {name}");
                    return false;
                }
                args.tool_table = Some(PathBuf::from(name));
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
