//! The histogram PNG: one panel per thread, one bar per histogram bucket
//! on a log scale of counts, LinuxCNC's thresholds marked.

use hal_core::{latency_bucket, latency_bucket_floor_us};
use plotters::prelude::*;

use super::report::period_text;
use super::stats::ThreadStats;
use crate::error::ScopeError;
use crate::plot;

/// The colour of the bars.
pub const BAR_COLOR: RGBColor = RGBColor(30, 90, 200);

/// Where a bar was drawn, in image pixels (for checks of the image).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bar {
    /// Index of the thread (panel).
    pub thread: usize,
    /// Histogram bucket.
    pub bucket: usize,
    /// Left, top, right, bottom pixel of the bar.
    pub rect: (i32, i32, i32, i32),
}

/// What was drawn: the bars of non-empty buckets, and the pixel columns
/// of the empty buckets shown (x centre, y top and bottom of the plot).
#[derive(Debug, Clone, Default)]
pub struct Drawn {
    /// Bars of buckets with counts.
    pub bars: Vec<Bar>,
    /// Empty buckets shown: (thread, bucket, x, y range of the plot).
    pub empty: Vec<(usize, usize, i32, (i32, i32))>,
}

/// Image size in pixels.
pub const SIZE: (u32, u32) = (1000, 360);

/// Buckets shown: up to one past the highest non-empty bucket of any
/// thread, and at least as far as the 50 µs threshold.
fn shown_buckets(threads: &[ThreadStats]) -> usize {
    let top = threads
        .iter()
        .filter_map(|t| t.histogram.iter().rposition(|&n| n > 0))
        .max()
        .unwrap_or(0);
    let len = threads.iter().map(|t| t.histogram.len()).max().unwrap_or(0);
    (top + 2).max(latency_bucket(50_000) + 2).min(len.max(1))
}

/// The x position (in buckets) of a latency of `ns`.
fn x_of(ns: u64) -> f64 {
    let b = latency_bucket(ns);
    let lo = latency_bucket_floor_us(b) as f64;
    let hi = latency_bucket_floor_us(b + 1) as f64;
    b as f64 + ((ns as f64 / 1000.0 - lo) / (hi - lo)).clamp(0.0, 1.0)
}

