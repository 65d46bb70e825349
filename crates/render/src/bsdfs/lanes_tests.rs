//! The lane kernels against their one-lane instances: eight different BSDFs of a kind in
//! eight lanes give, lane by lane, the bits the scalar BSDF gives for the same inputs
//! (sample, eval and pdf), including lanes where no sample exists.

use super::microfacet::Ggx;
use super::*;
use crate::test_payload::Rgbg;
use penumbra_core::lanes::{Lane8, F8};
use penumbra_core::spectrum::{Sampled4, Spectrum};
use penumbra_core::Pcg32;

/// A direction on the sphere from two uniforms, some of them below the surface.
fn direction(rng: &mut Pcg32) -> Vec3 {
    penumbra_core::warp::uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()))
}

fn lanes_of(v: [Vec3; 8]) -> V3<F8> {
    V3::from_lanes(&v)
}

fn f8(a: [f32; 8]) -> F8 {
    F8::from_array(a)
}

/// Eight conductors: smooth and rough, anisotropic, exact and Schlick Fresnel terms.
fn conductors(rng: &mut Pcg32) -> [Conductor; 8] {
    std::array::from_fn(|k| {
        let c = |rng: &mut Pcg32| Rgb::new(rng.next_f32() * 3.0, rng.next_f32() * 3.0, rng.next_f32() * 3.0);
        let fresnel = if k % 3 == 2 {
            MetalFresnel::Schlick
        } else {
            MetalFresnel::Complex { eta: c(rng), k: c(rng) }
        };
        let alpha = (k % 4 != 0)
            .then(|| Ggx::new(rng.next_f32() * 0.8, rng.next_f32() * 0.8))
            .flatten();
        Conductor {
            fresnel,
            specular: Rgb::new(rng.next_f32(), rng.next_f32(), rng.next_f32()),
            alpha,
        }
    })
}

fn bits(v: Vec3) -> [u32; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}

/// Runs the kernel `lanes` on random inputs for the eight scalar BSDFs `scalar` and
/// compares every lane with the scalar BSDF's own answer; the number of samples that
/// existed.
fn compare(rng: &mut Pcg32, scalar: &[&dyn BsdfModel; 8], lanes: &impl LaneKernel<F8>, mode: TransportMode) -> usize {
    let wo: [Vec3; 8] = std::array::from_fn(|_| direction(rng));
    let wi: [Vec3; 8] = std::array::from_fn(|_| direction(rng));
    let u: [Vec2; 8] = std::array::from_fn(|_| Vec2::new(rng.next_f32(), rng.next_f32()));
    let (lwo, lwi) = (lanes_of(wo), lanes_of(wi));
    let u_lobe: [f32; 8] = std::array::from_fn(|_| rng.next_f32());
    let s = lanes.sample(lwo, f8(u_lobe), (f8(u.map(|u| u.x)), f8(u.map(|u| u.y))));
    let (eval, pdf) = (lanes.eval(lwo, lwi).to_lanes(), lanes.pdf(lwo, lwi).to_array());
    let (ok, delta) = (F8::mask_bits(s.ok), F8::mask_bits(s.delta));
    let (swi, sweight, spdf, seta) = (s.wi.to_lanes(), s.weight.to_lanes(), s.pdf.to_array(), s.eta.to_array());
    let mut samples = 0;
    for k in 0..8 {
        let c = scalar[k];
        let e: Vec3 = Into::<V3<f32>>::into(c.eval(wo[k], wi[k], mode)).into();
        assert_eq!(bits(eval[k]), bits(e), "eval, lane {k}");
        assert_eq!(pdf[k].to_bits(), c.pdf(wo[k], wi[k], mode).to_bits(), "pdf, lane {k}");
        let one = c.sample(wo[k], u_lobe[k], u[k], mode);
        assert_eq!(ok >> k & 1 != 0, one.is_some(), "sample exists, lane {k}: {:?}", wo[k]);
        if let Some(one) = one {
            samples += 1;
            assert_eq!(bits(swi[k]), bits(one.wi), "sampled direction, lane {k}");
            let w = Vec3::new(one.weight.r, one.weight.g, one.weight.b);
            assert_eq!(bits(sweight[k]), bits(w), "sample weight, lane {k}");
            assert_eq!(spdf[k].to_bits(), one.pdf.to_bits(), "sample density, lane {k}");
            assert_eq!(delta >> k & 1 != 0, one.delta, "delta, lane {k}");
            assert_eq!(seta[k].to_bits(), one.eta.to_bits(), "relative index, lane {k}");
        }
    }
    samples
}

