//! `canservo-tool`: bring up CANopen CiA 402 servo drives: scan the bus,
//! read and write objects, show and step the power state, send NMT
//! commands, watch the traffic decoded. Exit status: 0 done, 1 the
//! drive or bus said no (the message says what), 2 usage.

use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use hal_canservo::tool::{Step, Tool, WatchOptions, STEPS};
use hal_canservo::Error;

use hal_canservo::tool_args::{Cli, Cmd};

fn run(cli: Cli) -> Result<Vec<String>, Error> {
    let timeout = Duration::from_millis(cli.timeout_ms.max(1));
    let tool = if cli.sim.is_empty() {
        Tool::socket(&cli.iface, timeout)?
    } else {
        Tool::sim(&cli.sim, timeout)
    };
    match cli.command {
        Cmd::Scan { reset } => tool.scan(reset),
        Cmd::Read { node, object, ty } => tool.read(node, &object, ty.as_deref()).map(|l| vec![l]),
        Cmd::Write {
            node,
            object,
            ty,
            value,
        } => tool.write(node, &object, &ty, &value).map(|l| vec![l]),
        Cmd::Status { node } => tool.status(node),
        Cmd::Power { node, step } => {
            let s = Step::parse(&step).ok_or(Error::NotAStep {
                name: step,
                steps: STEPS,
            })?;
            tool.power(node, s).map(|states| vec![states.join(" -> ")])
        }
        Cmd::Nmt { node, command } => tool.nmt(node, &command).map(|l| vec![l]),
        Cmd::Watch {
            nodes,
            read_mapping,
            start,
            sync_ms,
            count,
            seconds,
        } => {
            if count.is_none() && seconds.is_none() && !cli.sim.is_empty() {
                return Err(Error::WatchWithoutEnd);
            }
            let opts = WatchOptions {
                nodes,
                read_mapping,
                start,
                sync: sync_ms.map(Duration::from_millis),
                count,
                duration: seconds.map(Duration::from_secs_f64),
            };
            tool.watch(&opts, |line| println!("{line}"))?;
            Ok(Vec::new())
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(lines) => {
            for l in lines {
                println!("{l}");
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("canservo-tool: {e}");
            ExitCode::from(1)
        }
    }
}
