//! Exact triangle-box overlap by the separating axis theorem (Akenine-Möller, "Fast 3D
//! Triangle-Box Overlap Testing", JGT 2001): 13 candidate axes, the box's three face
//! normals, the triangle's normal and the nine cross products of their edges. Also the
//! bounds of a triangle clipped to a box (Sutherland and Hodgman 1974), which k-d tree
//! builds use for "perfect splits" (Havran 2000; Wald and Havran 2006).

use glam::{DVec3, Vec3};
use penumbra_core::Aabb;

/// Whether triangle `v` and box `b` may share a point (touching counts). Accelerators use
/// the answer to leave a triangle out of a cell, so it errs towards overlap: an axis
/// separates only by more than the test's rounding error (a relative slack of `SLACK` of
/// the coordinates' magnitude), which matters for tiny triangles in huge cells.
pub fn triangle_overlaps_box(v: [Vec3; 3], b: &Aabb) -> bool {
    let c = b.centroid();
    let h = 0.5 * (b.max - b.min);
    let [v0, v1, v2] = v.map(|p| p - c);
    let lo = v0.min(v1).min(v2);
    let hi = v0.max(v1).max(v2);
    let scale = c.abs().max_element() + h.max_element() + lo.abs().max(hi.abs()).max_element();
    // The slack for projections on axis `a`.
    let slack = |a: Vec3| SLACK * scale * (a.x.abs() + a.y.abs() + a.z.abs());
    // The box's face normals: the triangle's bounds against the box.
    let s = SLACK * scale;
    if lo.cmpgt(h + s).any() || hi.cmplt(-h - s).any() {
        return false;
    }
    // The triangle's plane against the box.
    let e = [v1 - v0, v2 - v1, v0 - v2];
    let n = e[0].cross(e[1]);
    let r = h.dot(n.abs()) + slack(n);
    let d = n.dot(v0);
    if d > r || d < -r {
        return false;
    }
    // The nine edge cross products.
    for edge in e {
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            let a = axis.cross(edge);
            if a == Vec3::ZERO {
                continue;
            }
            let (p0, p1, p2) = (a.dot(v0), a.dot(v1), a.dot(v2));
            let r = h.dot(a.abs()) + slack(a);
            if p0.min(p1).min(p2) > r || p0.max(p1).max(p2) < -r {
                return false;
            }
        }
    }
    true
}

/// Bounds of the part of triangle `v` inside box `b`: the triangle clipped by the box's six
/// planes in double precision, widened by the same rounding slack as
/// [`triangle_overlaps_box`] and cut to `b` and to the triangle's bounds. Empty when they do not meet.
pub fn triangle_clipped_bounds(v: [Vec3; 3], b: &Aabb) -> Aabb {
    let tri = Aabb::from_points(v);
    let scale = b.min.abs().max(b.max.abs()).max_element() + tri.min.abs().max(tri.max.abs()).max_element();
    let s = (SLACK * scale) as f64;
    let (lo, hi) = (b.min.as_dvec3() - s, b.max.as_dvec3() + s);
    // A triangle cut by six planes has at most nine corners.
    let mut poly = [DVec3::ZERO; 9];
    let mut next = [DVec3::ZERO; 9];
    poly[..3].copy_from_slice(&v.map(|p| p.as_dvec3()));
    let mut len = 3;
    for axis in 0..3 {
        for (plane, keep_above) in [(lo[axis], true), (hi[axis], false)] {
            let inside = |p: DVec3| if keep_above { p[axis] >= plane } else { p[axis] <= plane };
            let mut m = 0;
            for i in 0..len {
                let (p, q) = (poly[i], poly[(i + 1) % len]);
                if inside(p) {
                    next[m] = p;
                    m += 1;
                }
                if inside(p) != inside(q) {
                    let t = (plane - p[axis]) / (q[axis] - p[axis]);
                    let mut x = p + (q - p) * t;
                    x[axis] = plane;
                    next[m] = x;
                    m += 1;
                }
            }
            std::mem::swap(&mut poly, &mut next);
            len = m;
            if len == 0 {
                return Aabb::EMPTY;
            }
        }
    }
    let (mut min, mut max) = (poly[0], poly[0]);
    for p in &poly[1..len] {
        min = min.min(*p);
        max = max.max(*p);
    }
    let s = s as f32;
    Aabb {
        min: min.as_vec3() - s,
        max: max.as_vec3() + s,
    }
    .intersection(tri)
    .intersection(*b)
}