/// Draws the histograms of `threads` into a PNG at `path`, titled
/// `title`. Returns where the bars went.
pub fn draw(threads: &[ThreadStats], title: &str, path: &str) -> Result<Drawn, ScopeError> {
    let n = threads.len().max(1);
    let height = SIZE.1 * n as u32 + 40;
    let root = plot::png(path, (SIZE.0, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| ScopeError::plot(path, e))?;
    let root = root
        .titled(title, ("sans-serif", 20))
        .map_err(|e| ScopeError::plot(path, e))?;
    let panels = root.split_evenly((n, 1));
    let nb = shown_buckets(threads);
    let mut drawn = Drawn::default();
    for (i, (t, area)) in threads.iter().zip(panels.iter()).enumerate() {
        let top = t.histogram.iter().copied().max().unwrap_or(0).max(1) as f64;
        let caption = format!(
            "{} ({}): MIN {} MAX {} US, {} CYCLES, {} OVERRUNS",
            t.name,
            period_text(t.period_ns),
            t.min_ns
                .map_or("-".into(), |v| format!("{:.1}", v as f64 / 1e3)),
            t.max_ns
                .map_or("-".into(), |v| format!("{:.1}", v as f64 / 1e3)),
            t.cycles,
            t.overruns
        );
        let mut chart = ChartBuilder::on(area)
            .caption(caption, ("sans-serif", 16))
            .margin(10)
            .x_label_area_size(36)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..nb as f64, (0.5..top * 2.0).log_scale())
            .map_err(|e| ScopeError::plot(path, e))?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(nb / 2 + 1)
            .x_label_formatter(&|x| {
                if (x - x.round()).abs() < 1e-6 && *x >= 0.0 {
                    latency_bucket_floor_us(x.round() as usize).to_string()
                } else {
                    String::new()
                }
            })
            .y_label_formatter(&|y| format!("{y:.0}"))
            .x_desc("LATENCY US (BUCKET EDGES)")
            .y_desc("WAKE-UPS")
            .draw()
            .map_err(|e| ScopeError::plot(path, e))?;
        for (limit, label) in [(20_000u64, "20 US"), (50_000, "50 US"), (500_000, "500 US")] {
            let x = x_of(limit);
            if x < nb as f64 {
                chart
                    .draw_series(LineSeries::new(
                        [(x, 0.5), (x, top * 2.0)],
                        RED.stroke_width(1),
                    ))
                    .map_err(|e| ScopeError::plot(path, e))?;
                chart
                    .draw_series([Text::new(
                        label,
                        (x + 0.1, top * 1.5),
                        ("sans-serif", 12).into_font().color(&RED),
                    )])
                    .map_err(|e| ScopeError::plot(path, e))?;
            }
        }
        for b in 0..nb {
            let count = t.histogram.get(b).copied().unwrap_or(0);
            let (x0, x1) = (b as f64 + 0.1, b as f64 + 0.9);
            if count == 0 {
                let (x, y_top) = chart.backend_coord(&(b as f64 + 0.5, top * 2.0));
                let (_, y_bottom) = chart.backend_coord(&(b as f64 + 0.5, 0.5));
                drawn.empty.push((i, b, x, (y_top, y_bottom)));
                continue;
            }
            chart
                .draw_series([Rectangle::new(
                    [(x0, 0.5), (x1, count as f64)],
                    BAR_COLOR.filled(),
                )])
                .map_err(|e| ScopeError::plot(path, e))?;
            let (l, tp) = chart.backend_coord(&(x0, count as f64));
            let (r, bt) = chart.backend_coord(&(x1, 0.5));
            drawn.bars.push(Bar {
                thread: i,
                bucket: b,
                rect: (l, tp, r, bt),
            });
        }
    }
    root.present().map_err(|e| ScopeError::plot(path, e))?;
    Ok(drawn)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stats(name: &str, hist: &[(usize, u64)]) -> ThreadStats {
        let mut histogram = vec![0u64; 64];
        for &(b, n) in hist {
            histogram[b] = n;
        }
        ThreadStats {
            name: name.into(),
            period_ns: 25_000,
            cycles: histogram.iter().sum(),
            overruns: 0,
            min_ns: Some(1_500),
            max_ns: Some(30_000),
            histogram,
        }
    }

    #[test]
    fn one_bar_per_non_empty_bucket_taller_for_more_wake_ups() {
        let threads = [
            stats("base-thread", &[(1, 1000), (2, 10), (20, 1)]),
            stats("servo-thread", &[(3, 5)]),
        ];
        let path = std::env::temp_dir().join(format!("histplot-{}.png", std::process::id()));
        let drawn = draw(&threads, "TEST", path.to_str().unwrap()).unwrap();
        let png = std::fs::read(&path).unwrap();
        let _ = std::fs::remove_file(&path);
        assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"));
        let buckets: Vec<(usize, usize)> =
            drawn.bars.iter().map(|b| (b.thread, b.bucket)).collect();
        assert_eq!(buckets, [(0, 1), (0, 2), (0, 20), (1, 3)]);
        let height = |i: usize| drawn.bars[i].rect.3 - drawn.bars[i].rect.1;
        // Log scale: 1000 wake-ups stand taller than 10, 10 taller than 1.
        assert!(
            height(0) > height(1) && height(1) > height(2),
            "{:?}",
            drawn.bars
        );
        // Every bucket up to the 50 us threshold is shown, empty or not.
        let shown = shown_buckets(&threads);
        assert!(shown > latency_bucket(50_000));
        assert_eq!(drawn.bars.len() + drawn.empty.len(), 2 * shown);
    }
}
