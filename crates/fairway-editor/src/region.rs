//! Curve regions as the editor handles them, including regions across the
//! seam of a closed curve.
//!
//! A region is a parameter pair `(u1, u2)` in the domain `[a, b]`. With
//! `u1 < u2` it is the stretch `[u1, u2]`, as on any curve. On a closed curve
//! the parameter is circular (`a ≡ b`) and `u1 > u2` means the stretch from
//! `u1` forward through the seam to `u2`: `[u1, b] ∪ [a, u2]`, the core's
//! convention (`fairway::fair::CurveFairing`, route 2).
//!
//! Gestures track the moving end *unwrapped* ([`RegionDrag`]): on a closed
//! curve a pointer that crosses the seam keeps going (`u > b` or `u < a`)
//! instead of jumping back to the other end of the domain, and the region is
//! folded back into the domain at the end ([`from_unwrapped`]).

/// Whether `r` runs across the seam (`u1 > u2`).
pub fn wraps(r: (f64, f64)) -> bool {
    r.0 > r.1
}

/// Whether the region `r` contains the parameter `u` (ends included): `u1 ≤ u ≤ u2`, or for a region
/// across the seam `u ≥ u1` or `u ≤ u2`.
pub fn contains(r: (f64, f64), u: f64) -> bool {
    if wraps(r) {
        u >= r.0 || u <= r.1
    } else {
        u >= r.0 && u <= r.1
    }
}

/// Parameter length of `r` on the domain `dom = (a, b)`: `u2 − u1`, or `(b − u1) + (u2 − a)` across
/// the seam.
pub fn length(r: (f64, f64), dom: (f64, f64)) -> f64 {
    if wraps(r) {
        (dom.1 - r.0) + (r.1 - dom.0)
    } else {
        r.1 - r.0
    }
}

/// `u` folded into `[a, b)` modulo the domain length (the circular parameter of a closed curve).
pub fn normalize(u: f64, dom: (f64, f64)) -> f64 {
    let (a, b) = dom;
    let l = b - a;
    if !(l > 0.0) || !u.is_finite() {
        return u;
    }
    let x = a + (u - a).rem_euclid(l);
    // rem_euclid can round up to l itself
    if x >= b { a } else { x }
}

/// The one or two ordinary intervals that make up `r` on `dom`: `[(u1, u2)]`, or across the seam
/// `[(u1, b), (a, u2)]` (in that order: along the region).
pub fn parts(r: (f64, f64), dom: (f64, f64)) -> Vec<(f64, f64)> {
    if wraps(r) {
        vec![(r.0, dom.1), (dom.0, r.1)]
    } else {
        vec![r]
    }
}

/// The canonical form of a region on a curve with domain `dom`: on an open curve the ends in
/// increasing order; on a closed curve the order is kept (`u1 > u2` runs across the seam), and a
/// region across the seam that only touches it (`u1 = b` or `u2 = a`) is the ordinary region it is.
pub fn canonical(r: (f64, f64), dom: (f64, f64), closed: bool) -> (f64, f64) {
    let (u1, u2) = r;
    if !closed || u1 <= u2 {
        return (u1.min(u2), u1.max(u2));
    }
    if u2 <= dom.0 {
        (u1, dom.1)
    } else if u1 >= dom.1 {
        (dom.0, u2)
    } else {
        (u1, u2)
    }
}

/// The region between two unwrapped parameters `p`, `q` (any order) on `dom`. On an open curve both
/// are clamped to the domain. On a closed curve the stretch from `min(p, q)` to `max(p, q)` is folded
/// into the domain: within `[a, b]` an ordinary region, through `b` (or `a`) a region across the seam;
/// a stretch of a whole period or more is the whole curve `(a, b)`.
pub fn from_unwrapped(p: f64, q: f64, dom: (f64, f64), closed: bool) -> (f64, f64) {
    let (a, b) = dom;
    let (lo, hi) = (p.min(q), p.max(q));
    if !closed {
        return (lo.clamp(a, b), hi.clamp(a, b));
    }
    let l = b - a;
    if hi - lo >= l * (1.0 - 1e-12) {
        return (a, b);
    }
    // ends already in the domain are kept exactly; the end keeps b rather than folding to a (a
    // stretch ending at the seam is ordinary)
    let u1 = if lo >= a && lo < b { lo } else { normalize(lo, dom) };
    let u2 = if hi >= a && hi <= b { hi } else { normalize(hi, dom) };
    canonical((u1, u2), dom, true)
}

