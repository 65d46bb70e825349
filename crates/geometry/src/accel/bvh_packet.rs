//! Packet traversal of the wide BVH ([`super::bvh`]) for coherent rays (a tile's camera
//! rays, [`super::Accel::intersect_coherent`]): the rays of a packet ([`super::packet`])
//! walk the tree together, each node's children tested against all of them at once (one
//! child after another, the rays in SIMD lanes), and the leaves' primitives likewise where
//! the set has packet tests (Wald, Slusallek, Benthin and Wagner 2001). A subtree that only
//! one ray still enters is finished by that ray alone with the one-ray traversal, as
//! Embree's hybrid traversal does (Benthin, Wald, Woop, Ernst and Mark, "Combining Single
//! and Packet-Ray Tracing for Arbitrary Ray Distributions on the Intel MIC Architecture",
//! HPG 2012). Scattered rays stay with the one-ray walk: in packets they ran slower
//! (docs/performance.md, "Packets once more").
//!
//! Every ray gets the hit the one-ray traversal gives it (the same slab and primitive
//! floats), except where two primitives are hit at exactly the same distance: the walks
//! visit leaves in different orders, and either may be reported, as between accelerators.

use super::bvh::{Bvh, WideNode, ROOT, ROUNDING, STACK, WIDTH};
use super::packet::{packet_of, RayPacket, Sorted, CHUNK, PACKET};
use super::PrimitiveSet;
use crate::Hit;
use penumbra_core::lanes::Lane8;
use penumbra_core::Ray;
use std::mem::MaybeUninit;

/// A subtree entered by at most this many of a packet's rays is finished ray by ray.
const SINGLE: u32 = 1;

/// Room for the pending entries: a node pushes at most `WIDTH` after popping one.
const PACKET_STACK: usize = STACK + WIDTH;

impl<P: PrimitiveSet> Bvh<P> {
    /// Whether a batch of `n` rays goes in packets: the tree must have nodes (not a single
    /// leaf) and leaves that are runs of the set's slots.
    #[inline(always)]
    fn packets_pay(&self, n: usize) -> bool {
        n > SINGLE as usize && self.root_leaf.is_none() && !self.nodes.is_empty() && self.order.is_empty()
    }

    /// The closest hits of a batch, in packets, with lane type `L` (`AVX`: the one-ray
    /// traversal's slab kernel, as in [`Bvh::closest_from`]).
    #[inline(always)]
    pub(super) fn closest_packets<L: Lane8, const AVX: bool>(&self, rays: &[(Ray, f32)], hits: &mut [Option<Hit>]) {
        if !self.packets_pay(rays.len()) {
            for ((ray, t_max), hit) in rays.iter().zip(hits) {
                *hit = self.closest_from::<(), AVX>(ROOT, ray, &self.prims.prepare(ray), *t_max, &mut ());
            }
            return;
        }
        // Loops, not closures: a closure is compiled apart from the caller's SIMD level.
        for (k, chunk) in rays.chunks(CHUNK).enumerate() {
            let sorted = Sorted::new(&*self.prims, chunk);
            for group in sorted.groups() {
                let (p, mut t_max) = packet_of(&*self.prims, rays, k * CHUNK, group);
                let mut found = [None; PACKET];
                self.closest_packet::<L, AVX>(&p, &mut t_max, &mut found);
                for (j, &i) in p.index[..group.len()].iter().enumerate() {
                    hits[i] = found[j];
                }
            }
        }
    }

