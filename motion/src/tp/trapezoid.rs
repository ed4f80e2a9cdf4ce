//! The trapezoidal planner's arithmetic, in discrete time: every period
//! the path speed changes by at most `a·T` and the position advances by
//! the new speed times `T`. Braking distances are those of this discrete
//! motion, not of the continuous one, so a stop lands exactly on its point
//! and a corner is never crossed faster than its cap.

/// The largest speed for the coming period from which the motion can
/// still stop exactly at distance `d` (braking by `a·T` per period, the
/// last period landing on the point). Every speed below it is just as
/// safe.
///
/// Braking from `v` in `[n·aT, (n+1)·aT)` covers `T·Σ_{i=0..n}(v − i·aT)`;
/// solving that for `v` with the largest `n` that fits gives the speed.
pub fn v_stop(d: f64, a: f64, t: f64) -> f64 {
    if d <= 0.0 {
        return 0.0;
    }
    let at2 = a * t * t;
    let mut n = ((-1.0 + (1.0 + 8.0 * d / at2).sqrt()) / 2.0).floor();
    // Rounding may put n one off; the step distances must fit.
    while n > 0.0 && at2 * n * (n + 1.0) / 2.0 > d {
        n -= 1.0;
    }
    while at2 * (n + 1.0) * (n + 2.0) / 2.0 <= d {
        n += 1.0;
    }
    d / (t * (n + 1.0)) + a * t * n / 2.0
}

/// The largest speed for the coming period from which, braking by `a·T`
/// per period, every period faster than `c` ends before distance `d`
/// (strictly: a period ending exactly on the point is next to it too):
/// the point is then passed no faster than `c`. At least `c`.
pub fn v_cross(d: f64, c: f64, a: f64, t: f64) -> f64 {
    let d = d - (1e-12 * d + 1e-15);
    if d <= 0.0 {
        return c;
    }
    let at = a * t;
    // n periods above c starting at v cover T·(n·v − aT·n(n−1)/2): the
    // largest v for a given n, kept inside the speeds that take n periods.
    let per_n = |n: f64| {
        let v = ((d / t + at * n * (n - 1.0) / 2.0) / n).min(c + n * at);
        (v > c + (n - 1.0) * at).then_some(v)
    };
    let guess = (((c * c + 2.0 * a * d).sqrt() - c) / at).ceil().max(1.0);
    let mut best = c;
    let mut n = (guess - 3.0).max(1.0);
    while n <= guess + 3.0 {
        if let Some(v) = per_n(n) {
            best = best.max(v);
        }
        n += 1.0;
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brakes from `v` by `a·T` per period until at or below `c`; returns
    /// the distance of the periods above `c`.
    fn braking_above(v: f64, c: f64, a: f64, t: f64) -> f64 {
        let mut d = 0.0;
        let mut v = v;
        while v > c + 1e-12 {
            d += v * t;
            v -= a * t;
        }
        d
    }

    #[test]
    fn v_stop_lands_exactly_by_braking() {
        let (a, t) = (250.0, 0.001);
        for k in 0..2000 {
            let d = 0.0003 * k as f64 + 1e-7;
            let v = v_stop(d, a, t);
            // Simulate: each period the largest safe speed, never more
            // than aT slower than the last.
            let (mut left, mut speed) = (d, v);
            let mut steps = 0;
            while left > 1e-12 {
                assert!(speed <= v_stop(left, a, t) + 1e-9);
                left -= speed * t;
                assert!(left > -1e-12, "overshoot at d = {d}");
                let next = v_stop(left, a, t);
                assert!(speed - next <= a * t + 1e-9, "brakes too hard at d = {d}");
                speed = next;
                steps += 1;
                assert!(steps < 100_000);
            }
            assert!(speed <= a * t + 1e-9, "the landing period is slow");
        }
    }

    #[test]
    fn v_cross_is_the_fastest_speed_that_brakes_to_c_in_time() {
        let (a, t) = (100.0, 0.001);
        for k in 0..400 {
            let d = 0.0007 * k as f64;
            for c in [0.01, 0.3, 2.0, 7.5] {
                let v = v_cross(d, c, a, t);
                assert!(v >= c);
                assert!(
                    braking_above(v, c, a, t) <= d + 1e-12,
                    "d {d} c {c}: v {v} too fast"
                );
                // A little faster would not make it (unless c itself).
                if v > c {
                    assert!(braking_above(v + 1e-6, c, a, t) > d - 1e-9);
                }
            }
        }
    }
}