/// Text for the panel: "u from 0.2000 to 0.6000", or "u from 0.8500 to 0.1500 (across the seam)" (no
/// arrow: egui's default fonts have no glyph for it).
pub fn describe(r: (f64, f64)) -> String {
    let seam = if wraps(r) { " (across the seam)" } else { "" };
    format!("u from {:.4} to {:.4}{seam}", r.0, r.1)
}

/// A region gesture in progress: one end `fixed`, the other `moving` with the pointer, both unwrapped
/// parameters (on a closed curve they may leave `[a, b]` by up to a period; see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegionDrag {
    /// The end that stays (unwrapped).
    pub fixed: f64,
    /// The end that stays, as the parameter in the domain it was given as (kept exactly).
    pub fixed_u: f64,
    /// The end under the pointer (unwrapped).
    pub moving: f64,
    /// The curve's domain `(a, b)`.
    pub dom: (f64, f64),
    /// The curve is closed (the parameter is circular).
    pub closed: bool,
    /// An end of the whole closed curve was grabbed: both ends sit on the seam point, so the first
    /// move decides which one moves (outwards past the fixed end means the other one: the region
    /// shrinks from that side instead of staying the whole curve).
    pub whole: bool,
}

impl RegionDrag {
    /// A new selection that starts at parameter `u` (both ends there).
    pub fn select(u: f64, dom: (f64, f64), closed: bool) -> Self {
        Self {
            fixed: u,
            fixed_u: u,
            moving: u,
            dom,
            closed,
            whole: false,
        }
    }

    /// Grab end `k` (0: `u1`, 1: `u2`) of the region `r`; the other end stays. Across the seam the
    /// end `u2` is taken one period on (`u2 + L`), so that `fixed` and `moving` span the region.
    pub fn handle(r: (f64, f64), k: usize, dom: (f64, f64), closed: bool) -> Self {
        let l = dom.1 - dom.0;
        let u2 = if wraps(r) { r.1 + l } else { r.1 };
        let (fixed, fixed_u, moving) = if k == 0 { (u2, r.1, r.0) } else { (r.0, r.0, u2) };
        Self {
            fixed,
            fixed_u,
            moving,
            dom,
            closed,
            whole: closed && !wraps(r) && r.0 <= dom.0 && r.1 >= dom.1,
        }
    }

    /// Move the pointer's end to parameter `u` (from the nearest curve sample, in `[a, b]`, or beyond
    /// the ends where a gesture extends past them). On a closed curve the representative `u + kL`
    /// nearest to the last position is taken: a pointer that crosses the seam goes on through it. On
    /// an open curve `u` is clamped to the domain. Returns the region now selected.
    pub fn move_to(&mut self, u: f64) -> (f64, f64) {
        let (a, b) = self.dom;
        if self.closed {
            let l = b - a;
            if l > 0.0 && u.is_finite() {
                let k = ((self.moving - u) / l).round();
                self.place(u + k * l);
            }
        } else if u.is_finite() {
            self.moving = u.clamp(a, b);
        }
        self.region()
    }

    /// Put the pointer's end at the unwrapped parameter `m` as it is (for a gesture whose position is
    /// absolute, like the κ plot's: no guess from the last position, so a fast move cannot flip it
    /// through the seam), at most one period from the fixed end on a closed curve, in the domain on an
    /// open one. Returns the region now selected.
    pub fn set_moving(&mut self, m: f64) -> (f64, f64) {
        if m.is_finite() {
            let (a, b) = self.dom;
            if self.closed {
                self.place(m);
            } else {
                self.moving = m.clamp(a, b);
            }
        }
        self.region()
    }

    /// Closed curve: the moving end to the unwrapped `m`, at most one period from the fixed end (a
    /// whole loop is the whole curve); see [`RegionDrag::whole`] for the first move off the whole curve.
    fn place(&mut self, mut m: f64) {
        let l = self.dom.1 - self.dom.0;
        if self.whole && m != self.moving {
            self.whole = false;
            if (m - self.fixed).abs() > l {
                // outwards: the grabbed point is the fixed end's copy one period away; that end moves
                let shift = if self.moving < self.fixed { l } else { -l };
                self.fixed = self.moving;
                self.fixed_u = self.moving;
                m += shift;
            }
        }
        self.moving = m.clamp(self.fixed - l, self.fixed + l);
    }

