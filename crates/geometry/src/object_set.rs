//! The shapes and instances of a scene (with the few triangles that join them) as the
//! primitive set of their accelerator, tested four slots at a time once the accelerator
//! has put them in leaf order: round spheres and triangles in SIMD lanes, other kinds one
//! by one. A leaf's spheres then cost one test for four, with no dispatch on the kind per
//! primitive, as a mesh leaf's triangles do in [`Triangle4`] packets.
//!
//! Every lane computes the floats the one-primitive test computes, so the closest hit of a
//! run is the one the primitives tested one by one in slot order give: the smallest
//! distance, the lowest slot of equal ones.

use crate::accel::{packets_of, PrimitiveSet, RayPacket, PACKET, PAD};
use crate::geometry::PacketPrim;
use crate::shapes::sphere::nearest_root;
use crate::shapes::triangle::{dominant_axis, TriangleRay};
use crate::shapes::triangle4::{Triangle4, TriangleRays};
use crate::{Geometry, Hit};
use glam::{Vec2, Vec4};
use penumbra_core::lanes::Lane8;
use penumbra_core::{Aabb, Ray};
use std::sync::Arc;

/// Four slots: the round spheres' centres and squared radii (NaN in other lanes, which
/// no ray hits), the triangles, and which lanes hold which kind.
#[derive(Clone, Copy, Debug)]
struct Packet {
    centre: [Vec4; 3],
    r2: Vec4,
    triangles: Triangle4,
    sphere_lanes: u32,
    triangle_lanes: u32,
    /// Lanes tested one by one (other shapes, instances).
    other_lanes: u32,
}

impl Packet {
    const EMPTY: Packet = Packet {
        centre: [Vec4::NAN; 3],
        r2: Vec4::NAN,
        triangles: Triangle4::EMPTY,
        sphere_lanes: 0,
        triangle_lanes: 0,
        other_lanes: 0,
    };

    /// The sphere lanes' distances, and the mask of those hit in `(0, t_max)`: the
    /// world-space sphere test ([`nearest_root`]) in four lanes.
    #[inline(always)]
    fn spheres(&self, ray: &Ray, t_max: f32, active: u32) -> (u32, [f32; 4]) {
        let (o, d) = (ray.origin, ray.dir);
        let f = [
            Vec4::splat(o.x) - self.centre[0],
            Vec4::splat(o.y) - self.centre[1],
            Vec4::splat(o.z) - self.centre[2],
        ];
        let dir = [Vec4::splat(d.x), Vec4::splat(d.y), Vec4::splat(d.z)];
        let t = nearest_root(f, dir, Vec4::splat(d.length_squared()), self.r2);
        let hit = t.cmpgt(Vec4::ZERO) & t.cmplt(Vec4::splat(t_max));
        (hit.bitmask() & active & self.sphere_lanes, t.to_array())
    }
}

/// A lane's hit: lane, distance, the shape's coordinates, the instance's triangle.
type LaneHit = (usize, f32, Vec2, u32);

/// The closer of two lane hits, the lower lane of equal distances.
#[inline(always)]
fn closer(a: Option<LaneHit>, b: Option<LaneHit>) -> Option<LaneHit> {
    match (a, b) {
        (Some(x), Some(y)) => Some(if y.1 < x.1 || (y.1 == x.1 && y.0 < x.0) { y } else { x }),
        (x, None) => x,
        (None, y) => y,
    }
}

/// The geometry's shapes, instances and joining triangles; in packets of four once
/// [reordered](PrimitiveSet::reordered) into an accelerator's leaf order.
pub(crate) struct ObjectSet {
    geometry: Arc<Geometry>,
    /// Slot `i` is lane `i % 4` of packet `i / 4` (empty until reordered).
    packets: Vec<Packet>,
    /// The geometry's primitive in each slot ([`PAD`] for an empty one); empty until
    /// reordered, when slot `i` is primitive `i`.
    numbers: Vec<u32>,
}