// About half the views are above the surface, and most of their samples exist: 2,000
// rounds of eight lanes give some 7,000 samples to compare.
const ROUNDS: usize = 2_000;
const AT_LEAST: usize = 4_000;

#[test]
fn conductor_lanes_equal_the_scalar_conductor_bit_for_bit() {
    let mut rng = Pcg32::new(11, 5);
    let mut samples = 0;
    for _ in 0..ROUNDS {
        let cs = conductors(&mut rng);
        let lanes = Gather::gather::<F8>(&cs.map(|c| c.lanes(TransportMode::Radiance)));
        let scalar: [&dyn BsdfModel; 8] = std::array::from_fn(|k| &cs[k] as &dyn BsdfModel);
        samples += compare(&mut rng, &scalar, &lanes, TransportMode::Radiance);
    }
    assert!(samples > AT_LEAST, "only {samples} samples existed");
}

#[test]
fn diffuse_lanes_equal_the_scalar_diffuse_bit_for_bit() {
    let mut rng = Pcg32::new(12, 5);
    let mut samples = 0;
    for _ in 0..ROUNDS {
        let ds = diffuses(&mut rng);
        let lanes = Gather::gather::<F8>(&ds.map(|d| d.lanes(TransportMode::Radiance)));
        let scalar: [&dyn BsdfModel; 8] = std::array::from_fn(|k| &ds[k] as &dyn BsdfModel);
        samples += compare(&mut rng, &scalar, &lanes, TransportMode::Radiance);
    }
    assert!(samples > AT_LEAST, "only {samples} samples existed");
}

/// Eight dielectrics: smooth and rough, indices above and below 1 and index-matched.
fn dielectrics(rng: &mut Pcg32) -> [Dielectric; 8] {
    std::array::from_fn(|k| Dielectric {
        eta: [1.5, 1.0 / 1.33, 1.0, 2.4][k % 4] + if k < 4 { 0.0 } else { rng.next_f32() * 0.1 },
        reflectance: Rgb::new(rng.next_f32(), rng.next_f32(), 1.0),
        transmittance: Rgb::new(1.0, rng.next_f32(), rng.next_f32()),
        alpha: (k % 3 != 0)
            .then(|| Ggx::new(rng.next_f32() * 0.6, rng.next_f32() * 0.6))
            .flatten(),
    })
}

#[test]
fn dielectric_lanes_equal_the_scalar_dielectric_bit_for_bit() {
    let mut rng = Pcg32::new(13, 5);
    for mode in [TransportMode::Radiance, TransportMode::Importance] {
        let mut samples = 0;
        for _ in 0..ROUNDS {
            let ds = dielectrics(&mut rng);
            let lanes = Gather::gather::<F8>(&ds.map(|d| d.lanes(mode)));
            let scalar: [&dyn BsdfModel; 8] = std::array::from_fn(|k| &ds[k] as &dyn BsdfModel);
            samples += compare(&mut rng, &scalar, &lanes, mode);
        }
        // Glass samples from both sides, so nearly every view gives one.
        assert!(samples > 2 * AT_LEAST, "{mode:?}: only {samples} samples existed");
    }
}

#[test]
fn plastic_lanes_equal_the_scalar_plastic_bit_for_bit() {
    let mut rng = Pcg32::new(14, 5);
    let coats = coatings();
    let mut samples = 0;
    for _ in 0..ROUNDS {
        let ps = plastics(&mut rng, &coats);
        let lanes = Gather::gather::<F8>(&ps.map(|p| p.lanes(TransportMode::Radiance)));
        let scalar: [&dyn BsdfModel; 8] = std::array::from_fn(|k| &ps[k] as &dyn BsdfModel);
        samples += compare(&mut rng, &scalar, &lanes, TransportMode::Radiance);
    }
    assert!(samples > AT_LEAST, "only {samples} samples existed");
}

