//! A sampled motion run (one line per servo period: commanded X Y Z,
//! measured X Y Z, following errors of joints 0..2, as `halsampler`
//! prints them), its one-line summary and its plot: the commanded and
//! measured tool path in XY, and the path speed over time.

use plotters::prelude::*;

use crate::error::ScopeError;
use crate::plot;

/// One servo period's sample.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sample {
    /// Commanded X Y Z.
    pub cmd: [f64; 3],
    /// Measured X Y Z.
    pub fb: [f64; 3],
    /// Following error of joints 0, 1, 2.
    pub ferror: [f64; 3],
}

/// Reads halsampler's text.
pub fn parse_samples(file: &str, text: &str) -> Result<Vec<Sample>, ScopeError> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let v: Vec<f64> = line
            .split_whitespace()
            .map(str::parse)
            .collect::<Result<_, _>>()
            .map_err(|_| ScopeError::BadLine {
                file: file.into(),
                line: i + 1,
            })?;
        if v.len() != 9 || v.iter().any(|x| !x.is_finite()) {
            return Err(ScopeError::BadLine {
                file: file.into(),
                line: i + 1,
            });
        }
        out.push(Sample {
            cmd: [v[0], v[1], v[2]],
            fb: [v[3], v[4], v[5]],
            ferror: [v[6], v[7], v[8]],
        });
    }
    if out.is_empty() {
        return Err(ScopeError::Empty { file: file.into() });
    }
    Ok(out)
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Figures of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Summary {
    /// Duration, seconds.
    pub seconds: f64,
    /// Largest |following error| of any joint.
    pub max_ferror: f64,
    /// Largest commanded path speed.
    pub max_speed: f64,
    /// Largest commanded acceleration of any axis.
    pub max_acc: f64,
    /// Largest measured path speed (over 40 periods: the steps are
    /// coarse).
    pub max_measured_speed: f64,
}

/// The commanded path speed per period (the first is 0).
fn cmd_speed(s: &[Sample], period: f64) -> Vec<f64> {
    let mut v = vec![0.0];
    v.extend(s.windows(2).map(|w| dist(w[1].cmd, w[0].cmd) / period));
    v
}

/// The measured path speed over 40 periods (steppers move in steps).
fn fb_speed(s: &[Sample], period: f64) -> Vec<f64> {
    const W: usize = 40;
    (0..s.len())
        .map(|k| {
            let a = k.saturating_sub(W);
            if k == a {
                0.0
            } else {
                dist(s[k].fb, s[a].fb) / ((k - a) as f64 * period)
            }
        })
        .collect()
}

/// The figures of a run sampled every `period` seconds.
pub fn summarize(s: &[Sample], period: f64) -> Summary {
    let mut max_acc: f64 = 0.0;
    for w in s.windows(3) {
        for i in 0..3 {
            let a = (w[2].cmd[i] - 2.0 * w[1].cmd[i] + w[0].cmd[i]) / (period * period);
            max_acc = max_acc.max(a.abs());
        }
    }
    let fold = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(*x));
    Summary {
        seconds: s.len() as f64 * period,
        max_ferror: s
            .iter()
            .flat_map(|x| x.ferror)
            .fold(0.0f64, |m, x| m.max(x.abs())),
        max_speed: fold(&cmd_speed(s, period)),
        max_acc,
        max_measured_speed: fold(&fb_speed(s, period)),
    }
}

