//! The set of sample clocks a FIFO stream's reads allow: a convex polygon
//! of (b, p), where b is the host time of one sample and p the sample
//! period. Every read bounds b + m·p on both sides for the newest sample it
//! found, a linear constraint, so what all the reads allow together is the
//! intersection of half-planes: set-membership estimation of a straight
//! line's offset and slope (Schweppe, "Recursive state estimation: unknown
//! but bounded errors", IEEE TAC 13(1), 1968).

/// Slack given to every half-plane, in seconds: reads exactly on the
/// sample grid must not be lost to rounding.
const SLACK_S: f64 = 1e-9;

/// Vertices kept: beyond them, the polygon is replaced by a slightly larger
/// one with fewer (widening at every read would round it into hundreds).
const MAX_VERTICES: usize = 12;

/// A convex polygon of (b s, p s); empty when it has no vertex.
#[derive(Debug, Clone)]
pub(crate) struct ClockRegion {
    vertices: Vec<(f64, f64)>,
}

impl ClockRegion {
    /// b in [b_lo, b_hi], p in [p_lo, p_hi].
    pub(crate) fn rect(b_lo: f64, b_hi: f64, p_lo: f64, p_hi: f64) -> ClockRegion {
        ClockRegion {
            vertices: vec![(b_lo, p_lo), (b_hi, p_lo), (b_hi, p_hi), (b_lo, p_hi)],
        }
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// Moves the reference sample `m` samples on: b → b + m·p.
    pub(crate) fn shift(&mut self, m: i64) {
        for v in &mut self.vertices {
            v.0 += m as f64 * v.1;
        }
    }

    /// Keeps the part where b + m·p ≤ t: sample m after the reference was
    /// taken by host time t.
    pub(crate) fn taken_by(&mut self, m: f64, t: f64) {
        self.clip(1.0, m, t + SLACK_S);
    }

    /// Keeps the part where b + m·p ≥ t: sample m after the reference was
    /// not taken before host time t.
    pub(crate) fn not_before(&mut self, m: f64, t: f64) {
        self.clip(-1.0, -m, -t + SLACK_S);
    }

    /// Keeps the part where p_min ≤ p ≤ p_max.
    pub(crate) fn periods_within(&mut self, p_min: f64, p_max: f64) {
        self.clip(0.0, 1.0, p_max);
        self.clip(0.0, -1.0, -p_min);
    }

    /// Keeps the part where a·b + c·p ≤ k (Sutherland–Hodgman against one
    /// edge).
    fn clip(&mut self, a: f64, c: f64, k: f64) {
        let n = self.vertices.len();
        let mut out = Vec::with_capacity(n + 1);
        for i in 0..n {
            let (p, q) = (self.vertices[i], self.vertices[(i + 1) % n]);
            let (dp, dq) = (a * p.0 + c * p.1 - k, a * q.0 + c * q.1 - k);
            if dp <= 0.0 {
                out.push(p);
            }
            if (dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0) {
                let s = dp / (dp - dq);
                out.push((p.0 + s * (q.0 - p.0), p.1 + s * (q.1 - p.1)));
            }
        }
        self.vertices = out;
    }

    /// Grows the polygon by ±dp in p (its Minkowski sum with that segment):
    /// what a period drifting within bounds lets through. The chain from
    /// the leftmost vertex to the rightmost (counter-clockwise: the lower
    /// one) moves down, the other up.
    pub(crate) fn widen_period(&mut self, dp: f64) {
        if self.vertices.len() < 2 || dp <= 0.0 {
            return;
        }
        let n = self.vertices.len();
        let key = |i: &usize| (self.vertices[*i].0, self.vertices[*i].1);
        let by = |x: &usize, y: &usize| {
            let (x, y) = (key(x), key(y));
            x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1))
        };
        let left = (0..n).min_by(by).unwrap_or(0);
        let right = (0..n).max_by(by).unwrap_or(0);
        let mut out = Vec::with_capacity(n + 2);
        let mut i = left;
        loop {
            out.push((self.vertices[i].0, self.vertices[i].1 - dp));
            if i == right {
                break;
            }
            i = (i + 1) % n;
        }
        loop {
            out.push((self.vertices[i].0, self.vertices[i].1 + dp));
            if i == left {
                break;
            }
            i = (i + 1) % n;
        }
        self.vertices = out;
        while self.vertices.len() > MAX_VERTICES && self.drop_an_edge() {}
    }

    /// Grows the polygon to hold `other` too (the convex hull of both).
    pub(crate) fn merge(&mut self, other: &ClockRegion) {
        let mut points = std::mem::take(&mut self.vertices);
        points.extend_from_slice(&other.vertices);
        self.vertices = hull(points);
        while self.vertices.len() > MAX_VERTICES && self.drop_an_edge() {}
    }

    /// Removes the edge whose removal grows the polygon least: its two
    /// neighbours are extended to where they meet, which keeps every point
    /// the polygon held. False when no edge can go (every pair of
    /// neighbours diverges).
    fn drop_an_edge(&mut self) -> bool {
        let n = self.vertices.len();
        let v = |i: usize| self.vertices[i % n];
        let cross = |a: (f64, f64), b: (f64, f64)| a.0 * b.1 - a.1 * b.0;
        let mut best: Option<(f64, usize, (f64, f64))> = None;
        for i in 0..n {
            // Edge (v_i, v_i+1); neighbours run v_i−1 → v_i and v_i+2 → v_i+1.
            let (a, b) = (v(i), v(i + 1));
            let (prev, next) = (v(i + n - 1), v(i + 2));
            let d1 = (a.0 - prev.0, a.1 - prev.1);
            let d2 = (b.0 - next.0, b.1 - next.1);
            let ab = (b.0 - a.0, b.1 - a.1);
            let denom = cross(d1, d2);
            if denom == 0.0 {
                continue;
            }
            let s = cross(ab, d2) / denom;
            let u = cross(ab, d1) / denom;
            if !(s >= 0.0 && u >= 0.0 && s.is_finite() && u.is_finite()) {
                continue;
            }
            let x = (s * d1.0, s * d1.1);
            let grown = 0.5 * cross(ab, x).abs();
            if best.is_none_or(|(g, _, _)| grown < g) {
                best = Some((grown, i, (a.0 + x.0, a.1 + x.1)));
            }
        }
        let Some((_, i, x)) = best else {
            return false;
        };
        self.vertices[i] = x;
        self.vertices.remove((i + 1) % n);
        true
    }

    /// The range of (t − b)/p over the polygon: how many periods after the
    /// reference sample host time t may be.
    pub(crate) fn periods_to(&self, t: f64) -> (f64, f64) {
        self.vertices
            .iter()
            .map(|&(b, p)| (t - b) / p)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), f| {
                (lo.min(f), hi.max(f))
            })
    }

    /// Area and centroid; for a polygon too thin to have an area, the mean
    /// of its vertices.
    pub(crate) fn area_centroid(&self) -> (f64, (f64, f64)) {
        let Some(&o) = self.vertices.first() else {
            return (0.0, (f64::NAN, f64::NAN));
        };
        let n = self.vertices.len();
        // About the first vertex: b is a large host time, the polygon tiny.
        let (mut a2, mut cb, mut cp) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let (p, q) = (self.vertices[i], self.vertices[(i + 1) % n]);
            let (p, q) = ((p.0 - o.0, p.1 - o.1), (q.0 - o.0, q.1 - o.1));
            let cross = p.0 * q.1 - q.0 * p.1;
            a2 += cross;
            cb += (p.0 + q.0) * cross;
            cp += (p.1 + q.1) * cross;
        }
        if a2.abs() > 0.0 {
            (0.5 * a2.abs(), (o.0 + cb / (3.0 * a2), o.1 + cp / (3.0 * a2)))
        } else {
            let k = n as f64;
            let (sb, sp) = self
                .vertices
                .iter()
                .fold((0.0, 0.0), |(sb, sp), v| (sb + v.0 - o.0, sp + v.1 - o.1));
            (0.0, (o.0 + sb / k, o.1 + sp / k))
        }
    }

    /// The smallest and largest period allowed.
    #[cfg(test)]
    pub(crate) fn period_range(&self) -> (f64, f64) {
        self.vertices
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v.1), hi.max(v.1))
            })
    }
}

