//! Cutting polylines into drawable runs.
//!
//! plotters does not clip to the plotting area: a line that leaves the axis limits would be drawn
//! over the tick labels. We therefore clip every segment to the limits ourselves (Liang-Barsky),
//! in chart space, and break the line wherever a point cannot be drawn (NaN, infinite, or not
//! positive on a logarithmic axis), so that a tracked branch that disappears leaves a gap.

/// A point in chart space.
pub(crate) type Point = (f64, f64);

/// The visible rectangle in chart space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rect {
    pub x0: f64,
    pub x1: f64,
    pub y0: f64,
    pub y1: f64,
}

impl Rect {
    /// Whether `p` lies inside or on the border.
    pub fn contains(&self, p: Point) -> bool {
        p.0 >= self.x0 && p.0 <= self.x1 && p.1 >= self.y0 && p.1 <= self.y1
    }
}

/// Splits a polyline at undrawable points (`None`) and clips it to `rect`. Each returned run has
/// at least two points.
pub(crate) fn clip_polyline(
    points: impl IntoIterator<Item = Option<Point>>,
    rect: &Rect,
) -> Vec<Vec<Point>> {
    let mut runs = Vec::new();
    let mut run: Vec<Point> = Vec::new();
    let mut prev: Option<Point> = None;
    let mut flush = |run: &mut Vec<Point>| {
        if run.len() >= 2 {
            runs.push(std::mem::take(run));
        } else {
            run.clear();
        }
    };
    for p in points {
        match (prev, p) {
            (Some(a), Some(b)) => match clip_segment(a, b, rect) {
                Some((ca, cb, kept_a, kept_b)) => {
                    if !kept_a || run.is_empty() {
                        flush(&mut run);
                        run.push(ca);
                    }
                    run.push(cb);
                    if !kept_b {
                        flush(&mut run);
                    }
                }
                None => flush(&mut run),
            },
            (_, None) => flush(&mut run),
            (None, Some(_)) => {}
        }
        prev = p;
    }
    flush(&mut run);
    runs
}

/// Clips the segment `p`-`q` to `rect`. Returns the visible part and whether each end point was
/// kept unchanged, or `None` when nothing is visible.
fn clip_segment(p: Point, q: Point, rect: &Rect) -> Option<(Point, Point, bool, bool)> {
    let dx = q.0 - p.0;
    let dy = q.1 - p.1;
    if !(dx.is_finite() && dy.is_finite()) {
        return None;
    }
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    let edges = [
        (-dx, p.0 - rect.x0),
        (dx, rect.x1 - p.0),
        (-dy, p.1 - rect.y0),
        (dy, rect.y1 - p.1),
    ];
    for (pk, qk) in edges {
        if pk == 0.0 {
            if qk < 0.0 {
                return None; // parallel to this edge and outside it
            }
        } else {
            let r = qk / pk;
            if pk < 0.0 {
                if r > t1 {
                    return None;
                }
                t0 = t0.max(r);
            } else {
                if r < t0 {
                    return None;
                }
                t1 = t1.min(r);
            }
        }
    }
    let a = (p.0 + t0 * dx, p.1 + t0 * dy);
    let b = (p.0 + t1 * dx, p.1 + t1 * dy);
    let a = if t0 == 0.0 { p } else { a };
    let b = if t1 == 1.0 { q } else { b };
    Some((a, b, t0 == 0.0, t1 == 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    const UNIT: Rect = Rect {
        x0: 0.0,
        x1: 1.0,
        y0: 0.0,
        y1: 1.0,
    };

    #[test]
    fn gaps_split_the_line() {
        let pts = [
            Some((0.1, 0.1)),
            Some((0.2, 0.2)),
            None,
            Some((0.3, 0.3)),
            Some((0.4, 0.4)),
        ];
        let runs = clip_polyline(pts, &UNIT);
        assert_eq!(runs.len(), 2);
        assert_eq!(runs[0], vec![(0.1, 0.1), (0.2, 0.2)]);
    }

    #[test]
    fn leaving_and_reentering_gives_two_runs() {
        let pts = [Some((0.0, 0.5)), Some((0.5, 2.0)), Some((1.0, 0.5))];
        let runs = clip_polyline(pts, &UNIT);
        assert_eq!(runs.len(), 2);
        // Exact for these dyadic-friendly numbers up to rounding in the division.
        assert!((runs[0][1].1 - 1.0).abs() < 1e-12);
        assert!((runs[1][0].1 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn outside_segments_vanish() {
        let pts = [
            Some((2.0, 2.0)),
            Some((3.0, 3.0)),
            Some((f64::MAX, -f64::MAX)),
        ];
        assert!(clip_polyline(pts, &UNIT).is_empty());
    }
}
