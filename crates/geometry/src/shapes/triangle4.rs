//! Four triangles tested against one ray at once: the watertight test of
//! [`super::triangle`] (Woop, Benthin and Wald, JCGT 2013) in structure-of-arrays form, one
//! SIMD lane per triangle, as Embree's `Triangle4` leaves do.
//!
//! Every lane computes exactly the floats the scalar test computes (the same products and
//! sums in the same order), and a lane whose edge function is exactly zero, where the
//! scalar test falls back to double precision and the tie rule, is handed to the scalar
//! test. So the packet answers exactly as four scalar tests would, bit for bit.

use super::triangle::{intersect_triangle_prepared, TriangleRay};
use glam::{Vec2, Vec3, Vec4};
use penumbra_core::lanes::Lane8;

/// Rays of a packet in the watertight test's frame, one SIMD lane each, sharing its
/// permutation (`axes`): each lane's permuted origin and shear, as [`TriangleRay`] holds
/// them.
#[derive(Clone, Copy, Debug)]
pub struct TriangleRays {
    axes: [usize; 3],
    origin: [[f32; 8]; 3],
    shear: [[f32; 8]; 3],
}

impl TriangleRays {
    /// The lanes of `data`, if they share one permutation.
    pub fn new(data: &[TriangleRay; 8]) -> Option<Self> {
        let axes = data[0].axes;
        let mut rays = TriangleRays {
            axes,
            origin: [[0.0; 8]; 3],
            shear: [[0.0; 8]; 3],
        };
        for (j, d) in data.iter().enumerate() {
            if d.axes != axes {
                return None;
            }
            for axis in 0..3 {
                rays.origin[axis][j] = d.origin[axis];
                rays.shear[axis][j] = d.shear[axis];
            }
        }
        Some(rays)
    }
}

/// Where the rays of a packet hit one of the four triangles: per lane, which triangle and
/// the barycentrics (the distances are the rays' new `t_max`), for the lanes in `mask`.
pub struct RaysHit {
    pub mask: u32,
    pub which: [u32; 8],
    pub b1: [f32; 8],
    pub b2: [f32; 8],
}

impl RaysHit {
    /// Each hit lane's `Hit` into `hits`: its distance (the lane's `t_max` after
    /// [`Triangle4::closest_rays`]), the number `prim(k)` of the triangle in lane `k`, its
    /// barycentrics.
    #[inline(always)]
    pub fn write(&self, t_max: &[f32; 8], hits: &mut [Option<crate::Hit>; 8], prim: impl Fn(usize) -> u32) {
        for j in (0..8).filter(|j| self.mask >> j & 1 != 0) {
            hits[j] = Some(crate::Hit {
                t: t_max[j],
                prim: prim(self.which[j] as usize),
                sub: 0,
                uv: Vec2::new(self.b1[j], self.b2[j]),
            });
        }
    }
}

/// One triangle against a packet's rays: the lanes hit without the scalar fallback
/// (`valid`), those that need it, and every lane's distance and barycentrics.
struct RayLanes<L: Lane8> {
    valid: L::Mask,
    fallback: u32,
    t: L,
    b1: L,
    b2: L,
}

/// Four triangles: `v[3 * k + axis]` holds coordinate `axis` of vertex `k`, one triangle per
/// lane. Unused lanes hold NaN vertices, which no ray hits.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct Triangle4 {
    v: [Vec4; 9],
}

/// The hit of one lane: lane, distance, barycentrics `(b1, b2)`.
pub type LaneHit = (usize, f32, Vec2);

impl Triangle4 {
    /// Four empty lanes.
    pub const EMPTY: Triangle4 = Triangle4 { v: [Vec4::NAN; 9] };

    /// Packs `triangles` (at most four) into lanes `0..triangles.len()`.
    pub fn pack(triangles: &[[Vec3; 3]]) -> Self {
        let mut packet = Self::EMPTY;
        for (lane, tri) in triangles.iter().enumerate() {
            packet.set(lane, *tri);
        }
        packet
    }

    pub fn set(&mut self, lane: usize, tri: [Vec3; 3]) {
        for (k, p) in tri.iter().enumerate() {
            for axis in 0..3 {
                self.v[3 * k + axis][lane] = p[axis];
            }
        }
    }