/// Relative rounding slack of [`triangle_overlaps_box`]: about a hundred float epsilons.
const SLACK: f32 = 1e-5;

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_core::Pcg32;

    #[test]
    fn obvious_cases() {
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let inside = [Vec3::splat(0.2), Vec3::splat(0.3), Vec3::new(0.2, 0.5, 0.3)];
        assert!(triangle_overlaps_box(inside, &b));
        let far = inside.map(|p| p + Vec3::X * 5.0);
        assert!(!triangle_overlaps_box(far, &b));
        // A large triangle cutting through the box with every vertex outside it.
        let big = [
            Vec3::new(-10.0, -10.0, 0.5),
            Vec3::new(10.0, -10.0, 0.5),
            Vec3::new(0.0, 10.0, 0.5),
        ];
        assert!(triangle_overlaps_box(big, &b));
        // Near the corner but separated only along an edge-cross-product axis.
        let corner = [
            Vec3::new(1.5, 0.0, 0.5),
            Vec3::new(0.0, 1.5, 0.5),
            Vec3::new(1.6, 1.6, 0.5),
        ];
        assert!(!triangle_overlaps_box(corner.map(|p| p + Vec3::new(0.3, 0.3, 0.0)), &b));
    }

    #[test]
    fn clipped_bounds_hold_every_point_inside_the_box_and_are_tight() {
        // Every sampled point of the triangle inside the box lies in the clipped bounds.
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let mut rng = Pcg32::new(9, 0);
        let mut point = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 3.0 - Vec3::ONE;
        let mut clipped_smaller = 0;
        for _ in 0..2000 {
            let t = [point(), point(), point()];
            let c = triangle_clipped_bounds(t, &b);
            let mut seen = Aabb::EMPTY;
            let steps = 60;
            for i in 0..=steps {
                for j in 0..=steps - i {
                    let (u, v) = (i as f32 / steps as f32, j as f32 / steps as f32);
                    let p = t[0] + u * (t[1] - t[0]) + v * (t[2] - t[0]);
                    if p.cmpge(b.min).all() && p.cmple(b.max).all() {
                        // (The sample itself carries f32 rounding of a few 1e-7.)
                        let inside = p.cmpge(c.min - 1e-6).all() && p.cmple(c.max + 1e-6).all();
                        assert!(inside, "{t:?}: {p} outside {c:?}");
                        seen = seen.grow(p);
                    }
                }
            }
            if seen.is_empty() {
                continue;
            }
            // Never larger than the bounding box cut to the box; exactly the triangle's
            // bounds (up to the slack) when the triangle lies inside.
            let whole = Aabb::from_points(t).intersection(b);
            assert!(c.min.cmpge(whole.min).all() && c.max.cmple(whole.max).all());
            if t.iter().all(|p| p.cmpge(b.min).all() && p.cmple(b.max).all()) {
                assert!(
                    (c.min - whole.min).abs().max_element() < 1e-4 && (c.max - whole.max).abs().max_element() < 1e-4
                );
            }
            clipped_smaller += (c.extent().x * c.extent().y * c.extent().z
                < 0.9 * whole.extent().x * whole.extent().y * whole.extent().z) as u32;
        }
        // Clipping must actually cut: many triangles' clipped boxes are well inside box & bounds.
        assert!(clipped_smaller > 200, "{clipped_smaller}");
        let inside = [Vec3::splat(0.2), Vec3::splat(0.3), Vec3::new(0.2, 0.5, 0.3)];
        let c = triangle_clipped_bounds(inside, &b);
        assert!((c.min - Vec3::splat(0.2)).abs().max_element() < 1e-4);
        assert!((c.max - Vec3::new(0.3, 0.5, 0.3)).abs().max_element() < 1e-4);
        assert!(triangle_clipped_bounds([Vec3::splat(2.0), Vec3::splat(3.0), Vec3::new(2.0, 3.0, 2.5)], &b).is_empty());
    }

    #[test]
    fn agrees_with_dense_sampling() {
        // No sampled point of the triangle inside the box => no overlap claimed beyond a thin
        // tolerance; a sampled point inside => overlap claimed.
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let mut rng = Pcg32::new(5, 0);
        let mut point = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 3.0 - Vec3::ONE;
        for _ in 0..2000 {
            let t = [point(), point(), point()];
            let mut any_inside = false;
            let steps = 60;
            for i in 0..=steps {
                for j in 0..=steps - i {
                    let (u, v) = (i as f32 / steps as f32, j as f32 / steps as f32);
                    let p = t[0] + u * (t[1] - t[0]) + v * (t[2] - t[0]);
                    any_inside |= p.cmpge(b.min).all() && p.cmple(b.max).all();
                }
            }
            if any_inside {
                assert!(triangle_overlaps_box(t, &b), "{t:?}");
            }
        }
    }
}
