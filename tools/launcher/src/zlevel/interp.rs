//! The Z offset between probed points, as scipy's `griddata` gives it to
//! LinuxCNC's component: the nearest point's, or linear on the Delaunay
//! triangulation of the points (barycentric inside a triangle, none
//! outside their convex hull). LinuxCNC's component samples the surface at
//! whole machine units and looks up the sample nearest the position; the
//! map does the same, clamped to the probed area.

use super::probe::ProbePoint;

/// How the offset between points is found (`method` pin).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// The nearest probed point's offset (2).
    Nearest,
    /// Linear on the Delaunay triangles (1).
    Linear,
}

impl Method {
    /// The method for a `method` pin value, and whether the pin asked for
    /// one this component does not have (cubic, 0, or a value outside
    /// 0..=2, for which LinuxCNC's falls back to cubic): linear is used
    /// then.
    pub fn from_pin(value: i32) -> (Method, bool) {
        match value {
            1 => (Method::Linear, false),
            2 => (Method::Nearest, false),
            _ => (Method::Linear, true),
        }
    }
}

/// The points and their Delaunay triangles (counter-clockwise index
/// triples).
#[derive(Debug, Clone)]
pub struct Surface {
    points: Vec<ProbePoint>,
    triangles: Vec<[usize; 3]>,
}

/// Twice the signed area of (a, b, c): positive when counter-clockwise.
fn orient(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> f64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

/// A triangle under construction with its circumcircle.
struct Tri {
    v: [usize; 3],
    cx: f64,
    cy: f64,
    r2: f64,
}

fn make_tri(q: &[(f64, f64)], mut v: [usize; 3]) -> Option<Tri> {
    let (a, b, c) = (q[v[0]], q[v[1]], q[v[2]]);
    let d = orient(a, b, c);
    if d.abs() < 1e-14 {
        return None;
    }
    if d < 0.0 {
        v.swap(1, 2);
    }
    let d = 2.0 * (a.0 * (b.1 - c.1) + b.0 * (c.1 - a.1) + c.0 * (a.1 - b.1));
    let (a2, b2, c2) = (
        a.0 * a.0 + a.1 * a.1,
        b.0 * b.0 + b.1 * b.1,
        c.0 * c.0 + c.1 * c.1,
    );
    let cx = (a2 * (b.1 - c.1) + b2 * (c.1 - a.1) + c2 * (a.1 - b.1)) / d;
    let cy = (a2 * (c.0 - b.0) + b2 * (a.0 - c.0) + c2 * (b.0 - a.0)) / d;
    let r2 = (a.0 - cx).powi(2) + (a.1 - cy).powi(2);
    Some(Tri { v, cx, cy, r2 })
}

/// Bowyer-Watson on the points scaled into a unit box, inside a large
/// enclosing triangle whose corners are dropped at the end.
fn triangulate(points: &[ProbePoint]) -> Vec<[usize; 3]> {
    let n = points.len();
    let (mut lo, mut hi) = ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN));
    for p in points {
        lo = (lo.0.min(p.x), lo.1.min(p.y));
        hi = (hi.0.max(p.x), hi.1.max(p.y));
    }
    let span = (hi.0 - lo.0).max(hi.1 - lo.1);
    if n < 3 || span <= 0.0 {
        return Vec::new();
    }
    let mid = ((lo.0 + hi.0) / 2.0, (lo.1 + hi.1) / 2.0);
    let mut q: Vec<(f64, f64)> = points
        .iter()
        .map(|p| ((p.x - mid.0) / span, (p.y - mid.1) / span))
        .collect();
    let big = 1.0e4;
    q.extend([(-big, -big), (big, -big), (0.0, big)]);
    let mut tris: Vec<Tri> = make_tri(&q, [n, n + 1, n + 2]).into_iter().collect();
    for i in 0..n {
        // A point probed twice keeps its first value.
        if q[..i].contains(&q[i]) {
            continue;
        }
        let (px, py) = q[i];
        let (bad, keep): (Vec<Tri>, Vec<Tri>) = tris
            .into_iter()
            .partition(|t| (px - t.cx).powi(2) + (py - t.cy).powi(2) < t.r2 * (1.0 - 1e-12));
        tris = keep;
        let mut edges: Vec<(usize, usize)> = Vec::new();
        for t in &bad {
            for (a, b) in [(t.v[0], t.v[1]), (t.v[1], t.v[2]), (t.v[2], t.v[0])] {
                if let Some(k) = edges.iter().position(|&(c, d)| c == b && d == a) {
                    edges.swap_remove(k);
                } else {
                    edges.push((a, b));
                }
            }
        }
        tris.extend(
            edges
                .into_iter()
                .filter_map(|(a, b)| make_tri(&q, [a, b, i])),
        );
    }
    tris.into_iter()
        .map(|t| t.v)
        .filter(|v| v.iter().all(|&k| k < n))
        .collect()
}