    /// The triangle in `lane`.
    #[inline]
    pub fn get(&self, lane: usize) -> [Vec3; 3] {
        let vertex = |k: usize| Vec3::new(self.v[3 * k][lane], self.v[3 * k + 1][lane], self.v[3 * k + 2][lane]);
        [vertex(0), vertex(1), vertex(2)]
    }

    /// The closest hit in `(0, t_max)` among the lanes set in `active`; of equal distances
    /// the lowest lane wins.
    #[inline(always)]
    pub fn closest(&self, r: &TriangleRay, t_max: f32, active: u32) -> Option<LaneHit> {
        let hits = self.test(r, t_max, active);
        if hits.fallback != 0 {
            return self.closest_with_fallback(r, t_max, &hits);
        }
        let lane_hit = |lane: usize| (lane, hits.t[lane], Vec2::new(hits.b1[lane], hits.b2[lane]));
        if hits.mask & hits.mask.wrapping_sub(1) == 0 {
            // No lane or one, the common case.
            return (hits.mask != 0).then(|| lane_hit(hits.mask.trailing_zeros() as usize));
        }
        // The smallest distance among the active hit lanes, the lowest lane of equal ones
        // (lanes outside `active`, another leaf's triangles, are skipped).
        let mut lanes = hits.mask;
        let mut best: Option<LaneHit> = None;
        while lanes != 0 {
            let lane = lanes.trailing_zeros() as usize;
            lanes &= lanes - 1;
            if best.is_none_or(|b| hits.t[lane] < b.1) {
                best = Some(lane_hit(lane));
            }
        }
        best
    }

    /// [`Triangle4::closest`] when some lanes need the scalar test.
    #[cold]
    #[inline(never)]
    fn closest_with_fallback(&self, r: &TriangleRay, t_max: f32, hits: &Lanes) -> Option<LaneHit> {
        let mut best: Option<LaneHit> = None;
        for lane in 0..4 {
            let bit = 1u32 << lane;
            let hit = if hits.mask & bit != 0 {
                Some((hits.t[lane], Vec2::new(hits.b1[lane], hits.b2[lane])))
            } else if hits.fallback & bit != 0 {
                intersect_triangle_prepared(r, self.get(lane), t_max)
            } else {
                continue;
            };
            if let Some((t, b)) = hit {
                if best.is_none_or(|best| t < best.1) {
                    best = Some((lane, t, b));
                }
            }
        }
        best
    }

    /// Whether any lane set in `active` is hit in `(0, t_max)`.
    #[inline(always)]
    pub fn any(&self, r: &TriangleRay, t_max: f32, active: u32) -> bool {
        let hits = self.test(r, t_max, active);
        hits.mask != 0 || (hits.fallback != 0 && self.any_fallback(r, t_max, hits.fallback))
    }

    #[cold]
    #[inline(never)]
    fn any_fallback(&self, r: &TriangleRay, t_max: f32, lanes: u32) -> bool {
        (0..4).any(|lane| lanes & (1 << lane) != 0 && intersect_triangle_prepared(r, self.get(lane), t_max).is_some())
    }

