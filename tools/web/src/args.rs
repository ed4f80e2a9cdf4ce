//! hal-web's command line and help.

use std::net::{IpAddr, Ipv4Addr, SocketAddr};

use hal_tools::conventions::{common, Common};

use crate::WebError;

/// The port hal-web listens on unless `--port` says otherwise.
pub const DEFAULT_PORT: u16 = 8338;

/// `hal-web --help`; the man page is made from it too.
pub const USAGE: &str = "\
usage: hal-web [-i NAME] [--port PORT] [--listen ADDRESS] [--token] [--read-only]
       hal-web -h | --version

Serves a running HAL instance in a browser: its pins, parameters, signals
(with writer and readers), functions and threads as a tree with live
values, watch lists, meters (value, min and max), a scope (halscope's
sampler and trigger: level, edge, pre-trigger; single, normal and auto
modes; CSV and PNG), thread timing with live latency histograms,
setp/sets/net/unlinkp through halcmd's own checks, and, when a machine
runs on the instance (linuxcnc MACHINE.ini), its task state with the
e-stop, machine-on, home, run, pause and abort buttons. Start it on its
own against a running instance, with `loadusr -W hal-web`, or from the
machine's INI file: [HAL]HALWEB = hal-web [OPTIONS] (linuxcnc starts it
after the POSTGUI_HALFILEs). It prints the address it serves once it
listens.

It listens on 127.0.0.1 only unless --listen names another address; then
(or with --token) every request must carry the access token in the
X-HAL-Token header. The token is made afresh at each start, printed once
(on a terminal) and stored, readable by its owner only, as
hal-NAME.web-token in the private runtime directory. Every change also
needs a same-origin request from the page, and so does a scope capture
(it adds a sampler to the thread while it records); --read-only allows
captures only through a sampler channel the HAL file loaded.

options:
  -i, --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -p, --port PORT      the TCP port (default 8338; 0 picks a free one)
  --listen ADDRESS     listen on ADDRESS instead of 127.0.0.1; a token is then required
  --token              require the access token on the loopback address too
  --read-only          refuse every change to the HAL and the machine
  -h, --help           print this help and exit
  --version            print the version and exit

examples:
  hal-web                      serve the default instance on http://127.0.0.1:8338/
  hal-web --read-only -p 8400  a view that changes nothing, on port 8400
  hal-web --listen 0.0.0.0     every address of the machine, with the token

from a laptop:
  ssh -L 8338:127.0.0.1:8338 MACHINE
                               then open http://localhost:8338/ on the laptop";

/// What the command line asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Options {
    /// Where to listen.
    pub addr: SocketAddr,
    /// Whether requests must carry the access token.
    pub token: bool,
    /// Whether changes are refused.
    pub read_only: bool,
}

/// What to do after reading the command line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Command {
    /// Serve with these options.
    Serve(Options),
    /// Print the help.
    Help,
    /// Print the version.
    Version,
}

/// Reads hal-web's command line (without the program name). `-i` selects
/// the instance as in every tool of the suite.
pub fn parse(args: &[String]) -> Result<Command, WebError> {
    let mut ip = IpAddr::V4(Ipv4Addr::LOCALHOST);
    let mut port = DEFAULT_PORT;
    let mut token = false;
    let mut read_only = false;
    let mut i = 0;
    while i < args.len() {
        match common(args, i, true).map_err(|e| WebError::usage(e.to_string()))? {
            Some(Common::Help) => return Ok(Command::Help),
            Some(Common::Version) => return Ok(Command::Version),
            Some(Common::Instance(_, n)) => {
                i += n;
                continue;
            }
            None => {}
        }
        let value = args.get(i + 1).map(String::as_str);
        match args[i].as_str() {
            "-p" | "--port" => {
                let text = value.ok_or_else(|| WebError::usage("--port needs a port number"))?;
                port = text.parse().map_err(|_| {
                    WebError::usage(format!(
                        "--port: '{text}' is not a port number (0 to 65535)"
                    ))
                })?;
                i += 1;
            }
            "--listen" => {
                let text = value.ok_or_else(|| WebError::usage("--listen needs an address"))?;
                ip = text.parse().map_err(|_| {
                    WebError::usage(format!(
                        "--listen: '{text}' is not an IP address (such as 0.0.0.0 or 192.168.1.5)"
                    ))
                })?;
                i += 1;
            }
            "--token" => token = true,
            "--read-only" => read_only = true,
            other => {
                return Err(WebError::usage(format!(
                    "unknown option or word '{other}' (see hal-web --help)"
                )))
            }
        }
        i += 1;
    }
    Ok(Command::Serve(Options {
        addr: SocketAddr::new(ip, port),
        token: token || !ip.is_loopback(),
        read_only,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(w: &[&str]) -> Vec<String> {
        w.iter().map(|s| s.to_string()).collect()
    }

    fn serve(w: &[&str]) -> Options {
        match parse(&words(w)).unwrap() {
            Command::Serve(o) => o,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn loopback_needs_no_token_and_another_address_does() {
        let o = serve(&[]);
        assert_eq!(o.addr.to_string(), "127.0.0.1:8338");
        assert!(!o.token && !o.read_only);
        let o = serve(&["--listen", "0.0.0.0", "-p", "0", "--read-only"]);
        assert_eq!(o.addr.to_string(), "0.0.0.0:0");
        assert!(o.token && o.read_only);
        assert!(serve(&["--token"]).token);
        assert!(serve(&["--listen", "::1"]).addr.ip().is_loopback());
    }

    #[test]
    fn bad_words_are_named() {
        let e = |w: &[&str]| parse(&words(w)).unwrap_err().to_string();
        assert!(e(&["--port", "x"]).contains("'x' is not a port number"));
        assert!(e(&["--port"]).contains("needs a port"));
        assert!(e(&["--listen", "host"]).contains("'host' is not an IP address"));
        assert!(e(&["--frob"]).contains("'--frob'"));
        assert_eq!(parse(&words(&["-h"])).unwrap(), Command::Help);
        assert_eq!(parse(&words(&["--version"])).unwrap(), Command::Version);
    }
}
