//! The shading kernels one family at a time: every registered BSDF kind (sample, then eval
//! and pdf at the sampled direction), every light kind (`sample_li` from a shading point)
//! and every texture kind (`eval`), each over 4,096 inputs, in elements per second. Where a
//! family has an eight-lane kernel it is measured beside its scalar form on the same inputs
//! (the BSDF kinds the wavefront shades in lanes: diffuse, conductor, dielectric, plastic,
//! Phong and a blend at the CPU's SIMD level, the layered BSDF in the portable lanes; an
//! untextured triangle light sampled by area; every texture kind; point, spot, directional
//! and environment lights: the lanes at the CPU's SIMD level); the other kinds have no
//! lane form yet (issue 24), and this is where theirs will be measured.
//!
//! `cargo bench --bench kernels` (add `-- bsdf` or `-- light` or `-- texture` for one).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::{Mat3, Vec2, Vec3};
use penumbra::math::lanes::{Lane8, F8, V3};
#[cfg(target_arch = "x86_64")]
use penumbra::math::lanes_avx::F8Avx;
use penumbra::math::{warp, Draw, Pcg32, Rgb};
use penumbra::renderer::bsdfs::{BsdfKind, Gather, LaneKernel, MetalFresnel, MixtureLanes, TransportMode};
use penumbra::renderer::lights::emitter::{Emitter, EmitterShape};
use penumbra::renderer::lights::lanes::sample_li_lanes;
use penumbra::renderer::lights::{AreaLight, AreaSampling, Directional, Environment, LightSample, Point, Spot};
use penumbra::renderer::materials::{
    metal_ior, Coated, ConductorMaterial, DielectricMaterial, DiffuseMaterial, Phong, Roughness,
};
use penumbra::renderer::texture::TextureImage;
use penumbra::renderer::{Light, Material, Texture};
use std::hint::black_box;
use std::sync::Arc;

const N: usize = 4096;

fn grey(v: f32) -> Texture {
    Texture::Constant(Rgb::splat(v))
}

/// Random views from the upper hemisphere and sample points.
fn inputs() -> Vec<(Vec3, f32, Vec2)> {
    let mut rng = Pcg32::new(7, 2);
    (0..N)
        .map(|_| {
            let wo = warp::uniform_hemisphere(Vec2::new(rng.next_f32(), rng.next_f32()));
            (wo, rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()))
        })
        .collect()
}

fn materials() -> Vec<(&'static str, Material)> {
    let (eta, k) = metal_ior("Au").expect("gold");
    let rough = |a: f32| Some(Roughness::isotropic(a));
    vec![
        ("diffuse", Material::Diffuse(DiffuseMaterial { reflectance: grey(0.6) })),
        (
            "phong",
            Material::Phong(Phong {
                diffuse: grey(0.4),
                specular: Rgb::splat(0.3),
                exponent: 30.0,
                ..Default::default()
            }),
        ),
        (
            "rough conductor",
            Material::Conductor(ConductorMaterial {
                fresnel: MetalFresnel::Complex { eta, k },
                specular: grey(1.0),
                roughness: rough(0.2),
            }),
        ),
        (
            "rough dielectric",
            Material::Dielectric(DielectricMaterial {
                eta: 1.5,
                reflectance: grey(1.0),
                transmittance: grey(1.0),
                roughness: rough(0.2),
            }),
        ),
        (
            "rough plastic",
            Material::plastic(grey(0.5), grey(1.0), 1.5, rough(0.1)),
        ),
        (
            "blend",
            Material::Blend {
                a: Box::new(Material::Diffuse(DiffuseMaterial { reflectance: grey(0.8) })),
                b: Box::new(Material::Conductor(ConductorMaterial {
                    fresnel: MetalFresnel::Complex { eta, k },
                    specular: grey(1.0),
                    roughness: rough(0.3),
                })),
                weight: grey(0.5),
            },
        ),
        (
            "coated diffuse",
            Material::Coated(Coated {
                roughness: rough(0.1),
                ..Coated::default()
            }),
        ),
    ]
}

