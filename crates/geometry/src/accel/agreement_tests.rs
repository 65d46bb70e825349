//! Every accelerator must return the same closest hit and any-hit answer as `List`, for
//! random scenes and random rays, including the awkward cases: empty scenes, a single
//! primitive, coincident primitives, instances, axis-parallel rays and rays from inside.

use super::*;
use crate::shapes::{Cuboid, Disk, Plane, Quad, Sphere};
use crate::{Geometry, GeometryBuilder, Instance, MeshAccel, Shape, TriangleMesh};
use glam::Vec3;
use penumbra_core::{Pcg32, Transform};
use proptest::prelude::*;

fn point(rng: &mut Pcg32, scale: f32) -> Vec3 {
    Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5) * scale
}

fn random_mesh(rng: &mut Pcg32, triangles: usize) -> TriangleMesh {
    let positions: Vec<Vec3> = (0..triangles + 2).map(|_| point(rng, 4.0)).collect();
    let indices = (0..triangles as u32).map(|i| [i, i + 1, i + 2]).collect();
    TriangleMesh {
        positions,
        normals: None,
        uvs: None,
        indices,
    }
}

/// A random scene of `n` primitives of every kind; `coincident` repeats one sphere many
/// times. Instanced meshes get their own accelerator of kind `inner`.
fn random_scene(seed: u64, n: usize, coincident: bool, with_plane: bool, inner: AccelKind) -> Arc<Geometry> {
    let mut rng = Pcg32::new(seed, 0);
    let mut b = GeometryBuilder::new();
    let shared = Arc::new(MeshAccel::new(Arc::new(random_mesh(&mut rng, 20)), inner));
    for i in 0..n {
        let c = point(&mut rng, 10.0);
        let xf = Transform::rotate(point(&mut rng, 1.0), rng.next_f32() * 360.0).unwrap_or_default();
        match i % 6 {
            0 => {
                b.add_shape(Shape::Sphere(Sphere::new(c, 0.1 + rng.next_f32(), &xf).unwrap()));
            }
            1 => {
                if let Some(q) = Quad::new(c, point(&mut rng, 3.0), point(&mut rng, 3.0), &xf) {
                    b.add_shape(Shape::Quad(q));
                }
            }
            2 => {
                if let Some(d) = Disk::new(c, point(&mut rng, 1.0), 0.2 + rng.next_f32(), &xf) {
                    b.add_shape(Shape::Disk(d));
                }
            }
            3 => {
                let size = Vec3::splat(0.1) + point(&mut rng, 1.0).abs();
                if let Some(x) = Cuboid::new(c, c + size, &xf) {
                    b.add_shape(Shape::Cuboid(x));
                }
            }
            4 => {
                let triangles = 1 + (rng.next_u32() % 30) as usize;
                b.add_mesh(random_mesh(&mut rng, triangles).transformed(&xf));
            }
            _ => {
                let place = xf.then(Transform::translate(c));
                b.add_instance(Instance::new(shared.clone(), &place));
            }
        }
    }
    if coincident {
        for _ in 0..100 {
            b.add_shape(Shape::Sphere(
                Sphere::new(Vec3::ONE, 0.5, &Transform::IDENTITY).unwrap(),
            ));
        }
    }
    if with_plane {
        b.add_shape(Shape::Plane(
            Plane::new(Vec3::new(0.0, -6.0, 0.0), Vec3::Y, &Transform::IDENTITY).unwrap(),
        ));
    }
    Arc::new(b.build())
}

fn random_ray(rng: &mut Pcg32) -> Ray {
    let origin = point(rng, 30.0);
    let mut dir = point(rng, 2.0);
    match rng.next_u32() % 4 {
        // Axis-parallel rays, through cell and node boundaries.
        0 => {
            let axis = (rng.next_u32() % 3) as usize;
            dir = Vec3::ZERO;
            dir[axis] = if rng.next_u32().is_multiple_of(2) { 1.0 } else { -1.0 };
        }
        // Aimed at the scene from outside, or starting inside it.
        1 => dir = point(rng, 4.0) - origin,
        2 => return Ray::new(point(rng, 8.0), dir),
        _ => {}
    }
    Ray::new(origin, dir)
}