/// Convex hull, counter-clockwise (Andrew's monotone chain).
fn hull(mut points: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    points.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross =
        |o: (f64, f64), a: (f64, f64), b: (f64, f64)| (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
    let mut lower: Vec<(f64, f64)> = Vec::new();
    for &p in &points {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<(f64, f64)> = Vec::new();
    for &p in points.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0.0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_on_a_straight_clock_narrow_it_to_the_truth() {
        // Samples at 0.0013 + k·0.005 s, read at irregular times.
        let (b0, p): (f64, f64) = (0.0013, 0.005);
        let mut r = ClockRegion::rect(-0.01, 0.01, 0.0049, 0.0051);
        for &t in &[0.0211, 0.0437, 0.0702, 0.1009, 0.1333, 0.2718, 0.5] {
            let m = ((t - b0) / p).floor();
            r.taken_by(m, t);
            r.not_before(m + 1.0, t);
            assert!(!r.is_empty());
        }
        let (_, (b, pc)) = r.area_centroid();
        assert!((b - b0).abs() < 1e-3 && (pc - p).abs() < 2e-5, "{b} {pc}");
        let (lo, hi) = r.period_range();
        assert!(lo <= p && p <= hi);
        // After 100 samples the period is known to about 1 %: a read at
        // 120 samples claiming three more (2.5 %) contradicts them.
        assert!(hi - lo < 0.02 * p, "{lo} {hi}");
        let t = 0.6;
        let m = ((t - b0) / p).floor() + 3.0;
        r.taken_by(m, t);
        r.not_before(m + 1.0, t);
        assert!(r.is_empty());
    }

    #[test]
    fn widening_and_shifting_keep_a_rectangle_a_parallelogram() {
        let mut r = ClockRegion::rect(0.0, 1.0, 1.0, 2.0);
        r.widen_period(0.25);
        let (area, (b, p)) = r.area_centroid();
        assert!((area - 1.5).abs() < 1e-12 && (b - 0.5).abs() < 1e-12 && (p - 1.5).abs() < 1e-12);
        assert_eq!(r.period_range(), (0.75, 2.25));
        r.shift(2);
        let (area, (b, _)) = r.area_centroid();
        assert!(
            (area - 1.5).abs() < 1e-12 && (b - 3.5).abs() < 1e-12,
            "{area} {b}"
        );
        let (lo, hi) = r.periods_to(10.0);
        assert!(lo < hi);
        // Two apart: their hull.
        let mut a = ClockRegion::rect(0.0, 1.0, 0.0, 1.0);
        a.merge(&ClockRegion::rect(2.0, 3.0, 0.0, 1.0));
        let (area, (b, p)) = a.area_centroid();
        assert!((area - 3.0).abs() < 1e-12 && (b - 1.5).abs() < 1e-12 && (p - 0.5).abs() < 1e-12);
    }
}