fn bsdfs(c: &mut Criterion) {
    let inputs = inputs();
    let mode = TransportMode::Radiance;
    let mut group = c.benchmark_group("bsdf sample + eval + pdf");
    group.throughput(Throughput::Elements(N as u64));
    for (name, material) in materials() {
        let bsdf = material.bsdf(Vec2::ZERO);
        group.bench_function(BenchmarkId::new("scalar", name), |b| {
            b.iter(|| {
                let mut sum = 0.0f32;
                for &(wo, u, u2) in &inputs {
                    if let Some(s) = bsdf.sample(wo, u, u2, mode) {
                        sum += s.weight.r + bsdf.eval(wo, s.wi, mode).g + bsdf.pdf(wo, s.wi, mode);
                    }
                }
                black_box(sum)
            })
        });
    }
    // The same inputs eight to a pass, through the kinds' lane kernels.
    let groups: Vec<Group> = inputs.chunks(8).map(|c| std::array::from_fn(|j| c[j])).collect();
    for (name, material) in materials() {
        let bsdf = material.bsdf(Vec2::ZERO);
        let run: Box<dyn Fn(&Group) -> f32> = match bsdf.kind {
            BsdfKind::Diffuse(d) => Box::new(move |g| lanes_at_level(&[d.lanes(mode); 8], g)),
            BsdfKind::Conductor(c) => Box::new(move |g| lanes_at_level(&[c.lanes(mode); 8], g)),
            BsdfKind::Dielectric(d) => Box::new(move |g| lanes_at_level(&[d.lanes(mode); 8], g)),
            BsdfKind::Plastic(p) => Box::new(move |g| lanes_at_level(&[p.lanes(mode); 8], g)),
            BsdfKind::Phong(p) => Box::new(move |g| lanes_at_level(&[p.lanes(mode); 8], g)),
            // In the portable lanes, as the wavefront runs it at every level.
            BsdfKind::Layered(l) => Box::new(move |g| lane_pass::<_, F8>(&[l.lanes(mode); 8], g)),
            // The blend of a Lambertian and a rough conductor as the mixture of their kernels.
            BsdfKind::Blend(blend) => match (blend.a.bsdf(blend.uv).kind, blend.b.bsdf(blend.uv).kind) {
                (BsdfKind::Diffuse(d), BsdfKind::Conductor(c)) => {
                    let mix = MixtureLanes {
                        a: d.lanes(mode),
                        b: c.lanes(mode),
                        weight: blend.weight,
                    };
                    Box::new(move |g| lanes_at_level(&[mix; 8], g))
                }
                _ => continue,
            },
        };
        group.bench_function(BenchmarkId::new("8 lanes", name), |b| {
            b.iter(|| black_box(groups.iter().map(&run).sum::<f32>()))
        });
    }
    group.finish();
}

/// Eight BSDF inputs (view, lobe number, 2D number).
type Group = [(Vec3, f32, Vec2); 8];

/// Eight inputs through a lane kernel: the sample, then eval and pdf at the sampled
/// directions, summed as the scalar loop sums them (lanes without a sample add nothing).
#[inline(always)]
fn lane_pass<G: Gather, L: Lane8>(one: &[G; 8], g: &Group) -> f32 {
    let k = G::gather::<L>(one);
    let wo = V3::new(
        L::from_array(g.map(|x| x.0.x)),
        L::from_array(g.map(|x| x.0.y)),
        L::from_array(g.map(|x| x.0.z)),
    );
    let u = (L::from_array(g.map(|x| x.2.x)), L::from_array(g.map(|x| x.2.y)));
    let s = k.sample(wo, L::from_array(g.map(|x| x.1)), u);
    let (f, pdf) = (k.eval(wo, s.wi), k.pdf(wo, s.wi));
    let v = s.weight.x + f.y + pdf;
    let ok = L::bits(s.ok);
    v.to_array()
        .iter()
        .enumerate()
        .filter(|(j, _)| ok >> j & 1 != 0)
        .map(|(_, v)| v)
        .sum()
}

/// [`lane_pass`] at the SIMD level the renderer runs.
fn lanes_at_level<G: Gather>(one: &[G; 8], g: &Group) -> f32 {
    #[cfg(target_arch = "x86_64")]
    penumbra::math::level_fns! {
        unsafe fn [avx2, avx512]<G: Gather>(one: &[G; 8], g: &Group) -> f32 {
            lane_pass::<G, F8Avx>(one, g)
        }
    }
    penumbra::math::at_level!(avx512: avx512(one, g), avx2: avx2(one, g), portable: lane_pass::<G, F8>(one, g))
}

