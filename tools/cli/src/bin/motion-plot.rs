//! `motion-plot`: the plot and one-line summary of a sampled motion run
//! (see `--help`).

use std::process::ExitCode;

use clap::Parser;
use hal_scope::motion_plot::{parse_samples, plot, summarize};
use hal_tools::tool_args::motion_plot::Args;

fn main() -> ExitCode {
    let a = Args::parse();
    if !(a.period.is_finite() && a.period > 0.0) {
        eprintln!("motion-plot: --period must be a positive number of seconds");
        return ExitCode::from(2);
    }
    let text = match hal_core::files::read_user_text(
        std::path::Path::new(&a.samples),
        hal_core::files::limits::SAMPLES,
        "sample file",
    ) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("motion-plot: {e}");
            return ExitCode::from(2);
        }
    };
    let s = match parse_samples(&a.samples, &text) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("motion-plot: {e}");
            return ExitCode::from(2);
        }
    };
    let f = summarize(&s, a.period);
    if let Some(png) = &a.png {
        let title = a.title.unwrap_or_else(|| a.samples.to_uppercase());
        if let Err(e) = plot(&s, a.period, &title, png) {
            eprintln!("motion-plot: {e}");
            return ExitCode::from(1);
        }
    }
    println!(
        "{:.3} s, max following error {:.4} {u}, max speed {:.3} {u}/s (measured {:.3} {u}/s), max axis acceleration {:.1} {u}/s^2{}",
        f.seconds,
        f.max_ferror,
        f.max_speed,
        f.max_measured_speed,
        f.max_acc,
        a.png.map_or(String::new(), |p| format!(", plot {p}")),
        u = a.units,
    );
    ExitCode::SUCCESS
}