    /// The SIMD part of the test: lanes hit without needing the scalar fallback, and the
    /// lanes that need it.
    #[inline(always)]
    fn test(&self, r: &TriangleRay, t_max: f32, active: u32) -> Lanes {
        let [kx, ky, kz] = r.axes;
        let (sx, sy) = (Vec4::splat(r.shear.x), Vec4::splat(r.shear.y));
        // The origin already permuted (a `Vec4` array indexed by an axis became a jump
        // table, its target a coin toss).
        let origin = r.origin.map(Vec4::splat);
        // Each vertex relative to the origin, permuted so z is the dominant axis, sheared.
        let vertex = |k: usize| {
            let dz = self.v[3 * k + kz] - origin[2];
            (
                (self.v[3 * k + kx] - origin[0]) + sx * dz,
                (self.v[3 * k + ky] - origin[1]) + sy * dz,
                dz,
            )
        };
        let (p0, p1, p2) = (vertex(0), vertex(1), vertex(2));
        let e0 = p1.0 * p2.1 - p1.1 * p2.0;
        let e1 = p2.0 * p0.1 - p2.1 * p0.0;
        let e2 = p0.0 * p1.1 - p0.1 * p1.0;
        let zero = Vec4::ZERO;
        let fallback = (e0.cmpeq(zero) | e1.cmpeq(zero) | e2.cmpeq(zero)).bitmask() & active;
        let det = e0 + e1 + e2;
        let positive = e0.cmpgt(zero) & e1.cmpgt(zero) & e2.cmpgt(zero);
        let negative = e0.cmplt(zero) & e1.cmplt(zero) & e2.cmplt(zero);
        let t_scaled = (e0 * p0.2 + e1 * p1.2 + e2 * p2.2) * Vec4::splat(r.shear.z);
        let limit = Vec4::splat(t_max) * det;
        let in_range = (positive & t_scaled.cmpgt(zero) & t_scaled.cmple(limit))
            | (negative & t_scaled.cmplt(zero) & t_scaled.cmpge(limit));
        let inv_det = Vec4::ONE / det;
        let t = t_scaled * inv_det;
        let valid = in_range & t.cmpgt(zero) & t.cmplt(Vec4::splat(t_max));
        Lanes {
            mask: valid.bitmask() & active & !fallback,
            fallback,
            t: t.to_array(),
            b1: (e1 * inv_det).to_array(),
            b2: (e2 * inv_det).to_array(),
        }
    }
}

/// The packet tests: each triangle against up to eight rays at once, one ray per lane,
/// with exactly the floats of `Triangle4::test` (which are the scalar test's).
impl Triangle4 {
    /// [`Triangle4::closest`] for the rays `rays` of a packet (their data `data`, in the
    /// frame `r`), among the triangles `tris`: the triangles taken in lane order, each
    /// against every ray, keeping a ray's nearest (the lowest lane of equal ones), as the
    /// one-ray test does. A hit ray's `t_max` becomes its distance.
    #[inline(always)]
    pub fn closest_rays<L: Lane8>(
        &self,
        r: &TriangleRays,
        data: &[TriangleRay; 8],
        (tris, rays): (u32, u32),
        t_max: &mut [f32; 8],
    ) -> Option<RaysHit> {
        let t0 = L::from_array(*t_max);
        let active = lanes_of::<L>(rays);
        let zero = L::splat(0.0);
        let (mut best, mut b1, mut b2, mut which) = (t0, zero, zero, zero);
        let mut hit = 0;
        let mut left = tris;
        while left != 0 {
            let k = left.trailing_zeros() as usize;
            left &= left - 1;
            let h = self.test_rays::<L>(k, r, t0, active);
            let take = L::and(h.valid, h.t.cmp_lt(best));
            best = L::select(take, h.t, best);
            b1 = L::select(take, h.b1, b1);
            b2 = L::select(take, h.b2, b2);
            which = L::select(take, L::splat(k as f32), which);
            hit |= L::bits(take);
            if h.fallback != 0 {
                let mut lanes = [best.to_array(), b1.to_array(), b2.to_array(), which.to_array()];
                hit |= self.closest_fallback_rays(k, data, h.fallback, t_max, &mut lanes);
                let [t, u, v, w] = lanes;
                (best, b1, b2, which) = (L::from_array(t), L::from_array(u), L::from_array(v), L::from_array(w));
            }
        }
        if hit == 0 {
            return None;
        }
        *t_max = best.to_array();
        Some(RaysHit {
            mask: hit,
            which: which.to_array().map(|w| w as u32),
            b1: b1.to_array(),
            b2: b2.to_array(),
        })
    }

    /// The rays of `lanes` whose test of triangle `k` needs the scalar fallback: each
    /// taken where nearer than its best so far (`best`: distances, barycentrics, lanes).
    #[cold]
    #[inline(never)]
    fn closest_fallback_rays(
        &self,
        k: usize,
        data: &[TriangleRay; 8],
        lanes: u32,
        t_max: &[f32; 8],
        best: &mut [[f32; 8]; 4],
    ) -> u32 {
        let mut hit = 0;
        for j in (0..8).filter(|j| lanes >> j & 1 != 0) {
            if let Some((t, b)) = intersect_triangle_prepared(&data[j], self.get(k), t_max[j]) {
                if t < best[0][j] {
                    (best[0][j], best[1][j], best[2][j], best[3][j]) = (t, b.x, b.y, k as f32);
                    hit |= 1 << j;
                }
            }
        }
        hit
    }