fn lights() -> Vec<(&'static str, Light)> {
    let emitter = |shape| Emitter::new(shape).expect("has area");
    let area = |shape| {
        Light::Area(AreaLight {
            emitter: emitter(shape),
            radiance: Rgb::splat(3.0),
            two_sided: false,
            texture: None,
        })
    };
    let sky = TextureImage {
        width: 64,
        height: 32,
        pixels: (0..64 * 32)
            .map(|i| Rgb::splat(0.2 + ((i * 7919) % 101) as f32 / 50.0))
            .collect(),
        wrap: Default::default(),
    };
    vec![
        (
            "point",
            Light::Point(Point {
                position: Vec3::new(0.0, 0.0, 2.0),
                intensity: Rgb::splat(5.0),
            }),
        ),
        (
            "spot",
            Light::Spot(Spot::new(Vec3::Z * 2.0, -Vec3::Z, Rgb::splat(5.0), 30.0, 20.0)),
        ),
        (
            "directional",
            Light::Directional(Directional {
                direction: -Vec3::Z,
                irradiance: Rgb::WHITE,
            }),
        ),
        (
            "quad (spherical rectangle)",
            area(EmitterShape::Quad {
                corner: Vec3::new(-0.5, -0.5, 1.0),
                e1: Vec3::X,
                e2: Vec3::Y,
            }),
        ),
        (
            "triangle (spherical triangle)",
            area(EmitterShape::Triangle {
                v: [
                    Vec3::new(-0.5, -0.5, 1.0),
                    Vec3::new(0.5, -0.5, 1.0),
                    Vec3::new(0.0, 0.6, 1.2),
                ],
            }),
        ),
        (
            "sphere (cone)",
            area(EmitterShape::Sphere {
                center: Vec3::new(0.0, 0.0, 2.0),
                radius: 0.5,
            }),
        ),
        (
            "environment map",
            Light::Environment(Environment::image(sky, Rgb::WHITE, Mat3::IDENTITY, Draw::Alias).expect("a valid map")),
        ),
    ]
}

/// Eight light samples in lanes: points and numbers to samples.
type LanesFn<'a> = dyn Fn(&[Vec3; 8], &[Vec2; 8]) -> [Option<LightSample>; 8] + 'a;

fn light_kernels(c: &mut Criterion) {
    let inputs = inputs();
    let points: Vec<Vec3> = inputs.iter().map(|&(wo, _, _)| wo * 0.3).collect();
    let mut group = c.benchmark_group("light sample_li");
    group.throughput(Throughput::Elements(N as u64));
    for (name, light) in lights() {
        group.bench_function(BenchmarkId::new("scalar", name), |b| {
            b.iter(|| {
                let mut sum = 0.0f32;
                for (p, &(_, _, u)) in points.iter().zip(&inputs) {
                    if let Some(s) = light.sample_li(*p, u, AreaSampling::SolidAngle) {
                        sum += s.li.r / s.pdf;
                    }
                }
                black_box(sum)
            })
        });
        let lanes = |one: &LanesFn| {
            let mut sum = 0.0f32;
            for (p, i) in points.chunks_exact(8).zip(inputs.chunks_exact(8)) {
                let (p, u) = (p.try_into().expect("eight"), std::array::from_fn(|k| i[k].2));
                for s in one(p, &u).into_iter().flatten() {
                    sum += s.li.r / s.pdf;
                }
            }
            sum
        };
        let run: Option<Box<LanesFn>> = match &light {
            Light::Point(l) => Some(Box::new(|p, u| sample_li_lanes(&[l.lanes(); 8], p, u, true))),
            Light::Spot(l) => Some(Box::new(|p, u| sample_li_lanes(&[l.lanes(); 8], p, u, true))),
            Light::Directional(l) => Some(Box::new(|p, u| sample_li_lanes(&[l.lanes(); 8], p, u, true))),
            Light::Environment(l) => Some(Box::new(|p, u| sample_li_lanes(&[l.lanes(); 8], p, u, false))),
            _ => None,
        };
        if let Some(run) = run {
            group.bench_function(BenchmarkId::new("8 lanes", name), |b| {
                b.iter(|| black_box(lanes(&*run)))
            });
        }
    }
    group.finish();

    // What a path that escapes pays: the environment's radiance and density (for the MIS
    // weight) in its direction.
    let (_, env) = lights().pop().expect("the environment is last");
    let Light::Environment(env) = env else {
        unreachable!("the last light is the environment")
    };
    let mut group = c.benchmark_group("environment lookup");
    group.throughput(Throughput::Elements(N as u64));
    group.bench_function("scalar", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for &(wo, _, _) in &inputs {
                let at = env.lookup(wo);
                sum += env.le_at(&at).r + env.pdf_at(&at);
            }
            black_box(sum)
        })
    });
    group.finish();

    // A triangle light sampled by area (`TriangleByArea`), as the wavefront's light stage
    // and the eight-lane bounce take it.
    let tri = [
        Vec3::new(-0.5, -0.5, 1.0),
        Vec3::new(0.5, -0.5, 1.0),
        Vec3::new(0.0, 0.6, 1.2),
    ];
    let light = AreaLight {
        emitter: emitter_of(tri),
        radiance: Rgb::splat(3.0),
        two_sided: false,
        texture: None,
    };
    let kernel = light
        .triangle_by_area(Vec3::ZERO, AreaSampling::Area)
        .expect("an untextured triangle");
    let mut group = c.benchmark_group("triangle light by area");
    group.throughput(Throughput::Elements(N as u64));
    group.bench_function("scalar", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for (p, &(_, _, u)) in points.iter().zip(&inputs) {
                if let Some(s) = light.sample_li(*p, u, AreaSampling::Area) {
                    sum += s.li.r / s.pdf;
                }
            }
            black_box(sum)
        })
    });
    group.bench_function("8 lanes", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for (p, i) in points.chunks_exact(8).zip(inputs.chunks_exact(8)) {
                let (p, u) = (p.try_into().expect("eight"), std::array::from_fn(|k| i[k].2));
                for s in sample_li_lanes(&[kernel; 8], p, &u, false).into_iter().flatten() {
                    sum += s.li.r / s.pdf;
                }
            }
            black_box(sum)
        })
    });
    group.finish();
}