    /// The closest hits of the rays of `p`: the children of each node visited nearest
    /// first (by the least entry distance among the rays that enter them), entries culled
    /// ray by ray once beyond a ray's closest hit.
    #[inline(always)]
    fn closest_packet<L: Lane8, const AVX: bool>(
        &self,
        p: &RayPacket<P::RayData>,
        t_max: &mut [f32; PACKET],
        hits: &mut [Option<Hit>; PACKET],
    ) {
        let data = self.prims.prepare_packet(p);
        let slabs = Slabs::<L>::new(&p.rays);
        // Pending entries: the subtree, the rays that enter it and their entry distances.
        let mut entries = [MaybeUninit::<Pending>::uninit(); PACKET_STACK];
        entries[0].write(Pending {
            entry: ROOT,
            mask: p.mask,
            key: 0.0,
            near: [0.0; PACKET],
        });
        let mut top = 1;
        while top > 0 {
            top -= 1;
            // SAFETY: slots below the old `top` were written.
            let Pending { entry, mask, near, .. } = unsafe { entries[top].assume_init() };
            let live = mask & L::bits(L::from_array(near).cmp_le(L::from_array(*t_max)));
            if live == 0 {
                continue;
            }
            if live.count_ones() <= SINGLE {
                let mut lanes = live;
                while lanes != 0 {
                    let j = lanes.trailing_zeros() as usize;
                    lanes &= lanes - 1;
                    if let Some(hit) = self.closest_from::<(), AVX>(entry, &p.rays[j], &p.data[j], t_max[j], &mut ()) {
                        (t_max[j], hits[j]) = (hit.t, Some(hit));
                    }
                }
                continue;
            }
            let (index, count) = (entry as u32 as usize, (entry >> 32) as usize);
            if count > 0 {
                match &data {
                    Some(d) => self
                        .prims
                        .intersect_run_packet::<L>(index, count, p, d, live, (t_max, hits)),
                    None => {
                        let mut lanes = live;
                        while lanes != 0 {
                            let j = lanes.trailing_zeros() as usize;
                            lanes &= lanes - 1;
                            if let Some(hit) = self.prims.intersect_run(index, count, &p.rays[j], &p.data[j], t_max[j])
                            {
                                (t_max[j], hits[j]) = (hit.t, Some(hit));
                            }
                        }
                    }
                }
                continue;
            }
            let node = &self.nodes[index];
            let tm = L::from_array(*t_max);
            // The children some live ray enters, pushed farthest first (by the least entry
            // distance of their rays), so that the nearest is popped next.
            let start = top;
            for c in 0..WIDTH {
                if node.child[c] == 0 && node.count[c] == 0 {
                    break;
                }
                let (enter, near) = slabs.child(node, c, tm);
                let m = L::bits(enter) & live;
                if m == 0 {
                    continue;
                }
                let near = near.to_array();
                let mut key = f32::INFINITY;
                let mut lanes = m;
                while lanes != 0 {
                    key = key.min(near[lanes.trailing_zeros() as usize]);
                    lanes &= lanes - 1;
                }
                let child = node.child[c] as u64 | (node.count[c] as u64) << 32;
                let mut k = top;
                // SAFETY: slots below `top` were written.
                while k > start && unsafe { entries[k - 1].assume_init_ref() }.key < key {
                    entries[k] = entries[k - 1];
                    k -= 1;
                }
                entries[k].write(Pending {
                    entry: child,
                    mask: m,
                    key,
                    near,
                });
                top += 1;
            }
        }
    }
}

/// A subtree waiting in the closest-hit walk: its entry (a node, or a leaf with its count
/// in the high half), the rays that enter it, the least of their entry distances (the
/// order key) and each ray's.
#[derive(Clone, Copy)]
struct Pending {
    entry: u64,
    mask: u32,
    key: f32,
    near: [f32; PACKET],
}

/// What the slab test needs of a packet's rays, one lane each: origins, inverse
/// directions, and which axes' directions are negative.
struct Slabs<L: Lane8> {
    origin: [L; 3],
    inv: [L; 3],
    negative: [L::Mask; 3],
}

impl<L: Lane8> Slabs<L> {
    #[inline(always)]
    fn new(rays: &[Ray; PACKET]) -> Self {
        let (mut o, mut d) = ([[0.0f32; PACKET]; 3], [[0.0f32; PACKET]; 3]);
        for (j, ray) in rays.iter().enumerate() {
            for axis in 0..3 {
                o[axis][j] = ray.origin[axis];
                d[axis][j] = ray.dir[axis];
            }
        }
        let one = L::splat(1.0);
        // `Vec3::recip`'s 1 / d, as the one-ray traversal takes it.
        let inv = [
            one / L::from_array(d[0]),
            one / L::from_array(d[1]),
            one / L::from_array(d[2]),
        ];
        let zero = L::splat(0.0);
        Slabs {
            origin: [L::from_array(o[0]), L::from_array(o[1]), L::from_array(o[2])],
            negative: [inv[0].cmp_lt(zero), inv[1].cmp_lt(zero), inv[2].cmp_lt(zero)],
            inv,
        }
    }

    /// Child `c` of `node` against every lane: where the ray enters it before `t_max`,
    /// and the entry distance. The one-ray slab test's floats, lane by lane: the near
    /// plane by the direction's sign, a NaN slab (a ray in a face's plane) passed over,
    /// exit distances widened by `ROUNDING`.
    #[inline(always)]
    fn child(&self, node: &WideNode, c: usize, t_max: L) -> (L::Mask, L) {
        let mut near = L::splat(0.0);
        let mut far = t_max;
        for axis in (0..3).rev() {
            let lo = (L::splat(node.bounds[2 * axis][c]) - self.origin[axis]) * self.inv[axis];
            let hi = (L::splat(node.bounds[2 * axis + 1][c]) - self.origin[axis]) * self.inv[axis];
            near = L::select(self.negative[axis], hi, lo).max_or_other(near);
            far = L::select(self.negative[axis], lo, hi).min_or_other(far);
        }
        let far = far * L::splat(ROUNDING);
        (near.cmp_le(far), near)
    }
}

