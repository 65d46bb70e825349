//! The watertight ray-triangle test of Woop, Benthin and Wald, "Watertight Ray/Triangle
//! Intersection" (JCGT 2013): the ray is sheared to the +z axis and the edge functions are
//! evaluated in that frame, falling back to double precision when one is exactly zero, so a
//! ray never slips between triangles that share an edge. A top-left rule (as in
//! rasterisation) breaks the tie when the ray runs exactly through the edge, so it hits
//! exactly one of the two triangles.

use glam::{DVec3, Vec2, Vec3};
use penumbra_core::Ray;

/// What the watertight test needs of a ray, computed once per ray: the permutation that
/// makes z the dominant direction (`axes`) and the shear that aligns the ray with +z. A
/// vertex `q` maps to `x' = d[kx] + sx d[kz]`, `y' = d[ky] + sy d[kz]`, `z' = d[kz]` with
/// `d = q - origin`; the scalar and the four-wide tests compute exactly these floats.
#[derive(Clone, Copy, Debug)]
pub struct TriangleRay {
    /// The origin's coordinates in the permuted order: `[origin[kx], origin[ky], origin[kz]]`.
    pub(crate) origin: [f32; 3],
    /// The axes that become x, y and z.
    pub(crate) axes: [usize; 3],
    /// `(sx, sy, sz)`: the shear, and 1 / (the dominant direction component), which scales
    /// z' to ray distance.
    pub(crate) shear: Vec3,
}

impl TriangleRay {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        // z is the dominant axis, x and y the two after it in cyclic order; the components
        // are read from arrays by index.
        let d = ray.dir.to_array();
        let kz = dominant_axis(ray.dir);
        let (kx, ky) = (NEXT[kz], NEXT[NEXT[kz]]);
        let (dx, dy, dz) = (d[kx], d[ky], d[kz]);
        let o = ray.origin.to_array();
        let sz = 1.0 / dz;
        TriangleRay {
            origin: [o[kx], o[ky], o[kz]],
            axes: [kx, ky, kz],
            shear: Vec3::new(-dx * sz, -dy * sz, sz),
        }
    }

    /// Vertex `q` in the ray's sheared frame.
    #[inline(always)]
    fn sheared(&self, q: Vec3) -> Vec3 {
        let [kx, ky, kz] = self.axes;
        let q = q.to_array();
        let [ox, oy, oz] = self.origin;
        let dz = q[kz] - oz;
        Vec3::new((q[kx] - ox) + self.shear.x * dz, (q[ky] - oy) + self.shear.y * dz, dz)
    }
}

/// The axis after each in cyclic order.
const NEXT: [usize; 3] = [1, 2, 0];

/// The axis of the largest |component| of `dir`, the first of equal ones (as
/// `Vec3::max_position`): the watertight test's z. Chosen without branches: the dominant
/// axis of a scattered ray is a coin toss that a branch predictor loses about half the
/// time (cachegrind's branch simulation put 0.9 mispredictions per ray here); the
/// conditions become flags and the axis a conditional move.
#[inline(always)]
pub fn dominant_axis(dir: Vec3) -> usize {
    let a = dir.abs().to_array();
    let y_first = a[1] > a[0];
    let kz = y_first as usize;
    let max = if y_first { a[1] } else { a[0] };
    if a[2] > max {
        2
    } else {
        kz
    }
}

/// Distance and barycentrics `(b1, b2)` of the hit of `ray` with triangle `p`, if it lies in
/// `(0, t_max)`. Degenerate triangles are never hit.
#[inline]
pub fn intersect_triangle(ray: &Ray, p: [Vec3; 3], t_max: f32) -> Option<(f32, Vec2)> {
    intersect_triangle_prepared(&TriangleRay::new(ray), p, t_max)
}

/// [`intersect_triangle`] with the ray's permutation and shear already computed.
#[inline]
pub fn intersect_triangle_prepared(r: &TriangleRay, p: [Vec3; 3], t_max: f32) -> Option<(f32, Vec2)> {
    let (p0, p1, p2) = (r.sheared(p[0]), r.sheared(p[1]), r.sheared(p[2]));
    let mut e0 = p1.x * p2.y - p1.y * p2.x;
    let mut e1 = p2.x * p0.y - p2.y * p0.x;
    let mut e2 = p0.x * p1.y - p0.y * p1.x;
    if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
        let (a, b, c) = (DVec3::from(p0), DVec3::from(p1), DVec3::from(p2));
        e0 = (b.x * c.y - b.y * c.x) as f32;
        e1 = (c.x * a.y - c.y * a.x) as f32;
        e2 = (a.x * b.y - a.y * b.x) as f32;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return None;
    }
    // Inside when every edge function has the sign of det; a zero edge function (the ray
    // meets the edge's line) counts for one of the two triangles sharing that edge only.
    // The tie-break follows the triangle's facing, so it holds for either winding.
    let inside = |e: f32, a: Vec3, b: Vec3| {
        if e == 0.0 {
            top_left(a, b) != (det < 0.0)
        } else {
            (e > 0.0) == (det > 0.0)
        }
    };
    if !(inside(e0, p1, p2) && inside(e1, p2, p0) && inside(e2, p0, p1)) {
        return None;
    }
    let sz = r.shear.z;
    let t_scaled = (e0 * p0.z + e1 * p1.z + e2 * p2.z) * sz;
    if det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det) {
        return None;
    }
    if det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det) {
        return None;
    }
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    (t > 0.0 && t < t_max).then(|| (t, Vec2::new(e1 * inv_det, e2 * inv_det)))
}