impl Surface {
    /// Triangulates the points. Points all on one line have no
    /// triangles: linear finds no offset then.
    pub fn new(points: &[ProbePoint]) -> Surface {
        Surface {
            points: points.to_vec(),
            triangles: triangulate(points),
        }
    }

    /// The Delaunay triangles, as index triples into the points.
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }

    /// The offset of the point nearest (x, y) (the first of equals).
    pub fn nearest(&self, x: f64, y: f64) -> Option<f64> {
        let d2 = |p: &ProbePoint| (p.x - x).powi(2) + (p.y - y).powi(2);
        self.points
            .iter()
            .fold(None::<&ProbePoint>, |best, p| match best {
                Some(b) if d2(b) <= d2(p) => Some(b),
                _ => Some(p),
            })
            .map(|p| p.z)
    }

    /// The offset at (x, y) on the triangle holding it, or `None` outside
    /// the points' convex hull.
    pub fn linear(&self, x: f64, y: f64) -> Option<f64> {
        for t in &self.triangles {
            let [a, b, c] = t.map(|k| self.points[k]);
            let area = orient((a.x, a.y), (b.x, b.y), (c.x, c.y));
            let la = orient((x, y), (b.x, b.y), (c.x, c.y)) / area;
            let lb = orient((a.x, a.y), (x, y), (c.x, c.y)) / area;
            let lc = 1.0 - la - lb;
            let tol = -1e-9;
            if la >= tol && lb >= tol && lc >= tol {
                return Some(la * a.z + lb * b.z + lc * c.z);
            }
        }
        None
    }
}

/// A loaded probe map: the surface and the whole-unit area it covers.
#[derive(Debug, Clone)]
pub struct ProbeMap {
    surface: Surface,
    x_range: (f64, f64),
    y_range: (f64, f64),
}

impl ProbeMap {
    /// The map of the points (at least one).
    pub fn new(points: &[ProbePoint]) -> ProbeMap {
        let range = |f: fn(&ProbePoint) -> f64| {
            let lo = points.iter().map(f).fold(f64::MAX, f64::min);
            let hi = points.iter().map(f).fold(f64::MIN, f64::max);
            (lo.trunc(), hi.trunc())
        };
        ProbeMap {
            surface: Surface::new(points),
            x_range: range(|p| p.x),
            y_range: range(|p| p.y),
        }
    }

    /// The surface.
    pub fn surface(&self) -> &Surface {
        &self.surface
    }