    /// Triangle `k` against every lane of `r` within its `t_max`, for the lanes `active`:
    /// [`Triangle4::test`]'s floats with the roles of lanes swapped (there a triangle per
    /// lane, here a ray per lane).
    #[inline(always)]
    fn test_rays<L: Lane8>(&self, k: usize, r: &TriangleRays, t_max: L, active: L::Mask) -> RayLanes<L> {
        // No closures make lane values here: a closure is compiled apart from the caller's
        // SIMD level, its intrinsics then calls.
        let origin = [
            L::from_array(r.origin[0]),
            L::from_array(r.origin[1]),
            L::from_array(r.origin[2]),
        ];
        let shear = (L::from_array(r.shear[0]), L::from_array(r.shear[1]));
        let p0 = self.sheared_corner::<L>(0, k, r.axes, &origin, shear);
        let p1 = self.sheared_corner::<L>(1, k, r.axes, &origin, shear);
        let p2 = self.sheared_corner::<L>(2, k, r.axes, &origin, shear);
        let e0 = p1.0 * p2.1 - p1.1 * p2.0;
        let e1 = p2.0 * p0.1 - p2.1 * p0.0;
        let e2 = p0.0 * p1.1 - p0.1 * p1.0;
        let zero = L::splat(0.0);
        let on_edge = L::or(L::or(e0.cmp_eq(zero), e1.cmp_eq(zero)), e2.cmp_eq(zero));
        let fallback = L::and(on_edge, active);
        let det = e0 + e1 + e2;
        let positive = L::and(L::and(e0.cmp_gt(zero), e1.cmp_gt(zero)), e2.cmp_gt(zero));
        let negative = L::and(L::and(e0.cmp_lt(zero), e1.cmp_lt(zero)), e2.cmp_lt(zero));
        let t_scaled = (e0 * p0.2 + e1 * p1.2 + e2 * p2.2) * L::from_array(r.shear[2]);
        let limit = t_max * det;
        let in_range = L::or(
            L::and(L::and(positive, t_scaled.cmp_gt(zero)), t_scaled.cmp_le(limit)),
            L::and(L::and(negative, t_scaled.cmp_lt(zero)), t_scaled.cmp_ge(limit)),
        );
        let inv_det = L::splat(1.0) / det;
        let t = t_scaled * inv_det;
        let valid = L::and(L::and(in_range, t.cmp_gt(zero)), t.cmp_lt(t_max));
        RayLanes {
            valid: L::and(L::and(valid, active), L::not(fallback)),
            fallback: L::bits(fallback),
            t,
            b1: e1 * inv_det,
            b2: e2 * inv_det,
        }
    }
}

impl Triangle4 {
    /// Vertex `v` of triangle `k` relative to each lane's origin, permuted and sheared.
    #[inline(always)]
    fn sheared_corner<L: Lane8>(
        &self,
        v: usize,
        k: usize,
        axes: [usize; 3],
        origin: &[L; 3],
        (sx, sy): (L, L),
    ) -> (L, L, L) {
        let [kx, ky, kz] = axes;
        let dz = L::splat(self.coordinate(3 * v + kz, k)) - origin[2];
        (
            (L::splat(self.coordinate(3 * v + kx, k)) - origin[0]) + sx * dz,
            (L::splat(self.coordinate(3 * v + ky, k)) - origin[1]) + sy * dz,
            dz,
        )
    }

    /// Row `i` of lane `k`, read through an array: a `Vec4` indexed by a lane number is a
    /// jump table, its target a coin toss for the predictor.
    #[inline(always)]
    fn coordinate(&self, i: usize, k: usize) -> f32 {
        AsRef::<[f32; 4]>::as_ref(&self.v[i])[k]
    }
}

/// The mask of the lanes whose bits are set in `bits`.
#[inline(always)]
fn lanes_of<L: Lane8>(bits: u32) -> L::Mask {
    L::mask_of(std::array::from_fn(|j| bits >> j & 1 != 0))
}

