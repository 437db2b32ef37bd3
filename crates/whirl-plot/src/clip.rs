//! Cutting polylines into drawable runs.
//!
//! plotters does not clip to the plotting area: a line that leaves the axis limits would be drawn
//! over the tick labels. We therefore clip every segment to the limits ourselves (Liang-Barsky),
//! in chart space, and break the line wherever a point cannot be drawn (NaN, infinite, or not
//! positive on a logarithmic axis), so that a tracked branch that disappears leaves a gap.
//!
//! plotters' bitmap backend draws a line wider than 1 px as one filled polygon whose corners
//! are the intersections of the offset edges. Where a line turns back sharply (an orbit with
//! many samples per pixel, a noisy time history) those intersections lie far from the line,
//! and the polygon shows spikes well outside the data, even outside the frame.
//! [`split_sharp_turns`] therefore drops points closer than [`MIN_STEP_PX`] to the last kept
//! one and starts a new run at every turn sharper than [`MAX_TURN_DEG`], where the corner
//! stays within 1.2 half-widths of the line.

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

/// Least distance, device pixels, between the kept points of a run: at 3 px the direction of
/// a segment rounded to whole pixels is good to about 10 degrees.
pub(crate) const MIN_STEP_PX: f64 = 3.0;

/// Sharpest turn, degrees, kept inside one run: the corner of a turn by `a` lies
/// 1 / cos(a / 2) half-widths from the line, 1.15 at 60 degrees.
pub(crate) const MAX_TURN_DEG: f64 = 60.0;

/// Cuts a visible run into runs that a wide line draws without spikes: points closer than
/// [`MIN_STEP_PX`] to the last kept one are dropped (the run's last point is always kept) and
/// a new run starts at each turn sharper than [`MAX_TURN_DEG`]. `to_px` maps a point to device
/// pixels.
pub(crate) fn split_sharp_turns(run: &[Point], to_px: impl Fn(Point) -> Point) -> Vec<Vec<Point>> {
    let Some((&last, body)) = run.split_last().filter(|_| run.len() >= 2) else {
        return Vec::new();
    };
    let mut kept: Vec<(Point, Point)> = Vec::with_capacity(run.len());
    for &p in body {
        let px = to_px(p);
        if kept
            .last()
            .is_none_or(|&(_, q)| distance(px, q) >= MIN_STEP_PX)
        {
            kept.push((p, px));
        }
    }
    let last_px = to_px(last);
    if kept.len() > 1
        && kept
            .last()
            .is_some_and(|&(_, q)| distance(last_px, q) < MIN_STEP_PX)
    {
        kept.pop();
    }
    kept.push((last, last_px));
    let cos_max = MAX_TURN_DEG.to_radians().cos();
    let mut runs = Vec::new();
    let mut current = vec![kept[0].0];
    for w in kept.windows(3) {
        let (a, b, c) = (w[0].1, w[1].1, w[2].1);
        current.push(w[1].0);
        if turn_cosine(a, b, c) < cos_max {
            runs.push(std::mem::replace(&mut current, vec![w[1].0]));
        }
    }
    current.push(last);
    runs.push(current);
    runs
}

fn distance(a: Point, b: Point) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

/// Cosine of the angle between the directions a->b and b->c (1 when straight on).
fn turn_cosine(a: Point, b: Point, c: Point) -> f64 {
    let (u, v) = ((b.0 - a.0, b.1 - a.1), (c.0 - b.0, c.1 - b.1));
    (u.0 * v.0 + u.1 * v.1) / (u.0.hypot(u.1) * v.0.hypot(v.1))
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
    fn sharp_turns_start_new_runs_and_close_points_are_dropped() {
        let px = |p: Point| p;
        // A zigzag that turns back by 170 degrees at (10, 0): two runs meeting there.
        let zigzag = [(0.0, 0.0), (10.0, 0.0), (0.0, 1.76)];
        let runs = split_sharp_turns(&zigzag, px);
        assert_eq!(
            runs,
            vec![
                vec![(0.0, 0.0), (10.0, 0.0)],
                vec![(10.0, 0.0), (0.0, 1.76)]
            ]
        );
        // A gentle polygon (turns of 30 degrees) stays one run; a point 1 px after another
        // is dropped, the last point kept.
        let gentle = [
            (0.0, 0.0),
            (10.0, 0.0),
            (10.5, 0.5),
            (18.66, 5.0),
            (19.0, 5.0),
        ];
        let runs = split_sharp_turns(&gentle, px);
        assert_eq!(runs, vec![vec![(0.0, 0.0), (10.0, 0.0), (19.0, 5.0)]]);
        // Every kept turn is at most MAX_TURN_DEG: a circle sampled 1000 times per turn,
        // 100 px across, keeps points about 3 px apart and one run.
        let circle: Vec<Point> = (0..=1000)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / 1000.0;
                (50.0 * t.cos(), 50.0 * t.sin())
            })
            .collect();
        let runs = split_sharp_turns(&circle, px);
        assert_eq!(runs.len(), 1);
        assert!(
            runs[0].len() > 90 && runs[0].len() < 110,
            "{}",
            runs[0].len()
        );
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
