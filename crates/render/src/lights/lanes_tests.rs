//! The light kernels against their one-lane instances: eight lights of a kind (or the one
//! environment for eight points) in eight lanes give, lane by lane, the bits of the scalar
//! `sample_li` for the same inputs, including lanes with no sample (black lights, a point
//! at the source, directions outside a spot's cone).

use super::*;
use crate::test_payload::{Rgbg, RGB_CHANNEL};
use crate::texture::TextureImage;
use glam::Mat3;
use penumbra_core::lanes::{Lane8, F8, V3};
use penumbra_core::spectrum::Spectrum;
use penumbra_core::Draw;
use penumbra_core::Pcg32;

fn bits(v: Vec3) -> [u32; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}

fn rgb_bits(c: Rgb) -> [u32; 3] {
    [c.r.to_bits(), c.g.to_bits(), c.b.to_bits()]
}

fn point(rng: &mut Pcg32) -> Vec3 {
    Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 4.0 - Vec3::splat(2.0)
}

fn colour(rng: &mut Pcg32, k: usize) -> Rgb {
    if k % 5 == 4 {
        Rgb::BLACK
    } else {
        Rgb::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 3.0
    }
}

/// Runs `lanes` on eight random points (lane 3 at `at_source` when given) and compares
/// each lane with `scalar(k, p, u)`; the number of lanes with a sample.
fn compare<K: LightKernel<F8>>(
    rng: &mut Pcg32,
    lanes: &K,
    at_source: Option<Vec3>,
    scalar: impl Fn(usize, Vec3, Vec2) -> Option<LightSample>,
) -> usize {
    let mut p: [Vec3; 8] = std::array::from_fn(|_| point(rng));
    if let Some(source) = at_source {
        p[3] = source;
    }
    let u: [Vec2; 8] = std::array::from_fn(|_| Vec2::new(rng.next_f32(), rng.next_f32()));
    let s = lanes.sample_li(
        V3::from_lanes(&p),
        (F8::from_array(u.map(|u| u.x)), F8::from_array(u.map(|u| u.y))),
    );
    let ok = F8::bits(s.ok);
    let (wi, li, dist, pdf) = (s.wi.to_lanes(), s.li.to_lanes(), s.dist.to_array(), s.pdf.to_array());
    let mut samples = 0;
    for k in 0..8 {
        let one = scalar(k, p[k], u[k]);
        assert_eq!(ok >> k & 1 != 0, one.is_some(), "lane {k}: whether a sample exists");
        if let Some(one) = one {
            samples += 1;
            assert_eq!(bits(wi[k]), bits(one.wi), "lane {k}: wi");
            assert_eq!(
                rgb_bits(Rgb::new(li[k].x, li[k].y, li[k].z)),
                rgb_bits(one.li),
                "lane {k}: li"
            );
            assert_eq!(dist[k].to_bits(), one.dist.to_bits(), "lane {k}: dist");
            assert_eq!(pdf[k].to_bits(), one.pdf.to_bits(), "lane {k}: pdf");
        }
    }
    samples
}

#[test]
fn point_spot_and_directional_lanes_give_the_scalar_bits() {
    let mut rng = Pcg32::new(11, 3);
    let (mut points, mut spots, mut directionals) = (0, 0, 0);
    for _ in 0..2_000 {
        let lights: [Point; 8] = std::array::from_fn(|k| Point {
            position: point(&mut rng),
            intensity: colour(&mut rng, k),
        });
        let source = Some(lights[3].position);
        points += compare(
            &mut rng,
            &PointLanes::gather::<F8>(&lights.each_ref().map(|l| l.lanes())),
            source,
            |k, p, _| lights[k].sample_li(p),
        );
        let lights: [Spot; 8] = std::array::from_fn(|k| {
            let cone = 5.0 + rng.next_f32() * 80.0;
            // Some falloffs start at the cone's edge (a hard edge), some beyond it.
            let start = if k % 3 == 0 { cone } else { rng.next_f32() * 100.0 };
            Spot::new(point(&mut rng), point(&mut rng), colour(&mut rng, k), cone, start)
        });
        let source = Some(lights[3].position);
        spots += compare(
            &mut rng,
            &SpotLanes::gather::<F8>(&lights.each_ref().map(|l| l.lanes())),
            source,
            |k, p, _| lights[k].sample_li(p),
        );
        let lights: [Directional; 8] = std::array::from_fn(|k| Directional {
            direction: point(&mut rng).normalize(),
            irradiance: colour(&mut rng, k),
        });
        directionals += compare(
            &mut rng,
            &DirectionalLanes::gather::<F8>(&lights.each_ref().map(|l| l.lanes())),
            None,
            |k, p, _| lights[k].sample_li(p),
        );
    }
    // Every kind had lanes with and lanes without a sample.
    for (kind, n) in [("point", points), ("spot", spots), ("directional", directionals)] {
        assert!(n > 1_000 && n < 16_000, "{kind}: {n} samples of 16,000");
    }
}