fn emitter_of(v: [Vec3; 3]) -> Emitter {
    Emitter::new(EmitterShape::Triangle { v }).expect("a triangle with area")
}

fn textures(c: &mut Criterion) {
    let mut rng = Pcg32::new(5, 9);
    let uvs: Vec<Vec2> = (0..N)
        .map(|_| Vec2::new(rng.next_f32() * 3.0, rng.next_f32() * 3.0))
        .collect();
    let image = TextureImage {
        width: 256,
        height: 256,
        pixels: (0..256 * 256).map(|i| Rgb::splat((i % 251) as f32 / 251.0)).collect(),
        wrap: Default::default(),
    };
    let kinds = [
        ("constant", grey(0.5)),
        (
            "checker",
            Texture::Checker(penumbra::renderer::texture::Checker {
                even: Rgb::WHITE,
                odd: Rgb::BLACK,
                size: 0.1,
            }),
        ),
        (
            "image",
            Texture::Image(penumbra::renderer::texture::ImageTexture {
                image: Arc::new(image),
                scale: 1.0,
            }),
        ),
    ];
    let mut group = c.benchmark_group("texture eval");
    group.throughput(Throughput::Elements(N as u64));
    for (name, texture) in kinds {
        group.bench_function(BenchmarkId::new("scalar", name), |b| {
            b.iter(|| {
                let mut sum = 0.0f32;
                for uv in &uvs {
                    sum += texture.eval(*uv).g;
                }
                black_box(sum)
            })
        });
        group.bench_function(BenchmarkId::new("8 lanes", name), |b| {
            b.iter(|| {
                let mut sum = 0.0f32;
                for g in uvs.chunks_exact(8) {
                    sum += textures_at_level(&texture, g.try_into().expect("eight"));
                }
                black_box(sum)
            })
        });
    }
    group.finish();
}

/// Eight texture lookups in lanes of `L`, their green channels summed.
#[inline(always)]
fn texture_pass<L: Lane8>(texture: &Texture, uv: &[Vec2; 8]) -> f32 {
    let v = texture.eval_lanes(L::from_array(uv.map(|p| p.x)), L::from_array(uv.map(|p| p.y)));
    v.y.to_array().iter().sum()
}

/// [`texture_pass`] at the SIMD level the renderer runs.
fn textures_at_level(texture: &Texture, uv: &[Vec2; 8]) -> f32 {
    #[cfg(target_arch = "x86_64")]
    penumbra::math::level_fns! {
        unsafe fn [avx2, avx512](texture: &Texture, uv: &[Vec2; 8]) -> f32 {
            texture_pass::<F8Avx>(texture, uv)
        }
    }
    penumbra::math::at_level!(
        avx512: avx512(texture, uv),
        avx2: avx2(texture, uv),
        portable: texture_pass::<F8>(texture, uv)
    )
}

criterion_group!(benches, bsdfs, light_kernels, textures);
criterion_main!(benches);
