//! rs274's options, parsed as getopt("p:t:v:bsn:gi:Tl:") does: options
//! before the file names, letters may be grouped (`-gb`), an option's
//! value may follow it or be the next word.

use std::ffi::OsString;
use std::os::unix::ffi::{OsStrExt, OsStringExt};
use std::path::PathBuf;

/// What to do when a line is refused (`-n`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OnError {
    /// 0: go on with the next line.
    Continue,
    /// 1: take MDI lines from the keyboard, then ask.
    Mdi,
    /// 2: stop (the default).
    Stop,
}

/// The parsed command line.
#[derive(Debug, Clone)]
pub struct Args {
    pub plugin: Option<String>,
    pub tool_table: Option<PathBuf>,
    pub parameter_file: Option<PathBuf>,
    pub ini: Option<PathBuf>,
    pub on_error: OnError,
    pub block_delete: bool,
    pub print_stack: bool,
    pub go: bool,
    pub task_init: bool,
    pub input: Option<PathBuf>,
    pub output: Option<PathBuf>,
}

/// The usage text LinuxCNC's rs274 prints.
pub fn usage(program: &str) -> String {
    format!(
        "Usage: {program} [-p interp.so] [-t tool.tbl] [-v var-file.var] [-n 0|1|2]\n\
         \x20         [-b] [-s] [-g] [input file [output file]]\n\
         \n\
         \x20   -p: Specify the pluggable interpreter to use\n\
         \x20   -t: Specify the .tbl (tool table) file to use\n\
         \x20   -v: Specify the .var (parameter) file to use\n\
         \x20   -n: Specify the continue mode:\n\
         \x20          0: continue\n\
         \x20          1: enter MDI mode\n\
         \x20          2: stop (default)\n\
         \x20   -b: Toggle the 'block delete' flag (default: OFF)\n\
         \x20   -s: Toggle the 'print stack' flag (default: OFF)\n\
         \x20   -g: Toggle the 'go (batch mode)' flag (default: OFF)\n\
         \x20   -i: specify the INI file (default: no INI file)\n\
         \x20   -T: call task_init()\n\
         \x20   -l: specify the log_level (default: -1)\n"
    )
}

/// C's `atoi`: optional blanks and sign, then digits; 0 if none.
fn atoi(bytes: &[u8]) -> i64 {
    let mut rest = bytes
        .iter()
        .skip_while(|b| b.is_ascii_whitespace())
        .peekable();
    let negative = match rest.peek() {
        Some(b'-') => {
            rest.next();
            true
        }
        Some(b'+') => {
            rest.next();
            false
        }
        _ => false,
    };
    let mut value: i64 = 0;
    for b in rest.take_while(|b| b.is_ascii_digit()) {
        value = value.saturating_mul(10).saturating_add(i64::from(b - b'0'));
    }
    if negative {
        -value
    } else {
        value
    }
}

/// Set the option `letter` that takes a value.
fn set_valued(args: &mut Args, letter: u8, value: OsString) {
    match letter {
        b'p' => args.plugin = Some(value.to_string_lossy().into_owned()),
        b't' => args.tool_table = Some(PathBuf::from(value)),
        b'v' => args.parameter_file = Some(PathBuf::from(value)),
        b'i' => args.ini = Some(PathBuf::from(value)),
        b'n' => {
            args.on_error = match atoi(value.as_bytes()) {
                1 => OnError::Mdi,
                2 => OnError::Stop,
                _ => OnError::Continue,
            }
        }
        _ => {}
    }
}

/// Parse `argv`; `Err(())` means print the usage and exit 1.
pub fn parse(argv: &[OsString]) -> Result<Args, ()> {
    let mut args = Args {
        plugin: None,
        tool_table: None,
        parameter_file: None,
        ini: None,
        on_error: OnError::Stop,
        block_delete: false,
        print_stack: false,
        go: false,
        task_init: false,
        input: None,
        output: None,
    };
    let program = argv
        .first()
        .map(|p| p.to_string_lossy().into_owned())
        .unwrap_or_else(|| "rs274".into());
    let mut i = 1;
    let mut positional = Vec::new();
    while i < argv.len() {
        let word = argv[i].as_bytes();
        i += 1;
        if word == b"--" {
            positional.extend(argv[i..].iter().cloned());
            break;
        }
        if !word.starts_with(b"-") || word == b"-" {
            positional.push(argv[i - 1].clone());
            continue;
        }
        let mut k = 1;
        while k < word.len() {
            let c = word[k];
            k += 1;
            if matches!(c, b'p' | b't' | b'v' | b'n' | b'i' | b'l') {
                let value = if k < word.len() {
                    let v = OsString::from_vec(word[k..].to_vec());
                    k = word.len();
                    v
                } else if i < argv.len() {
                    i += 1;
                    argv[i - 1].clone()
                } else {
                    eprintln!("{program}: option requires an argument -- '{}'", c as char);
                    return Err(());
                };
                set_valued(&mut args, c, value);
                continue;
            }
            match c {
                b'b' => args.block_delete = !args.block_delete,
                b's' => args.print_stack = !args.print_stack,
                b'g' => args.go = !args.go,
                b'T' => args.task_init = true,
                _ => {
                    eprintln!(
                        "{program}: invalid option -- '{}'",
                        String::from_utf8_lossy(&[c])
                    );
                    return Err(());
                }
            }
        }
    }
    if positional.len() > 2 {
        return Err(());
    }
    let mut positional = positional.into_iter();
    args.input = positional.next().map(PathBuf::from);
    args.output = positional.next().map(PathBuf::from);
    Ok(args)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn argv(words: &[&str]) -> Vec<OsString> {
        words.iter().map(OsString::from).collect()
    }

    #[test]
    fn options_and_files() {
        let a = parse(&argv(&[
            "rs274", "-t", "t.tbl", "-gb", "-n0", "p.ngc", "o.txt",
        ]))
        .unwrap();
        assert_eq!(a.tool_table, Some(PathBuf::from("t.tbl")));
        assert!(a.go && a.block_delete);
        assert_eq!(a.on_error, OnError::Continue);
        assert_eq!(a.input, Some(PathBuf::from("p.ngc")));
        assert_eq!(a.output, Some(PathBuf::from("o.txt")));
        assert!(parse(&argv(&["rs274", "-x"])).is_err());
        assert!(parse(&argv(&["rs274", "a", "b", "c"])).is_err());
        assert!(parse(&argv(&["rs274", "-t"])).is_err());
        assert_eq!(
            parse(&argv(&["rs274", "-n", "2x"])).unwrap().on_error,
            OnError::Stop
        );
        assert_eq!(
            parse(&argv(&["rs274", "-n", " 1"])).unwrap().on_error,
            OnError::Mdi
        );
        let odd = OsString::from_vec(vec![b'p', 0xff, b'.', b'n']);
        let a = parse(&[OsString::from("rs274"), odd.clone()]).unwrap();
        assert_eq!(a.input, Some(PathBuf::from(odd)));
    }
}
