//! The analytic shapes' surface kernels in eight lanes against their one-lane instances
//! (each shape's `surface`): eight different shapes of a kind, placed by random rotations,
//! non-uniform scales and translations, hit by random rays, give lane by lane the scalar
//! bits.

use super::*;
use penumbra_core::lanes::F8;
use penumbra_core::{Pcg32, Transform};

fn point(rng: &mut Pcg32, scale: f32) -> Vec3 {
    (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE) * scale
}

/// A rotation, a non-uniform scale (sometimes a uniform one, which keeps spheres round)
/// and a translation.
fn placement(rng: &mut Pcg32) -> Transform {
    let s = if rng.next_f32() < 0.3 {
        Vec3::splat(0.5 + rng.next_f32())
    } else {
        Vec3::new(0.5 + rng.next_f32(), 0.5 + rng.next_f32(), 0.5 + rng.next_f32())
    };
    let axis = point(rng, 1.0) + Vec3::splat(1e-3);
    Transform::scale(s)
        .and_then(|t| Some(t.then(Transform::rotate(axis, 360.0 * rng.next_f32())?)))
        .map(|t| t.then(Transform::translate(point(rng, 2.0))))
        .expect("a valid placement")
}

/// Eight shapes made by `make` (a kernel, the shape, and a point to aim at: the centre
/// of its bounds, or a point of an unbounded plane), each with a ray that hits it and the
/// hit.
fn hit_shapes<S: Copy>(
    rng: &mut Pcg32,
    make: impl Fn(&mut Pcg32) -> (S, Shape, Option<Vec3>),
) -> ([S; 8], [Shape; 8], [(Ray, ShapeHit); 8]) {
    let mut found = Vec::new();
    while found.len() < 8 {
        let (kind, shape, aim) = make(rng);
        let target = aim.unwrap_or(shape.bounds().centroid()) + point(rng, 0.3);
        let origin = target + point(rng, 6.0);
        let ray = Ray::new(origin, (target - origin).normalize());
        if let Some(hit) = shape.intersect(&ray, f32::INFINITY) {
            found.push((kind, shape, (ray, hit)));
        }
    }
    let kinds = std::array::from_fn(|k| found[k].0);
    let shapes = std::array::from_fn(|k| found[k].1.clone());
    let hits = std::array::from_fn(|k| found[k].2);
    (kinds, shapes, hits)
}

fn bits(v: Vec3) -> [u32; 3] {
    v.to_array().map(f32::to_bits)
}

/// Runs the gathered kernel of `kinds` on the hits and compares each lane with its
/// shape's scalar surface.
fn compare<K: GatherSurface>(kinds: [K; 8], shapes: &[Shape; 8], hits: &[(Ray, ShapeHit); 8]) {
    let lanes = K::gather::<F8>(&kinds);
    let v = |f: fn(&(Ray, ShapeHit)) -> Vec3| V3::from_lanes(&hits.each_ref().map(f));
    let f = |f: fn(&(Ray, ShapeHit)) -> f32| F8::from_array(hits.each_ref().map(f));
    let s = lanes.surface(
        v(|h| h.0.origin),
        v(|h| h.0.dir),
        f(|h| h.1 .0),
        (f(|h| h.1 .1.x), f(|h| h.1 .1.y)),
    );
    let (p, ng, ns, dpdu) = (s.p.to_lanes(), s.ng.to_lanes(), s.ns.to_lanes(), s.dpdu.to_lanes());
    let (u, w) = (s.uv.0.to_array(), s.uv.1.to_array());
    for k in 0..8 {
        let one = shapes[k].surface(&hits[k].0, hits[k].1);
        assert_eq!(bits(p[k]), bits(one.p), "point, lane {k}");
        assert_eq!(bits(ng[k]), bits(one.n), "normal, lane {k}");
        assert_eq!(bits(ns[k]), bits(one.n), "shading normal, lane {k}");
        assert_eq!(bits(dpdu[k]), bits(one.dpdu), "dp/du, lane {k}");
        assert_eq!(
            [u[k].to_bits(), w[k].to_bits()],
            [one.uv.x.to_bits(), one.uv.y.to_bits()],
            "uv, lane {k}"
        );
    }
}

#[test]
fn shape_surface_lanes_equal_the_scalar_surfaces_bit_for_bit() {
    let mut rng = Pcg32::new(31, 3);
    for _ in 0..200 {
        let (k, s, h) = hit_shapes(&mut rng, |rng| {
            let sphere = Sphere::new(point(rng, 1.0), 0.2 + rng.next_f32(), &placement(rng)).expect("a sphere");
            (sphere.lanes(), Shape::Sphere(sphere), None)
        });
        compare(k, &s, &h);
        let (k, s, h) = hit_shapes(&mut rng, |rng| {
            let min = point(rng, 1.0);
            let max = min + Vec3::new(0.1 + rng.next_f32(), 0.1 + rng.next_f32(), 0.1 + rng.next_f32());
            let cuboid = Cuboid::new(min, max, &placement(rng)).expect("a box");
            (cuboid.lanes(), Shape::Cuboid(cuboid), None)
        });
        compare(k, &s, &h);
        let (k, s, h) = hit_shapes(&mut rng, |rng| {
            let t = placement(rng);
            let at = point(rng, 1.0);
            let plane = Plane::new(at, point(rng, 1.0), &t).expect("a plane");
            (plane.lanes(), Shape::Plane(plane), Some(t.point(at)))
        });
        compare(k, &s, &h);
        // Quads and disks, mixed in one group.
        let (k, s, h) = hit_shapes(&mut rng, |rng| {
            let t = placement(rng);
            if rng.next_f32() < 0.5 {
                let quad = Quad::new(point(rng, 1.0), point(rng, 1.0), point(rng, 1.0), &t).expect("a quad");
                (quad.lanes(), Shape::Quad(quad), None)
            } else {
                let disk = Disk::new(point(rng, 1.0), point(rng, 1.0), 0.2 + rng.next_f32(), &t).expect("a disk");
                (disk.lanes(), Shape::Disk(disk), None)
            }
        });
        compare(k, &s, &h);
    }
}