/// Eight untextured triangle lights (some two-sided, some black) sampled by area in eight
/// lanes give each lane the scalar area light's sample, including lanes with none (a
/// point in a light's plane, the light's back seen from a one-sided light gives black).
#[test]
fn triangle_lights_by_area_in_lanes_give_the_scalar_bits() {
    let mut rng = Pcg32::new(5, 9);
    let mut samples = 0;
    for _ in 0..2_000 {
        let lights: [AreaLight; 8] = std::array::from_fn(|k| AreaLight {
            emitter: emitter::Emitter::new(emitter::EmitterShape::Triangle {
                v: [point(&mut rng), point(&mut rng), point(&mut rng)],
            })
            .expect("a triangle with an area"),
            radiance: colour(&mut rng, k),
            two_sided: k % 3 == 0,
            texture: None,
        });
        let one = lights.each_ref().map(|l| {
            l.triangle_by_area(Vec3::ZERO, AreaSampling::Area)
                .expect("an untextured triangle")
        });
        // Lane 3's point in its light's plane: no density there.
        let (v, _, _) = lights[3].emitter.triangle_parts().expect("a triangle");
        samples += compare(
            &mut rng,
            &TriangleByArea::gather::<F8>(&one),
            Some(0.5 * (v[0] + v[1])),
            |k, p, u| lights[k].sample_li(p, u, AreaSampling::Area),
        );
    }
    assert!(samples > 10_000 && samples < 16_000, "{samples} samples of 16,000");
}

/// A rotated image environment (a bright spot, a black row, which is never sampled, and a
/// gradient) and a constant one.
fn environments() -> [Environment; 3] {
    let (width, height) = (16, 8);
    let map = TextureImage {
        width,
        height,
        pixels: (0..width * height)
            .map(|i| match (i % width, i / width) {
                (3, 2) => Rgb::new(30.0, 20.0, 10.0),
                (_, 6) => Rgb::BLACK,
                (x, y) => Rgb::new(0.5 + 0.03 * x as f32, 0.4, 0.1 * y as f32),
            })
            .collect(),
        wrap: Default::default(),
    };
    let rotation = Mat3::from_axis_angle(Vec3::new(0.3, 1.0, 0.2).normalize(), 1.1);
    [
        Environment::image(map.clone(), Rgb::new(1.0, 2.0, 0.5), rotation, Draw::Inverted).expect("a valid map"),
        Environment::image(map, Rgb::new(1.0, 2.0, 0.5), rotation, Draw::Alias).expect("a valid map"),
        Environment::constant(Rgb::new(0.2, 0.3, 0.4)),
    ]
}

/// `Environment::lookup8` (eight directions in lanes at the CPU's SIMD level) gives each
/// direction the bits of the scalar `lookup`: radiance and density, in cells of every
/// row (the black row's density 0 included) and along the axes and poles.
#[test]
fn environment_lookups_in_eight_lanes_give_the_scalar_bits() {
    let mut rng = Pcg32::new(9, 2);
    let axes = [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
        Vec3::ONE,
        -Vec3::ONE,
    ];
    for (k, env) in environments().into_iter().enumerate() {
        let (mut black_row, mut densities) = (0, std::collections::HashSet::new());
        for round in 0..2_000 {
            let dirs: [Vec3; 8] = if round == 0 {
                axes
            } else {
                std::array::from_fn(|_| point(&mut rng))
            };
            for (d, lane) in dirs.iter().zip(env.lookup8(&dirs)) {
                let one = env.lookup(*d);
                assert_eq!(
                    rgb_bits(env.le_at(&lane)),
                    rgb_bits(env.le_at(&one)),
                    "radiance towards {d}"
                );
                assert_eq!(
                    env.pdf_at(&lane).to_bits(),
                    env.pdf_at(&one).to_bits(),
                    "density towards {d}"
                );
                black_row += (env.pdf_at(&one) == 0.0) as u32;
                densities.insert(env.pdf_at(&one).to_bits());
            }
        }
        // The images' lookups (either draw) met the black row and many cells; the
        // constant map has one density.
        let n = densities.len();
        if k < 2 {
            assert!(
                black_row > 100 && n > 100,
                "image: {black_row} in the black row, {n} densities"
            );
        } else {
            assert!(
                black_row == 0 && n == 1,
                "constant: {black_row} of density 0, {n} densities"
            );
        }
    }
}

