//! Orbit camera of the 3D view: a target point, a distance and two angles
//! (z is up), perspective projection with wgpu's 0..1 depth range.
//!
//! The eye sits at `target + dist·d(yaw, pitch)` with
//! `d = (cos pitch cos yaw, cos pitch sin yaw, sin pitch)`. The view basis is
//! built from the angles directly (right = (−sin yaw, cos yaw, 0),
//! up = d × right… see [`Camera::basis`]), so the top view (pitch = 90°) has
//! no degenerate "up" vector.

use glam::{DMat4, DVec2, DVec3, DVec4};

/// Orbit camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Point orbited around (model units).
    pub target: DVec3,
    /// Distance eye–target (> 0).
    pub dist: f64,
    /// Azimuth of the eye around z (radians).
    pub yaw: f64,
    /// Elevation of the eye above the xy plane (radians, clamped to ±90°).
    pub pitch: f64,
    /// Vertical field of view (radians).
    pub fov_y: f64,
    /// Radius of the scene's bounding sphere (sets the clip planes).
    pub scene_radius: f64,
}

/// A standard view direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StandardView {
    /// Looking along +y (eye at −y).
    Front,
    /// Looking down −z.
    Top,
    /// Looking along −x (eye at +x).
    Side,
    /// Isometric: eye along (1, −1, 1).
    Iso,
}

impl StandardView {
    /// (yaw, pitch) of the eye direction.
    pub fn angles(self) -> (f64, f64) {
        use std::f64::consts::FRAC_PI_2;
        match self {
            StandardView::Front => (-FRAC_PI_2, 0.0),
            StandardView::Top => (-FRAC_PI_2, FRAC_PI_2),
            StandardView::Side => (0.0, 0.0),
            StandardView::Iso => (-std::f64::consts::FRAC_PI_4, (1.0 / 3f64.sqrt()).asin()),
        }
    }
}

impl Default for Camera {
    fn default() -> Self {
        let (yaw, pitch) = StandardView::Iso.angles();
        Self {
            target: DVec3::ZERO,
            dist: 5.0,
            yaw,
            pitch,
            fov_y: 30f64.to_radians(),
            scene_radius: 1.0,
        }
    }
}