fn check_agreement(seed: u64, n: usize, coincident: bool, with_plane: bool) -> Result<(), TestCaseError> {
    // The reference is brute force all the way down, instances included.
    let reference = random_scene(seed, n, coincident, with_plane, AccelKind::List).accel(AccelKind::List);
    let mut rng = Pcg32::new(seed, 1);
    for kind in AccelKind::ALL {
        let accel = random_scene(seed, n, coincident, with_plane, kind).accel(kind);
        let mut batch = Vec::new();
        for _ in 0..300 {
            let ray = random_ray(&mut rng);
            let t_max = if rng.next_u32().is_multiple_of(4) {
                rng.next_f32() * 20.0
            } else {
                f32::INFINITY
            };
            batch.push((ray, t_max));
            let want = reference.intersect(&ray, t_max);
            let got = accel.intersect(&ray, t_max);
            match (want, got) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    prop_assert!(
                        (a.t - b.t).abs() <= 1e-5 * a.t.abs().max(1e-3),
                        "{:?}: t {} vs {}",
                        kind,
                        a.t,
                        b.t
                    );
                    // Equal distances may come from different primitives (ties, coincident copies).
                    prop_assert!(
                        a.prim == b.prim || a.t == b.t,
                        "{:?}: prim {} vs {}",
                        kind,
                        a.prim,
                        b.prim
                    );
                }
                _ => prop_assert!(false, "{:?}: {:?} vs {:?} for {:?}", kind, want, got, ray),
            }
            prop_assert_eq!(reference.occluded(&ray, t_max), accel.occluded(&ray, t_max));
            prop_assert_eq!(want.is_some(), accel.occluded(&ray, t_max));
        }
        // A batch answers exactly what the rays one by one answer (`Hit` compared whole).
        let (mut hits, mut blocked) = (vec![None; batch.len()], vec![false; batch.len()]);
        accel.intersect_batch(&batch, &mut hits);
        accel.occluded_batch(&batch, &mut blocked);
        for (k, (ray, t_max)) in batch.iter().enumerate() {
            prop_assert_eq!(hits[k], accel.intersect(ray, *t_max), "{:?}: batch, ray {}", kind, k);
            prop_assert_eq!(blocked[k], accel.occluded(ray, *t_max), "{:?}: batch, ray {}", kind, k);
        }
        // In packets (where the structure has them) too, but for ties at an equal distance,
        // which the packet's walk may settle on another primitive.
        accel.intersect_coherent(&batch, &mut hits);
        for (k, (ray, t_max)) in batch.iter().enumerate() {
            let one = accel.intersect(ray, *t_max);
            let same = match (hits[k], one) {
                (Some(a), Some(b)) => a.t == b.t && (a.prim != b.prim || a == b),
                (a, b) => a == b,
            };
            prop_assert!(same, "{:?}: packets, ray {}: {:?} against {:?}", kind, k, hits[k], one);
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn accelerators_agree_with_brute_force(seed in any::<u64>(), n in 0usize..120, coincident in any::<bool>(), plane in any::<bool>()) {
        check_agreement(seed, n, coincident, plane)?;
    }
}