impl ObjectSet {
    pub(crate) fn new(geometry: Arc<Geometry>) -> Self {
        ObjectSet {
            geometry,
            packets: Vec::new(),
            numbers: Vec::new(),
        }
    }

    /// The geometry's primitive in slot `i` ([`PAD`] for none).
    #[inline]
    fn number(&self, i: u32) -> u32 {
        if self.numbers.is_empty() {
            i
        } else {
            self.numbers[i as usize]
        }
    }

    /// [`ObjectSet::number`] of an order's entry, [`PAD`] kept.
    fn slot_number(&self, slot: u32) -> u32 {
        if slot == PAD {
            PAD
        } else {
            self.number(slot)
        }
    }

    /// The closest hit among the lanes `active` of `packet` in `(0, t_max)`.
    #[inline(always)]
    fn packet_closest(&self, packet: usize, active: u32, ray: &Ray, data: &TriangleRay, t_max: f32) -> Option<Hit> {
        let p = &self.packets[packet];
        let mut best = None;
        if p.sphere_lanes & active != 0 {
            let (mut mask, t) = p.spheres(ray, t_max, active);
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                best = closer(best, Some((lane, t[lane], Vec2::ZERO, 0)));
            }
        }
        if p.triangle_lanes & active != 0 {
            let hit = p.triangles.closest(data, t_max, p.triangle_lanes & active);
            best = closer(best, hit.map(|(lane, t, uv)| (lane, t, uv, 0)));
        }
        let mut others = p.other_lanes & active;
        while others != 0 {
            let lane = others.trailing_zeros() as usize;
            others &= others - 1;
            let hit = self
                .geometry
                .intersect(self.numbers[packet * 4 + lane], ray, data, t_max);
            best = closer(best, hit.map(|h| (lane, h.t, h.uv, h.sub)));
        }
        best.map(|(lane, t, uv, sub)| Hit {
            t,
            prim: self.numbers[packet * 4 + lane],
            sub,
            uv,
        })
    }
}