#[test]
fn phong_lanes_equal_the_scalar_phong_bit_for_bit() {
    let mut rng = Pcg32::new(15, 5);
    for mode in [TransportMode::Radiance, TransportMode::Importance] {
        let mut samples = 0;
        for _ in 0..ROUNDS {
            let ps = phongs(&mut rng);
            let lanes = Gather::gather::<F8>(&ps.map(|p| p.lanes(mode)));
            let scalar: [&dyn BsdfModel; 8] = std::array::from_fn(|k| &ps[k] as &dyn BsdfModel);
            samples += compare(&mut rng, &scalar, &lanes, mode);
        }
        assert!(samples > AT_LEAST, "{mode:?}: only {samples} samples existed");
    }
}

fn diffuses(rng: &mut Pcg32) -> [Diffuse; 8] {
    std::array::from_fn(|_| Diffuse {
        reflectance: Rgb::new(rng.next_f32(), rng.next_f32(), rng.next_f32()),
    })
}

/// Smooth and rough coatings of a few indices and roughnesses, tables made once.
fn coatings() -> Vec<(f32, Option<Ggx>, Coating)> {
    [(1.5, 0.0), (1.5, 0.1), (1.33, 0.3), (1.9, 0.05)]
        .into_iter()
        .map(|(eta, alpha)| {
            let ggx = Ggx::new(alpha, alpha);
            let coating = ggx.map_or(Coating::smooth(eta), |g| Coating::rough(eta, g));
            (eta, ggx, coating)
        })
        .collect()
}

fn plastics<'a>(rng: &mut Pcg32, coats: &'a [(f32, Option<Ggx>, Coating)]) -> [Plastic<'a>; 8] {
    std::array::from_fn(|k| {
        let (eta, alpha, coating) = &coats[(k + rng.next_below(4) as usize) % 4];
        Plastic {
            diffuse: Rgb::new(rng.next_f32(), rng.next_f32(), rng.next_f32()),
            specular: Rgb::splat(rng.next_f32()),
            eta: *eta,
            coating,
            specular_weight: rng.next_f32(),
            alpha: *alpha,
        }
    })
}

/// Every mix of black and coloured diffuse, glossy, mirror and transmission parts,
/// exponents from 0 (a flat lobe) up, indices on both sides of 1.
fn phongs(rng: &mut Pcg32) -> [PhongBsdf; 8] {
    std::array::from_fn(|k| {
        let mut colour = |part: usize| {
            let c = Rgb::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.5;
            if (k >> part) & 1 == 0 && rng.next_below(2) == 0 {
                Rgb::BLACK
            } else {
                c
            }
        };
        let (diffuse, specular, mirror, transmission) = (colour(0), colour(1), colour(2), colour(3));
        PhongBsdf {
            diffuse,
            specular,
            exponent: [0.0, 1.0, 20.0, 3.5][k % 4],
            mirror,
            transmission,
            eta: [1.5, 0.75, 1.0, 2.4][(k + 1) % 4],
        }
    })
}