/// Draws the run into a PNG file at `path`.
pub fn plot(s: &[Sample], period: f64, title: &str, path: &str) -> Result<(), ScopeError> {
    let file = path;
    let root = plot::png(path, (1400, 640)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| ScopeError::plot(file, e))?;
    let root = root
        .titled(title, ("sans-serif", 22))
        .map_err(|e| ScopeError::plot(file, e))?;
    let (left, right) = root.split_horizontally(640);

    // The path, with equal scales on both axes.
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in s.iter().flat_map(|x| [x.cmd, x.fb]) {
        x0 = x0.min(p[0]);
        x1 = x1.max(p[0]);
        y0 = y0.min(p[1]);
        y1 = y1.max(p[1]);
    }
    let span = (x1 - x0).max(y1 - y0).max(1e-6) * 1.08;
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let mut path = ChartBuilder::on(&left)
        .caption(
            "TOOL PATH XY: COMMANDED (BLUE), MEASURED (RED)",
            ("sans-serif", 16),
        )
        .margin(12)
        .x_label_area_size(34)
        .y_label_area_size(60)
        .build_cartesian_2d(
            cx - span / 2.0..cx + span / 2.0,
            cy - span / 2.0..cy + span / 2.0,
        )
        .map_err(|e| ScopeError::plot(file, e))?;
    path.configure_mesh()
        .x_desc("X")
        .y_desc("Y")
        .draw()
        .map_err(|e| ScopeError::plot(file, e))?;
    path.draw_series(LineSeries::new(
        s.iter().map(|x| (x.fb[0], x.fb[1])),
        RED.stroke_width(3),
    ))
    .map_err(|e| ScopeError::plot(file, e))?;
    path.draw_series(LineSeries::new(
        s.iter().map(|x| (x.cmd[0], x.cmd[1])),
        &BLUE,
    ))
    .map_err(|e| ScopeError::plot(file, e))?;

    // Speed over time.
    let vc = cmd_speed(s, period);
    let vf = fb_speed(s, period);
    let vmax = vc
        .iter()
        .chain(&vf)
        .fold(0.0f64, |m, x| m.max(*x))
        .max(1e-6)
        * 1.1;
    let tmax = s.len() as f64 * period;
    let mut speed = ChartBuilder::on(&right)
        .caption(
            "PATH SPEED: COMMANDED (BLUE), MEASURED (RED)",
            ("sans-serif", 16),
        )
        .margin(12)
        .x_label_area_size(34)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..tmax, 0.0..vmax)
        .map_err(|e| ScopeError::plot(file, e))?;
    speed
        .configure_mesh()
        .x_desc("TIME S")
        .y_desc("UNITS/S")
        .draw()
        .map_err(|e| ScopeError::plot(file, e))?;
    let t = |k: usize| k as f64 * period;
    speed
        .draw_series(LineSeries::new(
            vf.iter().enumerate().map(|(k, v)| (t(k), *v)),
            &RED,
        ))
        .map_err(|e| ScopeError::plot(file, e))?;
    speed
        .draw_series(LineSeries::new(
            vc.iter().enumerate().map(|(k, v)| (t(k), *v)),
            &BLUE,
        ))
        .map_err(|e| ScopeError::plot(file, e))?;
    root.present().map_err(|e| ScopeError::plot(file, e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_of_a_straight_run() {
        // 1 unit/s along X, then at rest; measured one period late.
        let text: String = (0usize..200)
            .map(|k| {
                let x = (k.min(100) as f64) * 0.001;
                let fb = (k.saturating_sub(1).min(100) as f64) * 0.001;
                format!("{x} 0 0 {fb} 0 0 {} 0 0\n", x - fb)
            })
            .collect();
        let s = parse_samples("run", &text).unwrap();
        let f = summarize(&s, 0.001);
        assert!((f.seconds - 0.2).abs() < 1e-12);
        assert!((f.max_speed - 1.0).abs() < 1e-9);
        assert!((f.max_ferror - 0.001).abs() < 1e-12);
        assert!((f.max_acc - 1000.0).abs() < 1e-6, "the step at the start");
        let png = std::env::temp_dir().join(format!("run-plot-{}.png", std::process::id()));
        plot(&s, 0.001, "TEST", png.to_str().unwrap()).unwrap();
        let bytes = std::fs::read(&png).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        let _ = std::fs::remove_file(&png);
        assert_eq!(
            parse_samples("run", "1 2 3\n").unwrap_err().to_string(),
            "run:1: expected nine numbers (X Y Z commanded, X Y Z measured, three following errors)"
        );
    }
}
