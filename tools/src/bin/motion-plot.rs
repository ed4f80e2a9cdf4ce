//! `motion-plot`: the plot and one-line summary of a sampled motion run
//! (see `--help`).

use std::process::ExitCode;

use clap::Parser;
use hal_tools::run_plot::{parse_samples, plot, summarize};

/// Plots a sampled motion run into a PNG file (commanded and measured
/// tool path in XY, path speed over time) and prints a one-line summary:
/// duration, largest following error, largest commanded speed and axis
/// acceleration, largest measured speed.
///
/// The samples are halsampler's output, one servo period per line: X Y Z
/// commanded, X Y Z measured, following errors of joints 0, 1, 2.
#[derive(Debug, Parser)]
#[command(
    name = "motion-plot",
    version,
    after_help = "Examples:
  halsampler -n 5000 > run.samples && motion-plot run.samples run.png
  motion-plot --period 0.0005 --title \"POCKET\" run.samples pocket.png
  motion-plot run.samples                 only the summary"
)]
struct Args {
    /// The samples file.
    samples: String,
    /// The PNG file to write (none: only the summary).
    png: Option<String>,
    /// Seconds between samples (the servo period).
    #[arg(long, default_value_t = 0.001)]
    period: f64,
    /// The plot's title (default: the samples file's name).
    #[arg(long)]
    title: Option<String>,
}

fn main() -> ExitCode {
    let a = Args::parse();
    if !(a.period.is_finite() && a.period > 0.0) {
        eprintln!("motion-plot: --period must be a positive number of seconds");
        return ExitCode::from(2);
    }
    let text = match std::fs::read_to_string(&a.samples) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("motion-plot: {}: {e}", a.samples);
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
        "{:.3} s, max following error {:.4}, max speed {:.3}/s (measured {:.3}/s), max axis acceleration {:.1}/s^2{}",
        f.seconds,
        f.max_ferror,
        f.max_speed,
        f.max_measured_speed,
        f.max_acc,
        a.png.map_or(String::new(), |p| format!(", plot {p}"))
    );
    ExitCode::SUCCESS
}