#[cfg(test)]
mod tests {
    use crate::{AccelKind, GeometryBuilder, Shape, TriangleMesh};
    use glam::Vec3;
    use penumbra_core::simd::{self, Level};
    use penumbra_core::{Pcg32, Ray, Transform};
    use std::sync::Arc;

    /// A 16 x 16 grid of unit squares (two triangles each) in the plane z = 0, and a few
    /// triangles standing on it.
    fn grid() -> TriangleMesh {
        let mut mesh = TriangleMesh::default();
        for y in 0..=16 {
            for x in 0..=16 {
                mesh.positions.push(Vec3::new(x as f32, y as f32, 0.0));
            }
        }
        for y in 0..16u32 {
            for x in 0..16u32 {
                let v = y * 17 + x;
                mesh.indices.push([v, v + 1, v + 18]);
                mesh.indices.push([v, v + 18, v + 17]);
            }
        }
        for k in 0..6u32 {
            let c = Vec3::new(2.0 + 2.0 * k as f32, 3.0 + k as f32, 0.0);
            let n = mesh.positions.len() as u32;
            mesh.positions
                .extend([c, c + Vec3::new(1.0, 0.0, 2.0), c + Vec3::new(0.0, 1.0, 3.0)]);
            mesh.indices.push([n, n + 1, n + 2]);
        }
        mesh
    }

    /// Camera-like bundles (a grid of rays from one origin, aimed at the grid's vertices and
    /// edges so that the watertight test's scalar fallback decides some lanes, and between
    /// them), then scattered rays; some with a finite `t_max`.
    fn rays(rng: &mut Pcg32) -> Vec<(Ray, f32)> {
        let mut rays = Vec::new();
        for origin in [
            Vec3::new(8.0, 8.0, 12.0),
            Vec3::new(-3.0, 5.0, 4.0),
            Vec3::new(8.5, 8.25, 0.5),
        ] {
            for y in 0..16 {
                for x in 0..16 {
                    let half = if (x + y) % 3 == 0 { 0.5 } else { 0.0 };
                    let target = Vec3::new(x as f32 + half, y as f32, 0.0);
                    let t_max = if (x * y) % 7 == 3 { 5.0 } else { f32::INFINITY };
                    rays.push((Ray::new(origin, target - origin), t_max));
                }
            }
        }
        for _ in 0..512 {
            let p = |rng: &mut Pcg32| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let origin = p(rng) * 20.0 - Vec3::new(2.0, 2.0, 5.0);
            let target = p(rng) * Vec3::new(16.0, 16.0, 3.0);
            rays.push((Ray::new(origin, target - origin), f32::INFINITY));
        }
        rays
    }

    /// Packets give every ray the hit of the one-ray walk bit for bit (distance, primitive,
    /// barycentrics), but where two primitives are hit at exactly the same distance, at
    /// every SIMD level the CPU runs: on a triangle mesh's own structure and on the shapes'
    /// set (triangles and spheres, whose packets mixing kinds are tested ray by ray).
    #[test]
    fn packets_answer_as_single_rays() {
        let mut meshes = GeometryBuilder::new();
        meshes.add_mesh(grid());
        let mut mixed = GeometryBuilder::new();
        let mut small = grid();
        small.indices.truncate(40);
        mixed.add_mesh(small);
        for k in 0..8 {
            let c = Vec3::new(1.0 + 2.0 * k as f32, 1.5 * k as f32, 0.8);
            let sphere = crate::shapes::Sphere::new(c, 0.7, &Transform::IDENTITY).unwrap();
            mixed.add_shape(Shape::Sphere(sphere));
        }
        let scenes = [Arc::new(meshes.build()), Arc::new(mixed.build())];
        let mut rng = Pcg32::new(3, 5);
        let rays = rays(&mut rng);
        let (mut hits, mut ties, mut compared) = (0, 0, 0);
        for level in Level::ALL.into_iter().filter(|l| l.supported()) {
            simd::set_level(level).unwrap();
            for g in &scenes {
                let accel = g.accel(AccelKind::Bvh);
                let mut got = vec![None; rays.len()];
                accel.intersect_coherent(&rays, &mut got);
                for ((ray, t_max), got) in rays.iter().zip(&got) {
                    let one = accel.intersect(ray, *t_max);
                    compared += 1;
                    match (got, one) {
                        (Some(a), Some(b)) if a.prim != b.prim => {
                            assert_eq!(a.t, b.t, "{level}: {ray:?}: {a:?} against {b:?}");
                            ties += 1;
                        }
                        (a, b) => assert_eq!(*a, b, "{level}: {ray:?}"),
                    }
                    hits += one.is_some() as usize;
                }
            }
        }
        simd::set_level(Level::preferred()).unwrap();
        assert!(
            hits > compared / 2,
            "only {hits} of {compared} rays hit: the cases test too little"
        );
        assert!(ties < compared / 50, "{ties} ties of {compared}");
    }
}