/// What the SIMD part of the test found: the active lanes hit (`mask`), the lanes that need
/// the scalar test, and every lane's distance and barycentrics (arrays: a `Vec4` indexed
/// by a lane number is a jump table, its target a coin toss for the predictor).
struct Lanes {
    mask: u32,
    fallback: u32,
    t: [f32; 4],
    b1: [f32; 4],
    b2: [f32; 4],
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_core::{Pcg32, Ray};

    fn random_point(rng: &mut Pcg32) -> Vec3 {
        Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE
    }

    /// A point on a coarse grid, so that axis-parallel rays run exactly through edges and
    /// vertices.
    fn grid_point(rng: &mut Pcg32) -> Vec3 {
        (random_point(rng) * 2.0).round() * 0.5
    }

    /// The packet agrees exactly with four scalar tests, the closest winning and the lowest
    /// lane of equal distances, including rays through shared edges and vertices (where the
    /// scalar fallback decides) and copies of one triangle in several lanes.
    #[test]
    fn packet_equals_scalar_tests_bit_for_bit() {
        let mut rng = Pcg32::new(7, 11);
        let (mut hits, mut fallbacks) = (0, 0);
        for case in 0..50_000 {
            let on_grid = case % 2 == 1;
            let random_point = |rng: &mut Pcg32| if on_grid { grid_point(rng) } else { random_point(rng) };
            let shared = random_point(&mut rng);
            let mut tris = Vec::new();
            let n = 1 + (case % 4);
            for k in 0..n {
                // Some triangles share a vertex or an edge, some are copies of each other.
                let tri = match (case / 4 + k) % 4 {
                    0 => [shared, random_point(&mut rng), random_point(&mut rng)],
                    1 if !tris.is_empty() => tris[0],
                    2 if !tris.is_empty() => {
                        let t: [Vec3; 3] = tris[0];
                        [t[1], t[0], random_point(&mut rng)]
                    }
                    _ => [random_point(&mut rng), random_point(&mut rng), random_point(&mut rng)],
                };
                tris.push(tri);
            }
            let origin = random_point(&mut rng) * 3.0;
            let target = if case % 3 == 0 {
                shared
            } else if case % 3 == 1 {
                (tris[0][0] + tris[0][1]) * 0.5
            } else {
                random_point(&mut rng)
            };
            let ray = if on_grid {
                let axis = [Vec3::X, Vec3::NEG_Y, Vec3::Z][case % 3];
                Ray::new(target - axis * 3.0, axis)
            } else {
                Ray::new(origin, target - origin)
            };
            let r = TriangleRay::new(&ray);
            let t_max = if case % 5 == 0 { 0.7 } else { f32::INFINITY };
            let active = if case % 7 == 0 { 0b1010 } else { (1u32 << n) - 1 };
            let mut expected: Option<LaneHit> = None;
            for (lane, tri) in tris.iter().enumerate() {
                if active & (1 << lane) == 0 {
                    continue;
                }
                if let Some((t, b)) = intersect_triangle_prepared(&r, *tri, t_max) {
                    if expected.is_none_or(|e| t < e.1) {
                        expected = Some((lane, t, b));
                    }
                }
            }
            let packet = Triangle4::pack(&tris);
            fallbacks += packet.test(&r, t_max, active).fallback.count_ones();
            let got = packet.closest(&r, t_max, active);
            assert_eq!(
                got.map(|h| (h.0, h.1.to_bits(), h.2.x.to_bits(), h.2.y.to_bits())),
                expected.map(|h| (h.0, h.1.to_bits(), h.2.x.to_bits(), h.2.y.to_bits())),
                "case {case}: {tris:?} ray {ray:?}"
            );
            assert_eq!(packet.any(&r, t_max, active), expected.is_some(), "case {case}");
            hits += expected.is_some() as usize;
        }
        assert!(hits > 10_000, "only {hits} hits: the cases test too little");
        assert!(fallbacks > 1_000, "only {fallbacks} lanes needed the scalar fallback");
    }

    #[test]
    fn empty_lanes_are_never_hit() {
        let packet = Triangle4::pack(&[]);
        let ray = Ray::new(Vec3::new(0.0, 0.0, 1.0), Vec3::NEG_Z);
        assert!(packet.closest(&TriangleRay::new(&ray), f32::INFINITY, 0b1111).is_none());
        assert!(!packet.any(&TriangleRay::new(&ray), f32::INFINITY, 0b1111));
    }
}