/// The tie-break for a ray exactly on the edge from `a` to `b` (in the sheared frame): the
/// reversed edge, as seen by the neighbouring triangle, gives the opposite answer.
#[inline]
fn top_left(a: Vec3, b: Vec3) -> bool {
    let d = b - a;
    d.y > 0.0 || (d.y == 0.0 && d.x < 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_core::Pcg32;

    /// How many of the two triangles splitting the unit square along its diagonal `ray` hits,
    /// for both windings of the second triangle (as in meshes with inconsistent winding).
    fn square_hits(ray: &Ray) -> [usize; 2] {
        let a = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        let b = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let b_reversed = [b[0], b[2], b[1]];
        let count = |tris: [[Vec3; 3]; 2]| {
            tris.iter()
                .filter(|&&t| intersect_triangle(ray, t, f32::INFINITY).is_some())
                .count()
        };
        [count([a, b]), count([a, b_reversed])]
    }

    const TRI: [Vec3; 3] = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];

    #[test]
    fn hit_miss_and_barycentrics() {
        let ray = Ray::new(Vec3::new(0.25, 0.5, 1.0), Vec3::NEG_Z);
        let (t, b) = intersect_triangle(&ray, TRI, f32::INFINITY).unwrap();
        assert_eq!(t, 1.0);
        assert!((b - Vec2::new(0.25, 0.5)).length() < 1e-6);
        // From behind: triangles are two-sided.
        assert!(intersect_triangle(&Ray::new(Vec3::new(0.25, 0.25, -1.0), Vec3::Z), TRI, f32::INFINITY).is_some());
        assert!(intersect_triangle(&Ray::new(Vec3::new(0.75, 0.75, 1.0), Vec3::NEG_Z), TRI, f32::INFINITY).is_none());
        assert!(intersect_triangle(&ray, TRI, 0.5).is_none(), "t_max respected");
        assert!(
            intersect_triangle(&Ray::new(Vec3::new(0.25, 0.25, 1.0), Vec3::Z), TRI, 9.0).is_none(),
            "behind"
        );
    }

    #[test]
    fn axis_aligned_ray_exactly_on_the_edge_hits_one() {
        for (origin, dir) in [
            (Vec3::new(0.5, 0.5, 1.0), Vec3::NEG_Z),
            (Vec3::new(0.5, 0.5, -1.0), Vec3::Z),
            (Vec3::new(0.25, 0.25, 2.0), Vec3::new(0.25, 0.25, -2.0)),
        ] {
            assert_eq!(square_hits(&Ray::new(origin, dir)), [1, 1], "{origin} {dir}");
        }
    }

    #[test]
    fn degenerate_triangles_never_hit() {
        let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        let point = [Vec3::ONE; 3];
        for dir in [Vec3::NEG_Z, Vec3::NEG_Y, Vec3::new(1.0, -1.0, -1.0)] {
            let ray = Ray::new(Vec3::new(0.5, 0.0, 0.0) - dir, dir);
            assert!(intersect_triangle(&ray, line, f32::INFINITY).is_none());
            assert!(intersect_triangle(&Ray::new(Vec3::ONE - dir, dir), point, f32::INFINITY).is_none());
        }
    }

    #[test]
    fn shared_edge_is_watertight() {
        // Two triangles sharing the diagonal of the unit square, hit by rays aimed at points of
        // the diagonal from random origins: each ray hits exactly one triangle.
        let mut rng = Pcg32::new(1, 2);
        for _ in 0..20_000 {
            let s = rng.next_f32();
            let target = Vec3::new(s, s, 0.0);
            let origin = Vec3::new(
                rng.next_f32() * 4.0 - 2.0,
                rng.next_f32() * 4.0 - 2.0,
                0.5 + rng.next_f32() * 3.0,
            );
            let ray = Ray::new(origin, target - origin);
            let hits = square_hits(&ray);
            assert_eq!(hits, [1, 1], "ray through the shared edge at {target}");
        }
    }
}