#[test]
fn environment_lanes_give_the_scalar_bits() {
    let mut rng = Pcg32::new(4, 8);
    for env in environments() {
        let lanes = EnvironmentLanes::gather::<F8>(&[env.lanes(); 8]);
        let mut samples = 0;
        for _ in 0..4_000 {
            samples += compare(&mut rng, &lanes, None, |_, _, u| env.sample_li(u));
        }
        assert!(samples > 30_000, "{samples} samples of 32,000");
    }
}

/// `rgb` and the same light carrying the four-channel test payload (`four`) at eight
/// random points: the same directions, distances, densities and lanes with a sample,
/// and channel i of the light the RGB channel it holds.
fn compare_payloads(
    rng: &mut Pcg32,
    rgb: &impl LightKernel<F8>,
    four: impl Fn(V3<F8>, (F8, F8)) -> LaneLightSample<F8, Rgbg>,
) {
    let p = V3::from_lanes(&std::array::from_fn(|_| point(rng)));
    let u = (
        F8::from_array(std::array::from_fn(|_| rng.next_f32())),
        F8::from_array(std::array::from_fn(|_| rng.next_f32())),
    );
    let (a, b) = (rgb.sample_li(p, u), four(p, u));
    let ok = F8::bits(a.ok);
    assert_eq!(ok, F8::bits(b.ok), "lanes with a sample");
    for (x, y, what) in [
        (a.wi.x, b.wi.x, "wi.x"),
        (a.wi.y, b.wi.y, "wi.y"),
        (a.wi.z, b.wi.z, "wi.z"),
        (a.dist, b.dist, "dist"),
        (a.pdf, b.pdf, "pdf"),
    ] {
        let (x, y) = (x.to_array(), y.to_array());
        for k in (0..8).filter(|k| ok >> k & 1 != 0) {
            assert_eq!(x[k].to_bits(), y[k].to_bits(), "{what}, lane {k}");
        }
    }
    for (i, &c) in RGB_CHANNEL.iter().enumerate() {
        let (x, y) = (a.li.channel(c).to_array(), b.li.channel(i).to_array());
        for k in (0..8).filter(|k| ok >> k & 1 != 0) {
            assert_eq!(x[k].to_bits(), y[k].to_bits(), "li channel {i}, lane {k}");
        }
    }
}

/// The spectral-ready payload for lights: each kind's kernel carrying four channels
/// gives each channel the floats of the RGB run (point, spot, directional by their
/// converted intensities; the environment by its looked-up radiance converted).
#[test]
fn a_four_channel_payload_gives_each_channel_the_rgb_light() {
    let mut rng = Pcg32::new(12, 3);
    let env = Environment::constant(Rgb::new(0.2, 0.3, 0.4));
    for _ in 0..500 {
        let points: [Point; 8] = std::array::from_fn(|k| Point {
            position: point(&mut rng),
            intensity: colour(&mut rng, k),
        });
        let k = PointLanes::gather::<F8>(&points.each_ref().map(|l| l.lanes()));
        compare_payloads(&mut rng, &k, |p, u| k.with_spectrum(Rgbg::of).sample_li(p, u));
        let spots: [Spot; 8] =
            std::array::from_fn(|k| Spot::new(point(&mut rng), point(&mut rng), colour(&mut rng, k), 60.0, 40.0));
        let k = SpotLanes::gather::<F8>(&spots.each_ref().map(|l| l.lanes()));
        compare_payloads(&mut rng, &k, |p, u| k.with_spectrum(Rgbg::of).sample_li(p, u));
        let suns: [Directional; 8] = std::array::from_fn(|k| Directional {
            direction: point(&mut rng).normalize(),
            irradiance: colour(&mut rng, k),
        });
        let k = DirectionalLanes::gather::<F8>(&suns.each_ref().map(|l| l.lanes()));
        compare_payloads(&mut rng, &k, |p, u| k.with_spectrum(Rgbg::of).sample_li(p, u));
        let k = EnvironmentLanes::gather::<F8>(&[env.lanes(); 8]);
        compare_payloads(&mut rng, &k, |p, u| k.sample_li_with(p, u, Rgbg::of));
    }
}