impl PrimitiveSet for ObjectSet {
    type RayData = TriangleRay;
    type PacketData = TriangleRays;
    #[inline]
    fn prepare(&self, ray: &Ray) -> TriangleRay {
        TriangleRay::new(ray)
    }
    fn len(&self) -> usize {
        if self.numbers.is_empty() {
            self.geometry.len()
        } else {
            self.numbers.len()
        }
    }
    fn bounds(&self, i: u32) -> Aabb {
        match self.number(i) {
            PAD => Aabb::EMPTY,
            n => self.geometry.bounds(n),
        }
    }
    fn overlaps(&self, i: u32, b: &Aabb) -> bool {
        match self.number(i) {
            PAD => false,
            n => self.geometry.overlaps(n, b),
        }
    }
    fn clip_bounds(&self, i: u32, b: &Aabb) -> Aabb {
        match self.number(i) {
            PAD => Aabb::EMPTY,
            n => self.geometry.clip_bounds(n, b),
        }
    }
    #[inline]
    fn intersect(&self, i: u32, ray: &Ray, data: &TriangleRay, t_max: f32) -> Option<Hit> {
        match self.number(i) {
            PAD => None,
            n => self.geometry.intersect(n, ray, data, t_max),
        }
    }
    #[inline]
    fn occluded(&self, i: u32, ray: &Ray, data: &TriangleRay, t_max: f32) -> bool {
        match self.number(i) {
            PAD => false,
            n => self.geometry.occluded(n, ray, data, t_max),
        }
    }
    #[inline(always)]
    fn intersect_run(&self, first: usize, count: usize, ray: &Ray, data: &TriangleRay, t_max: f32) -> Option<Hit> {
        let mut t_max = t_max;
        let mut closest = None;
        for (packet, lanes) in packets_of(first, count) {
            if let Some(hit) = self.packet_closest(packet, lanes, ray, data, t_max) {
                t_max = hit.t;
                closest = Some(hit);
            }
        }
        closest
    }
    #[inline(always)]
    fn occluded_run(&self, first: usize, count: usize, ray: &Ray, data: &TriangleRay, t_max: f32) -> bool {
        for (packet, active) in packets_of(first, count) {
            let p = &self.packets[packet];
            if p.sphere_lanes & active != 0 && p.spheres(ray, t_max, active).0 != 0 {
                return true;
            }
            if p.triangle_lanes & active != 0 && p.triangles.any(data, t_max, p.triangle_lanes & active) {
                return true;
            }
            let mut others = p.other_lanes & active;
            while others != 0 {
                let lane = others.trailing_zeros() as usize;
                others &= others - 1;
                if self
                    .geometry
                    .occluded(self.numbers[packet * 4 + lane], ray, data, t_max)
                {
                    return true;
                }
            }
        }
        false
    }
    fn group(&self) -> usize {
        4
    }
    fn packet_class(&self, ray: &Ray) -> usize {
        dominant_axis(ray.dir)
    }
    fn prepare_packet(&self, p: &RayPacket<TriangleRay>) -> Option<TriangleRays> {
        TriangleRays::new(&p.data)
    }
    /// Packets of triangles alone take the packet test; a packet with spheres or other
    /// shapes is tested ray by ray (the one-ray packet test).
    #[inline(always)]
    fn intersect_run_packet<L: Lane8>(
        &self,
        first: usize,
        count: usize,
        p: &RayPacket<TriangleRay>,
        rays: &TriangleRays,
        lanes: u32,
        (t_max, hits): (&mut [f32; PACKET], &mut [Option<Hit>; PACKET]),
    ) {
        for (packet, active) in packets_of(first, count) {
            let q = &self.packets[packet];
            if (q.sphere_lanes | q.other_lanes) & active != 0 {
                for j in (0..PACKET).filter(|j| lanes >> j & 1 != 0) {
                    if let Some(hit) = self.packet_closest(packet, active, &p.rays[j], &p.data[j], t_max[j]) {
                        (t_max[j], hits[j]) = (hit.t, Some(hit));
                    }
                }
                continue;
            }
            let tris = q.triangle_lanes & active;
            if tris == 0 {
                continue;
            }
            if let Some(h) = q.triangles.closest_rays::<L>(rays, &p.data, (tris, lanes), t_max) {
                h.write(t_max, hits, |k| self.numbers[packet * 4 + k]);
            }
        }
    }
    fn reordered(&self, order: &[u32]) -> Option<Self> {
        let packets = order
            .chunks(4)
            .map(|slots| {
                let mut p = Packet::EMPTY;
                for (lane, &slot) in slots.iter().enumerate() {
                    let bit = 1 << lane;
                    match self.geometry.packet_prim(self.slot_number(slot)) {
                        PacketPrim::Pad => {}
                        PacketPrim::Sphere(centre, radius) => {
                            for axis in 0..3 {
                                p.centre[axis][lane] = centre[axis];
                            }
                            p.r2[lane] = radius * radius;
                            p.sphere_lanes |= bit;
                        }
                        PacketPrim::Triangle(v) => {
                            p.triangles.set(lane, v);
                            p.triangle_lanes |= bit;
                        }
                        PacketPrim::Other => p.other_lanes |= bit,
                    }
                }
                p
            })
            .collect();
        Some(ObjectSet {
            geometry: self.geometry.clone(),
            packets,
            numbers: order.iter().map(|&slot| self.slot_number(slot)).collect(),
        })
    }
    fn memory_bytes(&self) -> usize {
        self.geometry.memory_bytes()
            + self.packets.capacity() * std::mem::size_of::<Packet>()
            + self.numbers.capacity() * std::mem::size_of::<u32>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::{Quad, Sphere};
    use crate::{AccelKind, GeometryBuilder, Instance, MeshAccel, Shape, TriangleMesh};
    use glam::Vec3;
    use penumbra_core::{Pcg32, Transform};

    fn point(rng: &mut Pcg32, scale: f32) -> Vec3 {
        Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5) * scale
    }