    /// The offset for the position (x, y) relative to the probed
    /// coordinates: at the whole-unit sample nearest it, inside the
    /// probed area. `None` where linear has no triangle.
    pub fn offset(&self, x: f64, y: f64, method: Method) -> Option<f64> {
        let clamp = |v: f64, (lo, hi): (f64, f64)| v.round_ties_even().max(lo).min(hi);
        if !x.is_finite() || !y.is_finite() {
            return None;
        }
        let (sx, sy) = (clamp(x, self.x_range), clamp(y, self.y_range));
        match method {
            Method::Nearest => self.surface.nearest(sx, sy),
            Method::Linear => self.surface.linear(sx, sy),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(x: f64, y: f64, z: f64) -> ProbePoint {
        ProbePoint { x, y, z }
    }

    /// A 3 x 3 grid, 10 units apart, with z = x/100 + y/50 except the
    /// centre, raised to 1.
    fn grid() -> Vec<ProbePoint> {
        let mut v = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                let (x, y) = (f64::from(i) * 10.0, f64::from(j) * 10.0);
                let z = if i == 1 && j == 1 {
                    1.0
                } else {
                    x / 100.0 + y / 50.0
                };
                v.push(pt(x, y, z));
            }
        }
        v
    }

    #[test]
    fn grid_triangulates_into_eight_triangles() {
        let s = Surface::new(&grid());
        assert_eq!(s.triangles().len(), 8);
        let area: f64 = s
            .triangles()
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|k| grid()[k]);
                orient((a.x, a.y), (b.x, b.y), (c.x, c.y)) / 2.0
            })
            .sum();
        assert!((area - 400.0).abs() < 1e-9, "{area}");
    }

    #[test]
    fn linear_by_hand_on_the_grid() {
        let s = Surface::new(&grid());
        // Each corner point's value is its own.
        assert!((s.linear(20.0, 20.0).unwrap() - 0.6).abs() < 1e-12);
        // The grid's squares are cocircular: a square's diagonal is
        // either. (5, 5) is halfway along both: (0,0)=0 .. (10,10)=1
        // gives 0.5, (10,0)=0.1 .. (0,10)=0.2 gives 0.15.
        let mid = s.linear(5.0, 5.0).unwrap();
        assert!(
            (mid - 0.5).abs() < 1e-12 || (mid - 0.15).abs() < 1e-12,
            "{mid}"
        );
        // Midpoint of the bottom edge (0,0)=0 .. (10,0)=0.1: 0.05.
        assert!((s.linear(5.0, 0.0).unwrap() - 0.05).abs() < 1e-12);
        // (15, 10) on the edge (10,10)=1 .. (20,10)=0.4: 0.7.
        assert!((s.linear(15.0, 10.0).unwrap() - 0.7).abs() < 1e-12);
        assert_eq!(s.linear(-1.0, 5.0), None);
    }

    #[test]
    fn linear_by_hand_inside_one_triangle() {
        // One triangle: (0,0)=0, (4,0)=4, (0,2)=2 is the plane z = x + y.
        let s = Surface::new(&[pt(0.0, 0.0, 0.0), pt(4.0, 0.0, 4.0), pt(0.0, 2.0, 2.0)]);
        assert!((s.linear(1.0, 0.5).unwrap() - 1.5).abs() < 1e-12);
        assert_eq!(s.linear(3.0, 1.5), None);
    }

    #[test]
    fn a_plane_is_reproduced_on_scattered_points() {
        let xs = [0.0, 7.0, 3.5, 12.0, 1.0, 9.0, 5.5, 11.0, 2.0];
        let ys = [0.0, 1.0, 6.0, 0.0, 11.0, 8.0, 3.0, 12.0, 4.0];
        let pts: Vec<_> = xs
            .iter()
            .zip(ys)
            .map(|(&x, y)| pt(x, y, 0.25 * x - 0.5 * y + 2.0))
            .collect();
        let s = Surface::new(&pts);
        for (x, y) in [(4.0, 4.0), (6.0, 2.0), (8.0, 6.0), (2.0, 8.0)] {
            let z = s.linear(x, y).unwrap();
            assert!((z - (0.25 * x - 0.5 * y + 2.0)).abs() < 1e-9, "{x} {y} {z}");
        }
    }

    #[test]
    fn nearest_by_hand() {
        let s = Surface::new(&grid());
        assert_eq!(s.nearest(12.0, 9.0), Some(1.0));
        assert_eq!(s.nearest(19.0, 1.0), Some(0.2));
        assert_eq!(s.nearest(-50.0, 100.0), Some(0.4));
    }

    #[test]
    fn collinear_points_have_no_triangles() {
        let s = Surface::new(&[pt(0.0, 0.0, 0.0), pt(1.0, 1.0, 1.0), pt(2.0, 2.0, 2.0)]);
        assert!(s.triangles().is_empty());
        assert_eq!(s.linear(1.0, 1.0), None);
        assert_eq!(s.nearest(1.9, 2.0), Some(2.0));
    }

    #[test]
    fn map_rounds_and_clamps_to_the_probed_area() {
        let m = ProbeMap::new(&grid());
        // 4.6 rounds to 5: the bottom edge's midpoint.
        let z = m.offset(4.6, -3.0, Method::Linear).unwrap();
        assert!((z - 0.05).abs() < 1e-12, "{z}");
        // Far outside: the corner (20, 20).
        let z = m.offset(500.0, 500.0, Method::Linear).unwrap();
        assert!((z - 0.6).abs() < 1e-12, "{z}");
        assert_eq!(m.offset(f64::NAN, 0.0, Method::Nearest), None);
        assert_eq!(Method::from_pin(0), (Method::Linear, true));
        assert_eq!(Method::from_pin(2), (Method::Nearest, false));
    }

    /// The area of the points' convex hull (Andrew's monotone chain).
    fn hull_area(pts: &[ProbePoint]) -> f64 {
        let mut v: Vec<(f64, f64)> = pts.iter().map(|p| (p.x, p.y)).collect();
        v.sort_by(|a, b| a.partial_cmp(b).unwrap());
        v.dedup();
        let mut hull: Vec<(f64, f64)> = Vec::new();
        for pass in 0..2 {
            let start = hull.len();
            let iter: Box<dyn Iterator<Item = &(f64, f64)>> = if pass == 0 {
                Box::new(v.iter())
            } else {
                Box::new(v.iter().rev())
            };
            for &p in iter {
                while hull.len() >= start + 2
                    && orient(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
                {
                    hull.pop();
                }
                hull.push(p);
            }
            hull.pop();
        }
        let n = hull.len();
        (0..n)
            .map(|i| orient((0.0, 0.0), hull[i], hull[(i + 1) % n]))
            .sum::<f64>()
            / 2.0
    }

    #[test]
    fn triangles_cover_the_convex_hull() {
        // Probing grids (collinear rows on the hull, cocircular squares)
        // and scattered points from a fixed linear congruential sequence.
        let mut sets = Vec::new();
        for (nx, ny, step) in [(5, 7, 25.0), (10, 10, 3.3), (2, 12, 40.0)] {
            let mut v = Vec::new();
            for j in 0..ny {
                for i in 0..nx {
                    v.push(pt(f64::from(i) * step, f64::from(j) * step, 0.0));
                }
            }
            sets.push(v);
        }
        let mut seed: u64 = 12345;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 33) % 2000) as f64 / 10.0
        };
        for n in [3, 10, 60, 300] {
            sets.push((0..n).map(|_| pt(next(), next(), 0.0)).collect());
        }
        for pts in sets {
            let s = Surface::new(&pts);
            let area: f64 = s
                .triangles()
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|k| pts[k]);
                    let o = orient((a.x, a.y), (b.x, b.y), (c.x, c.y));
                    assert!(o > 0.0, "counter-clockwise, not degenerate");
                    o / 2.0
                })
                .sum();
            let hull = hull_area(&pts);
            assert!(
                (area - hull).abs() < 1e-6 * hull,
                "{} points: {area} vs {hull}",
                pts.len()
            );
        }
    }
}
