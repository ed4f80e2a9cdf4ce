//! linuxcncrsh's command line (LinuxCNC's options).

use std::path::PathBuf;

/// linuxcncrsh: answers LinuxCNC's text protocol for remote control on a
/// TCP port (hello, get, set, help, quit, shutdown), driving the running
/// machine's task. Started by `linuxcnc` when [DISPLAY]DISPLAY =
/// linuxcncrsh; `shutdown` from an enabled session ends it and with it
/// the machine.
#[derive(Debug, clap::Parser)]
#[command(
    name = "linuxcncrsh",
    version,
    after_help = "A client sends `hello PASSWORD CLIENT VERSION`, then `set enable PASSWORD` to
command the machine; `help get` lists the subcommands of get and set. Replies
end with CR LF: `NAME VALUE` for a get, `SET NAME ACK` (with `set verbose on`)
or `SET NAME NAK` for a set, `GET NAME NAK` for what cannot be got, `ERROR OK`
or the reason for `get error`.

Examples:
  linuxcncrsh -ini mill.ini --port 6000
  printf 'hello EMC me 1.0\\nget plat\\nquit\\n' | nc localhost 5007"
)]
pub struct Args {
    /// The TCP port to listen on.
    #[arg(short = 'p', long, default_value_t = 5007)]
    pub port: u16,
    /// The server name `hello` answers with.
    #[arg(short = 'n', long, default_value = "EMCNETSVR")]
    pub name: String,
    /// The password `hello` needs.
    #[arg(short = 'w', long, default_value = "EMC")]
    pub connectpw: String,
    /// The password `set enable` needs.
    #[arg(short = 'e', long, default_value = "EMCTOO")]
    pub enablepw: String,
    /// The most connections at once; -1 for no bound.
    #[arg(short = 's', long, default_value_t = -1, allow_negative_numbers = true)]
    pub sessions: i64,
    /// The directory a relative `set open` file is taken from (default:
    /// the INI file's directory, where task runs).
    #[arg(short = 'd', long)]
    pub path: Option<PathBuf>,
    /// The machine's INI file (LinuxCNC's `-ini FILE`, also after `--`);
    /// default: $INI_FILE_NAME.
    #[arg(long = "ini", value_name = "FILE")]
    pub ini: Option<PathBuf>,
}

/// The command line with LinuxCNC's single-dash `-ini` (and the `--`
/// that may come before it) in clap's spelling. Arguments that are not
/// UTF-8 pass through untouched, for clap to refuse with its message.
pub fn normalise<A: Into<std::ffi::OsString>>(
    args: impl IntoIterator<Item = A>,
) -> Vec<std::ffi::OsString> {
    let mut out = Vec::new();
    let mut it = args.into_iter().map(Into::into).peekable();
    while let Some(a) = it.next() {
        if a == "--" && it.peek().is_some_and(|n| n == "-ini") {
            continue;
        }
        out.push(if a == "-ini" { "--ini".into() } else { a });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[test]
    fn linuxcncs_spellings_are_taken() {
        let argv = |s: &str| normalise(s.split(' ').map(String::from));
        let a = Args::try_parse_from(argv("linuxcncrsh -p 6000 -- -ini /m/x.ini")).unwrap();
        assert_eq!((a.port, a.ini.unwrap()), (6000, PathBuf::from("/m/x.ini")));
        let a = Args::try_parse_from(argv("linuxcncrsh -ini a.ini --sessions 2 -n S")).unwrap();
        assert_eq!((a.sessions, a.name.as_str()), (2, "S"));
        assert_eq!(
            Args::try_parse_from(argv("linuxcncrsh")).unwrap().sessions,
            -1
        );
        assert!(Args::try_parse_from(argv("linuxcncrsh --port 99999")).is_err());
    }
}
