//! Shading arithmetic one path at a time against eight paths per instruction: a
//! cosine-weighted direction about a normal (the concentric disk map, the lift onto the
//! hemisphere, Duff et al.'s frame and the change to world coordinates), the same floats
//! either way (`lanes::tests`). Throughput is in directions per second.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::{Vec2, Vec3};
use penumbra::math::frame::{Basis, Frame};
use penumbra::math::lanes::{F8, V3};
use penumbra::math::{warp, Pcg32};
use std::hint::black_box;

const N: usize = 4096;

fn inputs() -> (Vec<Vec2>, Vec<Vec3>) {
    let mut rng = Pcg32::new(3, 1);
    let u = (0..N).map(|_| Vec2::new(rng.next_f32(), rng.next_f32())).collect();
    let n = (0..N)
        .map(|_| Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5).normalize())
        .collect();
    (u, n)
}

fn lanes(c: &mut Criterion) {
    let (u, n) = inputs();
    let mut group = c.benchmark_group("cosine direction about a normal");
    group.throughput(Throughput::Elements(N as u64));
    group.bench_function("scalar", |b| {
        b.iter(|| {
            let mut sum = Vec3::ZERO;
            for (u, n) in u.iter().zip(&n) {
                sum += Frame::from_normal(*n).to_world(warp::cosine_hemisphere(*u));
            }
            black_box(sum)
        })
    });
    group.bench_function("8 lanes", |b| {
        b.iter(|| {
            let mut sum = V3::new(F8::ZERO, F8::ZERO, F8::ZERO);
            for (u, n) in u.chunks_exact(8).zip(n.chunks_exact(8)) {
                let (ux, uy) = (
                    F8::from(std::array::from_fn(|k| u[k].x)),
                    F8::from(std::array::from_fn(|k| u[k].y)),
                );
                let n: &[Vec3; 8] = n.try_into().expect("chunks of eight");
                sum = sum + Basis::from_normal(V3::from_lanes(n)).to_world(warp::cosine_hemisphere_lanes(ux, uy));
            }
            black_box(sum)
        })
    });
    group.finish();
}

criterion_group!(benches, lanes);
criterion_main!(benches);
