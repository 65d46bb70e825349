//! Ray-query micro-benchmarks: ray-sphere, ray-triangle, and BVH closest-hit and any-hit
//! traversal on the Stanford bunny (69,451 triangles; read from ../shared when present,
//! else a generated sphere mesh of similar size). Throughput is in rays per second.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::Vec3;
use penumbra::geometry::accel::Bvh;
use penumbra::geometry::instance::MeshTriangles;
use penumbra::geometry::shapes::triangle::intersect_triangle;
use penumbra::geometry::shapes::Sphere;
use penumbra::geometry::{Accel, TriangleMesh};
use penumbra::math::{Aabb, Pcg32, Ray, Transform};
use std::hint::black_box;
use std::path::Path;
use std::sync::Arc;

const RAYS: usize = 4096;

fn random_unit(rng: &mut Pcg32) -> Vec3 {
    loop {
        let v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE;
        if let Some(n) = v.try_normalize().filter(|_| v.length_squared() <= 1.0) {
            return n;
        }
    }
}

/// Rays from a ring of origins around `bounds`, aimed at random points inside it.
fn incoherent_rays(bounds: Aabb, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, 0);
    let (c, r) = (bounds.centroid(), bounds.extent().length());
    (0..RAYS)
        .map(|_| {
            let origin = c + random_unit(&mut rng) * r;
            let target = bounds.min + bounds.extent() * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            Ray::new(origin, (target - origin).normalize())
        })
        .collect()
}

/// A 64 x 64 pinhole-camera grid of rays looking at `bounds` from the front.
fn coherent_rays(bounds: Aabb) -> Vec<Ray> {
    let (c, r) = (bounds.centroid(), bounds.extent().length());
    let eye = c + Vec3::new(0.0, 0.0, 1.5 * r);
    (0..64 * 64)
        .map(|i| {
            let (x, y) = ((i % 64) as f32 / 63.0 - 0.5, (i / 64) as f32 / 63.0 - 0.5);
            Ray::new(eye, (c + Vec3::new(x, -y, 0.0) * r * 0.8 - eye).normalize())
        })
        .collect()
}

fn bunny() -> (TriangleMesh, &'static str) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes/mesh-stanford-bunny/bun_zipper.ply");
    match penumbra::scene::formats::ply::load(&path) {
        Ok(mesh) => (mesh, "bunny"),
        Err(_) => {
            eprintln!("note: ../shared is absent; benchmarking a generated 70k-triangle sphere instead of the bunny");
            (uv_sphere(128, 272), "uv-sphere")
        }
    }
}

fn uv_sphere(rings: u32, segments: u32) -> TriangleMesh {
    let mut m = TriangleMesh::default();
    for i in 0..=rings {
        let theta = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..segments {
            let phi = 2.0 * std::f32::consts::PI * j as f32 / segments as f32;
            m.positions
                .push(Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()));
        }
    }
    for i in 0..rings {
        for j in 0..segments {
            let (a, b) = (i * segments + j, i * segments + (j + 1) % segments);
            let (c, d) = (a + segments, b + segments);
            m.indices.push([a, c, b]);
            m.indices.push([b, c, d]);
        }
    }
    m
}

fn primitives(c: &mut Criterion) {
    let unit = Aabb::new(Vec3::splat(-1.0), Vec3::ONE);
    let rays = incoherent_rays(unit, 1);
    let mut g = c.benchmark_group("primitive");
    g.throughput(Throughput::Elements(RAYS as u64));
    let sphere = Sphere::new(Vec3::ZERO, 0.8, &Transform::IDENTITY).unwrap();
    g.bench_function("ray-sphere", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| sphere.intersect(black_box(r), f32::INFINITY).is_some())
                .count()
        })
    });
    let tri = [
        Vec3::new(-0.8, -0.8, 0.0),
        Vec3::new(0.8, -0.8, 0.1),
        Vec3::new(0.0, 0.8, -0.1),
    ];
    g.bench_function("ray-triangle", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| intersect_triangle(black_box(r), tri, f32::INFINITY).is_some())
                .count()
        })
    });
    g.finish();
}

fn bvh(c: &mut Criterion) {
    let (mesh, name) = bunny();
    let mesh = Arc::new(mesh);
    let mut g = c.benchmark_group("bvh");
    g.sample_size(10);
    g.bench_function(BenchmarkId::new("build", name), |b| {
        b.iter(|| Bvh::new(Arc::new(MeshTriangles::new(mesh.clone()))))
    });
    let bvh = Bvh::new(Arc::new(MeshTriangles::new(mesh.clone())));
    let bounds = bvh.bounds();
    g.throughput(Throughput::Elements(RAYS as u64));
    g.sample_size(30);
    for (kind, rays) in [
        ("coherent", coherent_rays(bounds)),
        ("incoherent", incoherent_rays(bounds, 2)),
    ] {
        g.bench_function(BenchmarkId::new(format!("intersect-{kind}"), name), |b| {
            b.iter(|| {
                rays.iter()
                    .filter(|r| bvh.intersect(black_box(r), f32::INFINITY).is_some())
                    .count()
            })
        });
        g.bench_function(BenchmarkId::new(format!("occluded-{kind}"), name), |b| {
            b.iter(|| {
                rays.iter()
                    .filter(|r| bvh.occluded(black_box(r), f32::INFINITY))
                    .count()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, primitives, bvh);
criterion_main!(benches);
