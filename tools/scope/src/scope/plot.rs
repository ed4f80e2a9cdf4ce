//! The capture as a PNG: one panel per captured pin, time in ms with the
//! trigger at zero, bit pins drawn as logic traces.

use hal_core::HalType;
use plotters::prelude::*;

use super::capture::numeric;
use super::output::Record;
use crate::error::ScopeError;
use crate::plot;

/// Width of the image, and height of one panel, in pixels.
pub const PANEL: (u32, u32) = (1000, 180);
/// Height of a bit pin's panel.
pub const BIT_PANEL_HEIGHT: u32 = 110;

/// Trace colours, one per panel in turn.
const COLORS: [RGBColor; 4] = [
    RGBColor(30, 90, 200),
    RGBColor(0, 140, 60),
    RGBColor(180, 60, 0),
    RGBColor(120, 40, 160),
];

/// An axis label with up to three decimals, without a sign on zero.
fn axis_label(y: &f64) -> String {
    let s = format!("{y:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    match s {
        "-0" | "" => "0".to_string(),
        s => s.to_string(),
    }
}

/// Draws `r` into a PNG at `path` titled `title`.
pub fn draw(r: &Record, title: &str, path: &str) -> Result<(), ScopeError> {
    let heights: Vec<u32> = r
        .types
        .iter()
        .map(|t| {
            if *t == HalType::Bit {
                BIT_PANEL_HEIGHT
            } else {
                PANEL.1
            }
        })
        .collect();
    let total: u32 = heights.iter().sum::<u32>() + 40;
    let root = plot::png(path, (PANEL.0, total)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| ScopeError::plot(path, e))?;
    let mut area = root
        .titled(title, ("sans-serif", 18))
        .map_err(|e| ScopeError::plot(path, e))?;
    let t0 = r.time_ms(0);
    let t1 = r.time_ms(r.rows.len().saturating_sub(1)).max(t0 + 1e-9);
    for (m, (name, t)) in r.names.iter().zip(&r.types).enumerate() {
        let (panel, rest) = area.split_vertically(heights[m]);
        area = rest;
        let values: Vec<f64> = r.rows.iter().map(|row| numeric(*t, row[m + 1])).collect();
        let bit = *t == HalType::Bit;
        let (lo, hi) = if bit {
            (-0.25, 1.25)
        } else {
            let finite = values.iter().copied().filter(|v| v.is_finite());
            let lo = finite.clone().fold(f64::INFINITY, f64::min);
            let hi = finite.fold(f64::NEG_INFINITY, f64::max);
            if lo.is_finite() && hi > lo {
                let pad = (hi - lo) * 0.08;
                (lo - pad, hi + pad)
            } else if lo.is_finite() {
                (lo - 1.0, lo + 1.0)
            } else {
                (-1.0, 1.0)
            }
        };
        let mut chart = ChartBuilder::on(&panel)
            .margin(6)
            .x_label_area_size(if m + 1 == r.names.len() { 34 } else { 16 })
            .y_label_area_size(70)
            .caption(name.to_uppercase(), ("sans-serif", 14))
            .build_cartesian_2d(t0..t1, lo..hi)
            .map_err(|e| ScopeError::plot(path, e))?;
        let mut mesh = chart.configure_mesh();
        mesh.x_label_formatter(&|x| format!("{x:.2}"));
        if bit {
            mesh.y_labels(2)
                .y_label_formatter(&|y| if *y > 0.5 { "1".into() } else { "0".into() });
        } else {
            mesh.y_label_formatter(&axis_label);
        }
        if m + 1 == r.names.len() {
            mesh.x_desc("MS FROM TRIGGER");
        }
        mesh.draw().map_err(|e| ScopeError::plot(path, e))?;
        let color = COLORS[m % COLORS.len()];
        let points: Vec<(f64, f64)> = if bit {
            // A logic trace: hold each level until the next sample.
            let mut p = Vec::with_capacity(values.len() * 2);
            for (i, v) in values.iter().enumerate() {
                let t = r.time_ms(i);
                if let Some(&(_, prev)) = p.last() {
                    if prev != *v {
                        p.push((t, prev));
                    }
                }
                p.push((t, *v));
            }
            p
        } else {
            values
                .iter()
                .enumerate()
                .filter(|(_, v)| v.is_finite())
                .map(|(i, v)| (r.time_ms(i), *v))
                .collect()
        };
        chart
            .draw_series(LineSeries::new(points, color.stroke_width(2)))
            .map_err(|e| ScopeError::plot(path, e))?;
        if r.trigger_index > 0 || t0 < 0.0 {
            chart
                .draw_series(LineSeries::new([(0.0, lo), (0.0, hi)], RED.stroke_width(1)))
                .map_err(|e| ScopeError::plot(path, e))?;
        }
    }
    root.present().map_err(|e| ScopeError::plot(path, e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_labels_are_short_and_zero_has_no_sign() {
        assert_eq!(axis_label(&-0.00001), "0");
        assert_eq!(axis_label(&0.2), "0.2");
        assert_eq!(axis_label(&-1.0), "-1");
        assert_eq!(axis_label(&1234.5678), "1234.568");
    }
}
