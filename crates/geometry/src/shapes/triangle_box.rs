//! Exact triangle-box overlap by the separating axis theorem (Akenine-Möller, "Fast 3D
//! Triangle-Box Overlap Testing", JGT 2001): 13 candidate axes, the box's three face
//! normals, the triangle's normal and the nine cross products of their edges.

use glam::Vec3;
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
