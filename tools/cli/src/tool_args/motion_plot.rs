//! `motion-plot`'s command line (clap), here so the man page is built from it.

use clap::Parser;

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
  motion-plot --period 0.0005 --title \"POCKET\" --units mm run.samples pocket.png
  motion-plot run.samples                 only the summary"
)]
pub struct Args {
    /// The samples file.
    pub samples: String,
    /// The PNG file to write (none: only the summary).
    pub png: Option<String>,
    /// Seconds between samples (the servo period).
    #[arg(long, default_value_t = 0.001)]
    pub period: f64,
    /// The plot's title (default: the samples file's name).
    #[arg(long)]
    pub title: Option<String>,
    /// The machine's length unit, for the summary's speeds and
    /// accelerations ("mm", "inch").
    #[arg(long, value_name = "UNIT", default_value = "units")]
    pub units: String,
}
