//! The summary table, the live line and the CSV of a latency test.

use std::fmt::Write as _;

use hal_core::latency_bucket_floor_us;

use super::stats::ThreadStats;
use crate::error::ScopeError;

/// Microseconds with one decimal, or `-` when unknown.
fn us(ns: Option<u64>) -> String {
    ns.map_or("-".into(), |n| format!("{:.1}", n as f64 / 1000.0))
}

/// A period for people: `25 us`, `1 ms`.
pub fn period_text(ns: i64) -> String {
    if ns >= 1_000_000 && ns % 1000 == 0 {
        format!("{} ms", ns as f64 / 1e6)
    } else {
        format!("{} us", ns as f64 / 1e3)
    }
}

/// The live line: each thread's minimum and maximum so far.
pub fn live_line(elapsed_s: f64, threads: &[ThreadStats]) -> String {
    let mut s = format!("{elapsed_s:7.1} s");
    for t in threads {
        let _ = write!(
            s,
            "  |  {} ({}): min {} us  max {} us  overruns {}",
            t.name,
            period_text(t.period_ns),
            us(t.min_ns),
            us(t.max_ns),
            t.overruns
        );
    }
    s
}

/// The final table: one row per thread, latencies in µs.
pub fn summary_table(threads: &[ThreadStats]) -> String {
    let mut s = format!(
        "{:<14} {:>9} {:>10} {:>8} {:>8} {:>8} {:>8} {:>8} {:>9}\n",
        "thread", "period", "cycles", "min", "p50", "p99", "p99.9", "max", "overruns"
    );
    for t in threads {
        let _ = writeln!(
            s,
            "{:<14} {:>9} {:>10} {:>8} {:>8} {:>8} {:>8} {:>8} {:>9}",
            t.name,
            period_text(t.period_ns),
            t.cycles,
            us(t.min_ns),
            us(t.percentile_ns(0.5)),
            us(t.percentile_ns(0.99)),
            us(t.percentile_ns(0.999)),
            us(t.max_ns),
            t.overruns
        );
    }
    s.push_str(
        "(latency in us: how late each thread woke against its deadline; percentiles are \
         upper bounds, the edge of the thread histogram's bucket)\n",
    );
    s
}

/// The histogram as CSV: one row per bucket (`bucket,low_us,high_us`,
/// then one count column per thread, named after it); the last bucket
/// is open above.
pub fn histogram_csv(threads: &[ThreadStats]) -> String {
    let mut s = String::from("bucket,low_us,high_us");
    for t in threads {
        s.push(',');
        s.push_str(&t.name);
    }
    s.push('\n');
    let buckets = threads.iter().map(|t| t.histogram.len()).max().unwrap_or(0);
    for b in 0..buckets {
        let _ = write!(s, "{b},{},", latency_bucket_floor_us(b));
        if b + 1 < buckets {
            let _ = write!(s, "{}", latency_bucket_floor_us(b + 1));
        }
        for t in threads {
            let _ = write!(s, ",{}", t.histogram.get(b).copied().unwrap_or(0));
        }
        s.push('\n');
    }
    s
}

/// Reads a CSV written by [`histogram_csv`] back: thread names and their
/// counts per bucket.
pub fn parse_histogram_csv(text: &str) -> Result<Vec<(String, Vec<u64>)>, ScopeError> {
    let mut lines = text.lines();
    let header = lines.next().ok_or(ScopeError::CsvEmpty)?;
    let names: Vec<String> = header.split(',').skip(3).map(str::to_string).collect();
    if !header.starts_with("bucket,low_us,high_us") || names.is_empty() {
        return Err(ScopeError::CsvHeader {
            header: header.to_string(),
        });
    }
    let mut counts = vec![Vec::new(); names.len()];
    for (i, line) in lines.enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != names.len() + 3 || f[0] != i.to_string() {
            return Err(ScopeError::CsvLine {
                line: i + 2,
                text: line.to_string(),
            });
        }
        for (c, v) in counts.iter_mut().zip(&f[3..]) {
            c.push(v.parse().map_err(|_| ScopeError::CsvCount {
                line: i + 2,
                value: v.to_string(),
            })?);
        }
    }
    Ok(names.into_iter().zip(counts).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(name: &str, hist: Vec<u64>) -> ThreadStats {
        ThreadStats {
            name: name.into(),
            period_ns: 25_000,
            cycles: hist.iter().sum(),
            overruns: 2,
            min_ns: Some(1_234),
            max_ns: Some(17_900),
            histogram: hist,
        }
    }

    #[test]
    fn csv_round_trips_and_has_bucket_edges() {
        let mut h = vec![0u64; 64];
        h[1] = 10;
        h[17] = 1;
        let threads = [t("base-thread", h.clone()), t("servo-thread", vec![0; 64])];
        let csv = histogram_csv(&threads);
        assert!(csv.starts_with(
            "bucket,low_us,high_us,base-thread,servo-thread\n0,0,1,0,0\n1,1,2,10,0\n"
        ));
        assert!(csv.contains("\n17,20,24,1,0\n"), "{csv}");
        assert!(csv.ends_with(",0,0\n") && csv.lines().count() == 65);
        let back = parse_histogram_csv(&csv).unwrap();
        assert_eq!(back[0], ("base-thread".to_string(), h));
        assert!(parse_histogram_csv("x\n").is_err());
    }

    #[test]
    fn table_and_live_line() {
        let mut h = vec![0u64; 64];
        h[1] = 10;
        let table = summary_table(&[t("base-thread", h)]);
        let row = table.lines().nth(1).unwrap();
        let cols: Vec<&str> = row.split_whitespace().collect();
        assert_eq!(
            cols,
            [
                "base-thread",
                "25",
                "us",
                "10",
                "1.2",
                "2.0",
                "2.0",
                "2.0",
                "17.9",
                "2"
            ]
        );
        let live = live_line(1.0, &[t("servo-thread", vec![0; 64])]);
        assert!(
            live.contains("servo-thread (25 us): min 1.2 us  max 17.9 us  overruns 2"),
            "{live}"
        );
        assert_eq!(period_text(1_000_000), "1 ms");
        assert_eq!(period_text(25_000), "25 us");
    }
}