    /// The region between the two ends ([`from_unwrapped`]); the fixed end keeps its exact value
    /// (folding an unwrapped `u2 + L` back into the domain rounds).
    pub fn region(&self) -> (f64, f64) {
        let mut r = from_unwrapped(self.fixed, self.moving, self.dom, self.closed);
        let (a, b) = self.dom;
        let exact = self.fixed_u;
        let eps = 1e-9 * (b - a);
        if self.fixed <= self.moving {
            if (r.0 - exact).abs() <= eps {
                r.0 = exact;
            }
        } else if (r.1 - exact).abs() <= eps {
            r.1 = exact;
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOM: (f64, f64) = (0.0, 1.0);

    #[test]
    fn contains_and_length_of_ordinary_and_wrapping_regions() {
        let r = (0.2, 0.6);
        assert!(contains(r, 0.2) && contains(r, 0.4) && contains(r, 0.6));
        assert!(!contains(r, 0.1) && !contains(r, 0.7));
        assert!((length(r, DOM) - 0.4).abs() < 1e-15);
        let w = (0.85, 0.15);
        assert!(wraps(w) && !wraps(r));
        for u in [0.85, 0.9, 1.0, 0.0, 0.1, 0.15] {
            assert!(contains(w, u), "{u}");
        }
        for u in [0.16, 0.5, 0.84] {
            assert!(!contains(w, u), "{u}");
        }
        assert!((length(w, DOM) - 0.3).abs() < 1e-15);
        // on a shifted domain
        assert!((length((3.5, 2.5), (2.0, 4.0)) - 1.0).abs() < 1e-15);
        assert_eq!(parts(w, DOM), vec![(0.85, 1.0), (0.0, 0.15)]);
        assert_eq!(parts(r, DOM), vec![r]);
    }

    #[test]
    fn normalize_folds_into_the_half_open_domain() {
        assert_eq!(normalize(0.25, DOM), 0.25);
        assert!((normalize(1.25, DOM) - 0.25).abs() < 1e-15);
        assert!((normalize(-0.25, DOM) - 0.75).abs() < 1e-15);
        assert_eq!(normalize(1.0, DOM), 0.0);
        assert!((normalize(7.0, (2.0, 4.0)) - 3.0).abs() < 1e-15);
        assert!((normalize(1.5, (2.0, 4.0)) - 3.5).abs() < 1e-15);
        // rounding at the top end stays in [a, b)
        let x = normalize(-1e-18, DOM);
        assert!((0.0..1.0).contains(&x), "{x}");
    }

    #[test]
    fn canonical_orders_open_regions_and_keeps_wrapping_ones() {
        assert_eq!(canonical((0.6, 0.2), DOM, false), (0.2, 0.6));
        assert_eq!(canonical((0.6, 0.2), DOM, true), (0.6, 0.2));
        assert_eq!(canonical((0.2, 0.6), DOM, true), (0.2, 0.6));
        // touching the seam from either side is an ordinary region
        assert_eq!(canonical((0.7, 0.0), DOM, true), (0.7, 1.0));
        assert_eq!(canonical((1.0, 0.3), DOM, true), (0.0, 0.3));
    }

    #[test]
    fn unwrapped_stretches_fold_into_the_domain() {
        // inside the domain: ordinary, either order
        assert_eq!(from_unwrapped(0.3, 0.1, DOM, true), (0.1, 0.3));
        // through b or below a: across the seam
        let (u1, u2) = from_unwrapped(0.8, 1.2, DOM, true);
        assert!((u1 - 0.8).abs() < 1e-15 && (u2 - 0.2).abs() < 1e-12, "{u1} {u2}");
        let (u1, u2) = from_unwrapped(0.2, -0.3, DOM, true);
        assert!((u1 - 0.7).abs() < 1e-12 && (u2 - 0.2).abs() < 1e-15, "{u1} {u2}");
        // ending at the seam stays ordinary
        assert_eq!(from_unwrapped(0.6, 1.0, DOM, true), (0.6, 1.0));
        // a whole period or more: the whole curve
        assert_eq!(from_unwrapped(0.3, 1.3, DOM, true), (0.0, 1.0));
        // open curves clamp
        assert_eq!(from_unwrapped(0.8, 1.2, DOM, false), (0.8, 1.0));
    }

    #[test]
    fn a_selection_dragged_past_the_seam_wraps_and_back_unwraps() {
        let mut d = RegionDrag::select(0.8, DOM, true);
        assert_eq!(d.move_to(0.9), (0.8, 0.9));
        // the nearest sample jumps from the end of the domain to its start: the pointer crossed the seam
        assert_eq!(d.move_to(0.99), (0.8, 0.99));
        let r = d.move_to(0.1);
        assert!(
            wraps(r) && (r.0 - 0.8).abs() < 1e-15 && (r.1 - 0.1).abs() < 1e-12,
            "{r:?}"
        );
        // and back again
        assert_eq!(d.move_to(0.95), (0.8, 0.95));
        // the other way: start near a, go backwards through the seam
        let mut d = RegionDrag::select(0.1, DOM, true);
        d.move_to(0.02);
        let r = d.move_to(0.9);
        assert!(
            wraps(r) && (r.0 - 0.9).abs() < 1e-12 && (r.1 - 0.1).abs() < 1e-12,
            "{r:?}"
        );
        // an open curve never wraps
        let mut d = RegionDrag::select(0.8, DOM, false);
        d.move_to(0.99);
        assert_eq!(d.move_to(0.1), (0.1, 0.8));
    }

    #[test]
    fn an_absolute_position_is_taken_as_it_is() {
        // a fast jump across most of the domain stays on this side of the seam
        let mut d = RegionDrag::select(0.1, DOM, true);
        assert_eq!(d.set_moving(0.9), (0.1, 0.9));
        // beyond the domain: through the seam
        let r = d.set_moving(1.05);
        assert!(wraps(r) && (r.1 - 0.05).abs() < 1e-12, "{r:?}");
        // at most a period from the fixed end
        assert_eq!(d.set_moving(5.0), (0.0, 1.0));
        let mut d = RegionDrag::select(0.1, DOM, false);
        assert_eq!(d.set_moving(1.05), (0.1, 1.0));
    }

    #[test]
    fn a_handle_dragged_past_the_seam_moves_only_its_end() {
        // the end of an ordinary region, past b
        let mut d = RegionDrag::handle((0.6, 0.9), 1, DOM, true);
        d.move_to(0.98);
        let r = d.move_to(0.05);
        assert!((r.0 - 0.6).abs() < 1e-15 && (r.1 - 0.05).abs() < 1e-12, "{r:?}");
        // the start of a region across the seam, moved forward past b: ordinary again, end unchanged
        let mut d = RegionDrag::handle((0.85, 0.15), 0, DOM, true);
        d.move_to(0.95);
        let r = d.move_to(0.05);
        assert!((r.0 - 0.05).abs() < 1e-12 && (r.1 - 0.15).abs() < 1e-12, "{r:?}");
        // the end of a region across the seam, moved back through the seam: ordinary [u1, u]
        let mut d = RegionDrag::handle((0.85, 0.15), 1, DOM, true);
        d.move_to(0.02);
        let r = d.move_to(0.95);
        assert!((r.0 - 0.85).abs() < 1e-12 && (r.1 - 0.95).abs() < 1e-12, "{r:?}");
        // growing past the other end: at most the whole curve
        let mut d = RegionDrag::handle((0.85, 0.15), 1, DOM, true);
        for u in [0.3, 0.5, 0.7, 0.84, 0.9] {
            d.move_to(u);
        }
        assert_eq!(d.region(), (0.0, 1.0));
        // and back: it shrinks again from the end that moved
        let r = d.move_to(0.8);
        assert!((r.0 - 0.85).abs() < 1e-12 && (r.1 - 0.8).abs() < 1e-12, "{r:?}");
    }

    #[test]
    fn the_whole_closed_curve_shrinks_from_the_side_its_seam_point_is_dragged_to() {
        // both handles sit on the seam point; the canvas grabs handle 0 (u1 = a)
        for k in [0, 1] {
            // forwards: the start moves
            let mut d = RegionDrag::handle(DOM, k, DOM, true);
            d.move_to(0.02);
            assert_eq!(d.move_to(0.1), (0.1, 1.0), "handle {k}");
            // backwards: the end moves
            let mut d = RegionDrag::handle(DOM, k, DOM, true);
            d.move_to(0.98);
            let r = d.move_to(0.9);
            assert!(r.0 == 0.0 && (r.1 - 0.9).abs() < 1e-12, "handle {k}: {r:?}");
        }
        // an open curve's whole domain: handles are ordinary
        let mut d = RegionDrag::handle(DOM, 0, DOM, false);
        assert_eq!(d.move_to(0.1), (0.1, 1.0));
    }
}