/// Kernel `rgb` and the same kernel carrying [`Rgbg`] (`four`) on random inputs: every
/// direction, density, mask and relative index equal, and channel i of every value the
/// RGB channel i (the fourth the green one).
fn compare_payloads(rng: &mut Pcg32, rgb: &impl LaneKernel<F8>, four: &impl LaneKernel<F8, Rgbg>) {
    let lanes3 = |rng: &mut Pcg32| lanes_of(std::array::from_fn(|_| direction(rng)));
    let f8s = |rng: &mut Pcg32| f8(std::array::from_fn(|_| rng.next_f32()));
    let (wo, wi, u_lobe, u) = (lanes3(rng), lanes3(rng), f8s(rng), (f8s(rng), f8s(rng)));
    let same =
        |a: F8, b: F8, what: &str| assert_eq!(a.to_array().map(f32::to_bits), b.to_array().map(f32::to_bits), "{what}");
    let same_colour = |a: V3<F8>, b: Rgbg, what: &str| {
        for i in 0..4 {
            same(a.channel(crate::test_payload::RGB_CHANNEL[i]), b.channel(i), what);
        }
    };
    same_colour(rgb.eval(wo, wi), four.eval(wo, wi), "eval");
    same(rgb.pdf(wo, wi), four.pdf(wo, wi), "pdf");
    let (a, b) = (rgb.sample(wo, u_lobe, u), four.sample(wo, u_lobe, u));
    assert_eq!(F8::bits(a.ok), F8::bits(b.ok), "sample exists");
    let ok = F8::bits(a.ok);
    // Where no sample exists the values are unspecified: compare the others.
    let keep = |v: F8| {
        F8::from_array(std::array::from_fn(|k| {
            if ok >> k & 1 != 0 {
                v.to_array()[k]
            } else {
                0.0
            }
        }))
    };
    let keep3 = |v: V3<F8>| V3::new(keep(v.x), keep(v.y), keep(v.z));
    let keep4 = |v: Rgbg| Rgbg(Sampled4(v.0 .0.map(keep)));
    for (x, y, what) in [
        (a.wi.x, b.wi.x, "wi.x"),
        (a.wi.y, b.wi.y, "wi.y"),
        (a.wi.z, b.wi.z, "wi.z"),
        (a.pdf, b.pdf, "sample pdf"),
        (a.eta, b.eta, "eta"),
    ] {
        same(keep(x), keep(y), what);
    }
    assert_eq!(F8::bits(a.delta) & ok, F8::bits(b.delta) & ok, "delta");
    same_colour(keep3(a.weight), keep4(b.weight), "sample weight");
}

/// The spectral-ready payload: every BSDF kind's kernel, run carrying four channels
/// instead of RGB's three, gives each channel the floats of the RGB run, and the same
/// directions, densities and choices: a spectral renderer's four wavelengths are another
/// payload of the same code, not a second copy of it.
#[test]
fn a_four_channel_payload_gives_each_channel_the_rgb_floats() {
    let mut rng = Pcg32::new(16, 5);
    let coats = coatings();
    let to4 = |_: Role, v| Rgbg::of(v);
    for _ in 0..ROUNDS / 4 {
        let mode = if rng.next_below(2) == 0 {
            TransportMode::Radiance
        } else {
            TransportMode::Importance
        };
        let k = Gather::gather::<F8>(&diffuses(&mut rng).map(|d| d.lanes(mode)));
        compare_payloads(&mut rng, &k, &k.with_spectrum(to4));
        let k = Gather::gather::<F8>(&conductors(&mut rng).map(|d| d.lanes(mode)));
        compare_payloads(&mut rng, &k, &k.with_spectrum(to4));
        let k = Gather::gather::<F8>(&dielectrics(&mut rng).map(|d| d.lanes(mode)));
        compare_payloads(&mut rng, &k, &k.with_spectrum(to4));
        let k = Gather::gather::<F8>(&plastics(&mut rng, &coats).map(|d| d.lanes(mode)));
        compare_payloads(&mut rng, &k, &k.with_spectrum(to4));
        let k = Gather::gather::<F8>(&phongs(&mut rng).map(|d| d.lanes(mode)));
        compare_payloads(&mut rng, &k, &k.with_spectrum(to4));
        // A blend's mixture of two kinds, weights 0 and 1 included.
        let a = Gather::gather::<F8>(&diffuses(&mut rng).map(|d| d.lanes(mode)));
        let b = Gather::gather::<F8>(&conductors(&mut rng).map(|d| d.lanes(mode)));
        let weight = f8(std::array::from_fn(|k| [0.0, 1.0, rng.next_f32()][k % 3]));
        let rgb = MixtureLanes { a, b, weight };
        let four = MixtureLanes {
            a: a.with_spectrum(to4),
            b: b.with_spectrum(to4),
            weight,
        };
        compare_payloads(&mut rng, &rgb, &four);
    }
}