    /// Round spheres (some of them coincident copies), ellipsoids, quads, an instance and
    /// a few joining triangles: every kind of lane.
    fn scene(rng: &mut Pcg32) -> Arc<Geometry> {
        let mut b = GeometryBuilder::new();
        let squash = Transform::scale(Vec3::new(1.0, 0.3, 1.0)).unwrap();
        for i in 0..14 {
            let c = point(rng, 6.0);
            let shape = match i % 7 {
                0..=2 => Shape::Sphere(Sphere::new(c, 0.2 + rng.next_f32(), &Transform::IDENTITY).unwrap()),
                3 => Shape::Sphere(Sphere::new(Vec3::ONE, 0.5, &Transform::IDENTITY).unwrap()),
                4 => Shape::Sphere(Sphere::new(c, 0.5, &squash).unwrap()),
                _ => Shape::Quad(Quad::new(c, point(rng, 3.0), point(rng, 3.0), &Transform::IDENTITY).unwrap()),
            };
            b.add_shape(shape);
        }
        let positions: Vec<Vec3> = (0..8).map(|_| point(rng, 6.0)).collect();
        let mesh = TriangleMesh {
            indices: (0..6).map(|i| [i, i + 1, i + 2]).collect(),
            positions,
            normals: None,
            uvs: None,
        };
        let shared = Arc::new(MeshAccel::new(Arc::new(mesh.clone()), AccelKind::Bvh));
        b.add_instance(Instance::new(shared, &Transform::translate(point(rng, 4.0))));
        b.add_mesh(mesh);
        Arc::new(b.build())
    }

    /// A run of packets answers what its slots tested one at a time in slot order answer
    /// (the closest, the lowest slot of equal distances), bit for bit, for any run of
    /// slots in a reordering with empty slots; and the occlusion test agrees.
    #[test]
    fn packets_answer_as_slots_one_at_a_time() {
        let mut rng = Pcg32::new(3, 5);
        let (mut hits, mut spheres) = (0, 0);
        for _ in 0..60 {
            let geometry = scene(&mut rng);
            let set = ObjectSet::new(geometry.clone());
            assert!(geometry.len() > 20, "the triangles joined the shapes' set");
            // A shuffled order with empty slots.
            let mut order: Vec<u32> = (0..set.len() as u32).collect();
            for k in (1..order.len()).rev() {
                order.swap(k, rng.next_u32() as usize % (k + 1));
            }
            for _ in 0..4 {
                order.insert(rng.next_u32() as usize % order.len(), PAD);
            }
            let packed = set.reordered(&order).unwrap();
            for _ in 0..300 {
                let origin = point(&mut rng, 16.0);
                let ray = Ray::new(origin, point(&mut rng, 6.0) - origin);
                let data = TriangleRay::new(&ray);
                let t_max = if rng.next_u32().is_multiple_of(4) {
                    rng.next_f32() * 12.0
                } else {
                    f32::INFINITY
                };
                let first = rng.next_u32() as usize % order.len();
                let count = 1 + rng.next_u32() as usize % (order.len() - first);
                let mut want: Option<Hit> = None;
                for slot in first..first + count {
                    let limit = want.map_or(t_max, |h| h.t);
                    if let Some(hit) = packed.intersect(slot as u32, &ray, &data, limit) {
                        want = Some(hit);
                    }
                }
                let got = packed.intersect_run(first, count, &ray, &data, t_max);
                let bits =
                    |h: Option<Hit>| h.map(|h| (h.t.to_bits(), h.prim, h.sub, h.uv.x.to_bits(), h.uv.y.to_bits()));
                assert_eq!(
                    bits(got),
                    bits(want),
                    "slots {first}..{} of {order:?}, {ray:?}",
                    first + count
                );
                assert_eq!(packed.occluded_run(first, count, &ray, &data, t_max), want.is_some());
                hits += want.is_some() as usize;
                spheres +=
                    want.is_some_and(|h| matches!(geometry.packet_prim(h.prim), PacketPrim::Sphere(..))) as usize;
            }
        }
        assert!(
            hits > 3_000 && spheres > 800,
            "too few hits to test: {hits}, {spheres} on spheres"
        );
    }
}
