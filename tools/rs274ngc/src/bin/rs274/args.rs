//! rs274's options, parsed as getopt("p:t:v:bsn:gi:Tl:") does: options
//! before the file names, letters may be grouped (`-gb`), an option's
//! value may follow it or be the next word.

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

/// Parse `argv`; `Err(())` means print the usage and exit 1.
pub fn parse(argv: &[String]) -> Result<Args, ()> {
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
    let program = argv.first().map(String::as_str).unwrap_or("rs274");
    let mut i = 1;
    let mut positional = Vec::new();
    while i < argv.len() {
        let word = &argv[i];
        i += 1;
        if word == "--" {
            positional.extend(argv[i..].iter().cloned());
            break;
        }
        if !word.starts_with('-') || word == "-" {
            positional.push(word.clone());
            continue;
        }
        let letters: Vec<char> = word[1..].chars().collect();
        let mut k = 0;
        while k < letters.len() {
            let c = letters[k];
            k += 1;
            if matches!(c, 'p' | 't' | 'v' | 'n' | 'i' | 'l') {
                let value = if k < letters.len() {
                    let v: String = letters[k..].iter().collect();
                    k = letters.len();
                    v
                } else if i < argv.len() {
                    i += 1;
                    argv[i - 1].clone()
                } else {
                    eprintln!("{program}: option requires an argument -- '{c}'");
                    return Err(());
                };
                match c {
                    'p' => args.plugin = Some(value),
                    't' => args.tool_table = Some(PathBuf::from(value)),
                    'v' => args.parameter_file = Some(PathBuf::from(value)),
                    'i' => args.ini = Some(PathBuf::from(value)),
                    'n' => {
                        args.on_error = match value.trim().parse::<i64>().unwrap_or(0) {
                            1 => OnError::Mdi,
                            2 => OnError::Stop,
                            _ => OnError::Continue,
                        }
                    }
                    _ => {}
                }
                continue;
            }
            match c {
                'b' => args.block_delete = !args.block_delete,
                's' => args.print_stack = !args.print_stack,
                'g' => args.go = !args.go,
                'T' => args.task_init = true,
                _ => {
                    eprintln!("{program}: invalid option -- '{c}'");
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

    fn argv(words: &[&str]) -> Vec<String> {
        words.iter().map(|s| s.to_string()).collect()
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
    }
}