/// Blends of a Lambertian and a conductor (smooth or rough) with weights including 0 and
/// 1 (a part left out): eight lanes of the mixture of the two kinds' lane kernels give
/// the scalar blend's bits, whose parts are whole `Bsdf`s.
#[test]
fn blend_lanes_equal_the_scalar_blend_bit_for_bit() {
    use crate::materials::{ConductorMaterial, DiffuseMaterial, Roughness};
    use crate::{Material, Texture};
    let mut rng = Pcg32::new(17, 5);
    let mut samples = 0;
    for _ in 0..ROUNDS {
        let mut colour = || Rgb::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let a: [Material; 8] = std::array::from_fn(|_| {
            Material::Diffuse(DiffuseMaterial {
                reflectance: Texture::Constant(colour()),
            })
        });
        let b: [Material; 8] = std::array::from_fn(|k| {
            Material::Conductor(ConductorMaterial {
                specular: Texture::Constant(colour()),
                roughness: (k % 2 == 1).then(|| Roughness::isotropic(0.05 + 0.5 * (k as f32 / 8.0))),
                ..ConductorMaterial::default()
            })
        });
        let weight: [f32; 8] = std::array::from_fn(|k| match k {
            0 => 0.0,
            1 => 1.0,
            _ => rng.next_f32(),
        });
        let blends: [Blend; 8] = std::array::from_fn(|k| Blend {
            a: &a[k],
            b: &b[k],
            weight: weight[k],
            uv: Vec2::ZERO,
        });
        let part = |m: &Material| match m.bsdf(Vec2::ZERO).kind {
            BsdfKind::Diffuse(d) => (Some(d.lanes(TransportMode::Radiance)), None),
            BsdfKind::Conductor(c) => (None, Some(c.lanes(TransportMode::Radiance))),
            _ => unreachable!("a diffuse or a conductor"),
        };
        let lanes = MixtureLanes {
            a: Gather::gather::<F8>(&a.each_ref().map(|m| part(m).0.expect("diffuse"))),
            b: Gather::gather::<F8>(&b.each_ref().map(|m| part(m).1.expect("conductor"))),
            weight: f8(weight),
        };
        let scalar: [&dyn BsdfModel; 8] = std::array::from_fn(|k| &blends[k] as &dyn BsdfModel);
        samples += compare(&mut rng, &scalar, &lanes, TransportMode::Radiance);
    }
    assert!(samples > AT_LEAST, "only {samples} samples existed");
}

/// Eight layered BSDFs: smooth and rough coatings over diffuse, rough and mirror metal
/// bases, with and without a scattering medium, walks of 1 to 12 events, 1 to 3 walks
/// per estimate: every lane walks its own way, and gives the one-lane floats.
fn layereds(rng: &mut Pcg32) -> [Layered; 8] {
    let ds = dielectrics(rng);
    let cs = conductors(rng);
    std::array::from_fn(|k| {
        let base = if k % 2 == 0 {
            LayerBase::Diffuse(Diffuse {
                reflectance: Rgb::new(rng.next_f32(), rng.next_f32(), rng.next_f32()),
            })
        } else {
            LayerBase::Conductor(cs[k])
        };
        let medium = k % 3 != 0;
        Layered {
            coat: Dielectric {
                reflectance: Rgb::WHITE,
                transmittance: Rgb::WHITE,
                ..ds[k]
            },
            base,
            thickness: if medium {
                0.05 + rng.next_f32()
            } else {
                f32::MIN_POSITIVE
            },
            albedo: if medium {
                Rgb::new(rng.next_f32(), rng.next_f32(), rng.next_f32())
            } else {
                Rgb::BLACK
            },
            g: rng.next_f32() * 1.6 - 0.8,
            max_depth: 1 + (rng.next_u32() % 12),
            samples: 1 + (rng.next_u32() % 3),
        }
    })
}

#[test]
fn layered_lanes_equal_the_scalar_layered_bit_for_bit() {
    let mut rng = Pcg32::new(17, 5);
    for mode in [TransportMode::Radiance, TransportMode::Importance] {
        let mut samples = 0;
        for _ in 0..ROUNDS / 4 {
            let ls = layereds(&mut rng);
            let lanes = Gather::gather::<F8>(&ls.map(|l| l.lanes(mode)));
            let scalar: [&dyn BsdfModel; 8] = std::array::from_fn(|k| &ls[k] as &dyn BsdfModel);
            samples += compare(&mut rng, &scalar, &lanes, mode);
        }
        // Half the views are above the surface; most of their walks leave.
        assert!(samples > AT_LEAST / 8, "{mode:?}: only {samples} samples existed");
    }
}