impl Camera {
    /// Unit vector from the target to the eye.
    pub fn eye_dir(&self) -> DVec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        DVec3::new(cp * cy, cp * sy, sp)
    }

    /// Eye position.
    pub fn eye(&self) -> DVec3 {
        self.target + self.dist * self.eye_dir()
    }

    /// Orthonormal (right, up, back) of the view: back = eye direction,
    /// right = (−sin yaw, cos yaw, 0), up = back × right.
    pub fn basis(&self) -> (DVec3, DVec3, DVec3) {
        let back = self.eye_dir();
        let right = DVec3::new(-self.yaw.sin(), self.yaw.cos(), 0.0);
        let up = back.cross(right);
        (right, up, back)
    }

    /// World → camera matrix.
    pub fn view(&self) -> DMat4 {
        let (r, u, b) = self.basis();
        let e = self.eye();
        DMat4::from_cols(
            DVec4::new(r.x, u.x, b.x, 0.0),
            DVec4::new(r.y, u.y, b.y, 0.0),
            DVec4::new(r.z, u.z, b.z, 0.0),
            DVec4::new(-r.dot(e), -u.dot(e), -b.dot(e), 1.0),
        )
    }

    /// Near and far clip distances enclosing the scene sphere.
    pub fn clip(&self) -> (f64, f64) {
        let r = self.scene_radius.max(1e-9);
        let center_depth = self.dist;
        let near = (center_depth - 2.0 * r).max(center_depth * 1e-3).max(1e-6);
        let far = center_depth + 2.0 * r;
        (near, far.max(near * 1.01))
    }

    /// Camera → clip matrix (right-handed, depth 0..1) for `aspect` = width/height.
    pub fn proj(&self, aspect: f64) -> DMat4 {
        // right-handed, camera looks down −z, depth 0 (near) .. 1 (far)
        let (n, f) = self.clip();
        let t = 1.0 / (self.fov_y * 0.5).tan();
        let a = aspect.max(1e-6);
        DMat4::from_cols(
            DVec4::new(t / a, 0.0, 0.0, 0.0),
            DVec4::new(0.0, t, 0.0, 0.0),
            DVec4::new(0.0, 0.0, f / (n - f), -1.0),
            DVec4::new(0.0, 0.0, n * f / (n - f), 0.0),
        )
    }

    /// World → clip.
    pub fn view_proj(&self, aspect: f64) -> DMat4 {
        self.proj(aspect) * self.view()
    }

    /// Normalized device coordinates (x, y ∈ [−1, 1], z ∈ [0, 1]) of `p`;
    /// `None` behind the eye.
    pub fn to_ndc(&self, p: DVec3, aspect: f64) -> Option<DVec3> {
        let c = self.view_proj(aspect) * p.extend(1.0);
        (c.w > 1e-12).then(|| c.truncate() / c.w)
    }

    /// Screen position of `p` in a viewport of `size` (pixels or points,
    /// origin top left, y down).
    pub fn project(&self, p: DVec3, size: DVec2) -> Option<DVec2> {
        let n = self.to_ndc(p, size.x / size.y)?;
        Some(DVec2::new((n.x + 1.0) * 0.5 * size.x, (1.0 - n.y) * 0.5 * size.y))
    }

    /// The ray (origin at the eye, unit direction) through screen position
    /// `s` of a viewport of `size` — the inverse of [`Camera::project`].
    pub fn ray(&self, s: DVec2, size: DVec2) -> (DVec3, DVec3) {
        let aspect = size.x / size.y;
        let nx = 2.0 * s.x / size.x - 1.0;
        let ny = 1.0 - 2.0 * s.y / size.y;
        let t = (self.fov_y * 0.5).tan();
        let (r, u, b) = self.basis();
        let dir = (r * (nx * t * aspect) + u * (ny * t) - b).normalize();
        (self.eye(), dir)
    }

    /// Rotate by screen drag `(dx, dy)` in radians.
    pub fn orbit(&mut self, dx: f64, dy: f64) {
        self.yaw -= dx;
        self.pitch = (self.pitch + dy).clamp(-std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2);
    }

    /// Move the target by a screen drag of `(dx, dy)` in a viewport of height
    /// `h` (same units), so that the point under the pointer follows it.
    pub fn pan(&mut self, dx: f64, dy: f64, h: f64) {
        let (r, u, _) = self.basis();
        let world_per_unit = 2.0 * self.dist * (self.fov_y * 0.5).tan() / h.max(1e-9);
        self.target += (-dx * r + dy * u) * world_per_unit;
    }

    /// Multiply the distance by `factor` (> 1 zooms out).
    pub fn zoom(&mut self, factor: f64) {
        if factor.is_finite() && factor > 0.0 {
            self.dist = (self.dist * factor).clamp(self.scene_radius * 1e-4, self.scene_radius * 1e4);
        }
    }

    /// Set a standard view direction (keeps target and distance).
    pub fn set_view(&mut self, v: StandardView) {
        (self.yaw, self.pitch) = v.angles();
    }

    /// Aim at the box `[lo, hi]` and back off so that its bounding sphere fits
    /// in a viewport of `aspect` (width/height) with a small margin.
    pub fn fit(&mut self, lo: DVec3, hi: DVec3, aspect: f64) {
        let c = 0.5 * (lo + hi);
        let r = (0.5 * (hi - lo).length()).max(1e-9);
        let half_y = self.fov_y * 0.5;
        let half_x = (half_y.tan() * aspect.max(1e-6)).atan();
        let half = half_y.min(half_x);
        self.target = c;
        self.scene_radius = r;
        self.dist = 1.05 * r / half.sin();
    }
}