#[test]
fn large_meshes_built_in_parallel_agree() {
    // Enough small triangles (a scan-like mesh, not one of overlapping giants) to cross the
    // BVH's parallel-build threshold and fill the grid's cells unevenly.
    let mut rng = Pcg32::new(99, 0);
    let mut mesh = TriangleMesh::default();
    for i in 0..20_000u32 {
        let c = point(&mut rng, 8.0) * Vec3::new(1.0, 0.3, 1.0);
        mesh.positions
            .extend([c, c + point(&mut rng, 0.2), c + point(&mut rng, 0.2)]);
        mesh.indices.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    let mut b = GeometryBuilder::new();
    b.add_mesh(mesh.clone());
    let g = Arc::new(b.build());
    let reference = g.accel(AccelKind::List);
    // The same triangles as one mesh's own primitive set too: the BVH then stores them in
    // leaf order, in packets of four tested at once.
    let mesh = Arc::new(mesh);
    for kind in AccelKind::ALL {
        let flat = g.accel(kind);
        let packed = build_accel(kind, Arc::new(crate::instance::MeshTriangles::new(mesh.clone())));
        for _ in 0..300 {
            let ray = random_ray(&mut rng);
            let want = reference.intersect(&ray, f32::INFINITY);
            for accel in [&flat, &packed] {
                let got = accel.intersect(&ray, f32::INFINITY);
                assert_eq!(want.map(|h| h.t), got.map(|h| h.t), "{kind:?} {ray:?}");
                assert_eq!(want.map(|h| h.prim), got.map(|h| h.prim), "{kind:?} {ray:?}");
                assert_eq!(want.is_some(), accel.occluded(&ray, f32::INFINITY), "{kind:?} {ray:?}");
            }
        }
    }
}

#[test]
fn huge_coordinates_and_degenerate_triangles_neither_panic_nor_loop() {
    // A tiny mesh beside triangles 1e30 across, collinear and single-point triangles, and one
    // spanning the float range: every accelerator builds and answers like brute force.
    let mut rng = Pcg32::new(5, 0);
    let mut mesh = random_mesh(&mut rng, 50);
    let n = mesh.positions.len() as u32;
    mesh.positions.extend([
        Vec3::new(-1e30, 0.0, -1e30),
        Vec3::new(1e30, 0.0, -1e30),
        Vec3::new(0.0, 1e30, 1e30),
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(2.0, 2.0, 2.0),
        Vec3::new(3.0, 3.0, 3.0),
        Vec3::new(-3e38, -3e38, 0.0),
        Vec3::new(3e38, -3e38, 0.0),
        Vec3::new(0.0, 3e38, 0.0),
    ]);
    mesh.indices
        .extend([[n, n + 1, n + 2], [n + 3, n + 4, n + 5], [n + 3, n + 3, n + 3]]);
    let mut b = GeometryBuilder::new();
    b.add_mesh(mesh);
    b.add_shape(Shape::Plane(
        Plane::new(Vec3::ZERO, Vec3::Y, &Transform::IDENTITY).unwrap(),
    ));
    let g = Arc::new(b.build());
    let reference = g.accel(AccelKind::List);
    // Rays with NaN, infinite or zero parts: no hit, and above all no endless walk.
    let broken = [
        Ray::new(Vec3::NAN, Vec3::Z),
        Ray::new(Vec3::ZERO, Vec3::new(f32::NAN, 1.0, 0.0)),
        Ray::new(Vec3::new(0.5, 0.5, 0.5), Vec3::ZERO),
        Ray::new(Vec3::new(f32::INFINITY, 0.0, 0.0), -Vec3::X),
        Ray::new(Vec3::ZERO, Vec3::new(f32::INFINITY, 1.0, 0.0)),
    ];
    for kind in AccelKind::ALL {
        let accel = g.accel(kind);
        for ray in &broken {
            assert_eq!(
                reference.intersect(ray, f32::INFINITY).map(|h| h.prim),
                accel.intersect(ray, f32::INFINITY).map(|h| h.prim),
                "{kind:?} {ray:?}"
            );
            accel.occluded(ray, f32::INFINITY);
        }
        for _ in 0..200 {
            let ray = random_ray(&mut rng);
            let (want, got) = (
                reference.intersect(&ray, f32::INFINITY),
                accel.intersect(&ray, f32::INFINITY),
            );
            assert_eq!(
                want.map(|h| (h.prim, h.t)),
                got.map(|h| (h.prim, h.t)),
                "{kind:?} {ray:?}"
            );
        }
    }
}

#[test]
fn empty_and_single_primitive_scenes() {
    for n in [0, 1] {
        check_agreement(7, n, false, false).unwrap();
        check_agreement(8, n, false, true).unwrap();
    }
}

#[test]
fn rays_inside_split_planes_and_along_shared_edges_agree() {
    // A floor of unit squares on the integer lattice plus walls standing in the planes
    // x = integer: split planes fall on the shared edges and on the walls. Rays run inside
    // those planes (x exactly an integer, no x motion) and down onto vertices and edges.
    let mut mesh = TriangleMesh::default();
    let mut quad = |p: [Vec3; 4]| {
        let n = mesh.positions.len() as u32;
        mesh.positions.extend(p);
        mesh.indices.extend([[n, n + 1, n + 2], [n, n + 2, n + 3]]);
    };
    for i in 0..8 {
        for j in 0..8 {
            let (x, z) = (i as f32, j as f32);
            quad([
                Vec3::new(x, 0.0, z),
                Vec3::new(x + 1.0, 0.0, z),
                Vec3::new(x + 1.0, 0.0, z + 1.0),
                Vec3::new(x, 0.0, z + 1.0),
            ]);
        }
        if i % 3 == 1 {
            let x = i as f32;
            quad([
                Vec3::new(x, 0.0, 1.0),
                Vec3::new(x, 0.0, 5.0),
                Vec3::new(x, 2.0, 5.0),
                Vec3::new(x, 2.0, 1.0),
            ]);
        }
    }
    let mut b = GeometryBuilder::new();
    b.add_mesh(mesh);
    let g = Arc::new(b.build());
    let reference = g.accel(AccelKind::List);
    let mut rng = Pcg32::new(17, 0);
    let mut rays = Vec::new();
    for _ in 0..400 {
        let x = (rng.next_u32() % 9) as f32;
        let z = (rng.next_u32() % 17) as f32 * 0.5;
        let dz = [0.0, 0.5, -0.25][(rng.next_u32() % 3) as usize];
        rays.push(Ray::new(Vec3::new(x, 3.0, z), Vec3::new(0.0, -1.0, dz)));
        // From below the floor, shared edges fall to the other triangle of each pair.
        rays.push(Ray::new(Vec3::new(x, -3.0, z), Vec3::new(0.0, 1.0, dz)));
        rays.push(Ray::new(Vec3::new(x, -3.0, z), Vec3::new(-0.0, 1.0, -dz)));
        rays.push(Ray::new(Vec3::new(x - 0.5, 1.0, z), Vec3::new(1.0, 0.0, 0.0)));
        rays.push(Ray::new(Vec3::new(x, 1.0, -1.0), Vec3::new(0.0, 0.0, 1.0)));
    }
    let mut hits = 0;
    for kind in AccelKind::ALL {
        let accel = g.accel(kind);
        for ray in &rays {
            let want = reference.intersect(ray, f32::INFINITY);
            let got = accel.intersect(ray, f32::INFINITY);
            hits += want.is_some() as usize;
            assert_eq!(want.map(|h| h.t), got.map(|h| h.t), "{kind:?} {ray:?}");
            assert_eq!(want.is_some(), accel.occluded(ray, f32::INFINITY), "{kind:?} {ray:?}");
        }
    }
    assert!(hits > rays.len(), "too few hits to mean anything: {hits}");
}