/// Bounding box of points (`None` if empty).
pub fn bbox(points: impl IntoIterator<Item = DVec3>) -> Option<(DVec3, DVec3)> {
    let mut it = points.into_iter();
    let first = it.next()?;
    Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cams() -> Vec<Camera> {
        let mut out = vec![];
        for v in [
            StandardView::Front,
            StandardView::Top,
            StandardView::Side,
            StandardView::Iso,
        ] {
            let mut c = Camera::default();
            c.set_view(v);
            c.target = DVec3::new(0.3, -1.0, 2.0);
            c.dist = 7.0;
            c.scene_radius = 3.0;
            out.push(c);
        }
        let mut c = Camera::default();
        c.orbit(0.7, -0.4);
        out.push(c);
        out
    }

    #[test]
    fn view_basis_is_orthonormal_and_right_handed() {
        for c in cams() {
            let (r, u, b) = c.basis();
            for (x, y) in [(r, u), (u, b), (b, r)] {
                assert!(x.dot(y).abs() < 1e-12);
            }
            for x in [r, u, b] {
                assert!((x.length() - 1.0).abs() < 1e-12);
            }
            assert!((r.cross(u) - b).length() < 1e-12);
            // the target is straight ahead, at distance dist
            let t = c.view().transform_point3(c.target);
            assert!(t.truncate().length() < 1e-9 && (t.z + c.dist).abs() < 1e-9, "{t}");
        }
    }

    #[test]
    fn project_then_ray_passes_through_the_point() {
        let size = DVec2::new(800.0, 500.0);
        for c in cams() {
            for p in [
                c.target,
                c.target + DVec3::new(0.5, -0.7, 0.9),
                c.target + DVec3::new(-1.2, 0.4, -0.3),
            ] {
                let s = c.project(p, size).unwrap();
                let (o, d) = c.ray(s, size);
                let dist_to_ray = (p - o).cross(d).length();
                assert!(dist_to_ray < 1e-9, "{dist_to_ray}");
                // and the ray's points project back to s
                let q = o + d * 3.3;
                let s2 = c.project(q, size).unwrap();
                assert!((s2 - s).length() < 1e-9);
            }
        }
    }

    #[test]
    fn depth_is_in_unit_range_inside_the_scene_sphere() {
        for c in cams() {
            for k in 0..50 {
                let t = k as f64 * 0.61;
                let dir = DVec3::new(t.cos() * (t * 0.3).sin(), t.sin() * (t * 0.3).sin(), (t * 0.3).cos());
                let p = c.target + dir * c.scene_radius * 0.999;
                let n = c.to_ndc(p, 1.6).unwrap();
                assert!((0.0..=1.0).contains(&n.z), "{n}");
            }
        }
    }

    #[test]
    fn fit_all_contains_the_bounding_box() {
        let (lo, hi) = (DVec3::new(-1.0, 2.0, 0.0), DVec3::new(5.0, 3.0, 0.4));
        for aspect in [0.5, 1.0, 2.5] {
            for mut c in cams() {
                c.fit(lo, hi, aspect);
                for k in 0..8 {
                    let p = DVec3::new(
                        if k & 1 == 0 { lo.x } else { hi.x },
                        if k & 2 == 0 { lo.y } else { hi.y },
                        if k & 4 == 0 { lo.z } else { hi.z },
                    );
                    let n = c.to_ndc(p, aspect).unwrap();
                    assert!(
                        n.x.abs() <= 1.0 && n.y.abs() <= 1.0,
                        "corner {p} -> {n} (aspect {aspect})"
                    );
                    assert!((0.0..=1.0).contains(&n.z));
                }
            }
        }
    }

    #[test]
    fn pan_moves_the_point_under_the_pointer_with_it() {
        let size = DVec2::new(640.0, 480.0);
        let mut c = Camera::default();
        let p = c.target;
        let s0 = c.project(p, size).unwrap();
        c.pan(40.0, -25.0, size.y);
        let s1 = c.project(p, size).unwrap();
        // p sits at the target depth, where the pan is exact
        assert!((s1 - s0 - DVec2::new(40.0, -25.0)).length() < 1e-9, "{}", s1 - s0);
    }

    #[test]
    fn standard_views_look_along_the_axes() {
        let mut c = Camera::default();
        c.set_view(StandardView::Top);
        assert!((c.eye_dir() - DVec3::Z).length() < 1e-12);
        c.set_view(StandardView::Front);
        assert!((c.eye_dir() + DVec3::Y).length() < 1e-12);
        c.set_view(StandardView::Side);
        assert!((c.eye_dir() - DVec3::X).length() < 1e-12);
        c.set_view(StandardView::Iso);
        assert!((c.eye_dir() - DVec3::new(1.0, -1.0, 1.0).normalize()).length() < 1e-12);
    }
}
