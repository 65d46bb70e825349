//! The layered BSDF against what must hold whatever the walk does: the closed form of a
//! smooth coating over a Lambertian base (what pbrt-v4's `coateddiffuse` converges to),
//! energy kept by lossless stacks, reciprocity, and the specular series of a smooth
//! coating over a smooth metal.

use super::*;
use crate::bsdfs::microfacet::Ggx;
use crate::bsdfs::{BsdfKind, MetalFresnel};
use crate::materials::{metal_ior, Coated, CoatedBase, Roughness};
use crate::optics::fresnel_diffuse_reflectance;
use crate::{Material, Texture};
use penumbra_testkit::{assert_within_se, MeanEstimate, Uniforms};
use std::f32::consts::PI;

const RADIANCE: TransportMode = TransportMode::Radiance;

fn dir(theta_degrees: f32, phi_degrees: f32) -> Vec3 {
    let (t, p) = (theta_degrees.to_radians(), phi_degrees.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

fn coat(eta: f32, alpha: Option<f32>) -> Dielectric {
    Dielectric {
        eta,
        reflectance: Rgb::WHITE,
        transmittance: Rgb::WHITE,
        alpha: alpha.and_then(|a| Ggx::new(a, a)),
    }
}

fn over_diffuse(rho: f32, coat: Dielectric) -> Layered {
    Layered {
        coat,
        base: LayerBase::Diffuse(Diffuse {
            reflectance: Rgb::splat(rho),
        }),
        thickness: f32::MIN_POSITIVE,
        albedo: Rgb::BLACK,
        g: 0.0,
        max_depth: 400,
        samples: 1,
    }
}

/// Mean and standard error of `n` walks' estimates (red channel) of f(wo, wi), without
/// the coating's own reflection.
fn walks(l: &Layered, wo: Vec3, wi: Vec3, n: usize, seed: u64) -> (f64, f64) {
    let mut m = MeanEstimate::default();
    for f in l.lanes(RADIANCE).walk_estimates(wo, wi, n, seed) {
        m.push(f.r as f64);
    }
    (m.mean(), m.standard_error())
}

/// The light that enters a smooth coating, bounces between it and a Lambertian base of
/// albedo ρ any number of times and leaves: f = (1 - F(θo)) (1 - F(θi)) ρ / (π η² (1 - ρ
/// F_dr,int)), F_dr,int = 2 ∫ F(μ, 1/η) μ dμ. 40,000 walks per pair of directions; 4
/// standard errors (27 comparisons) plus 1e-4 relative for the single-precision sums.
#[test]
fn a_smooth_coat_over_a_lambertian_base_is_the_closed_form() {
    let mut seed = 0;
    for (rho, eta) in [(0.5f32, 1.5f32), (0.9, 1.5), (0.7, 1.33)] {
        let l = over_diffuse(rho, coat(eta, None));
        let fdr = fresnel_diffuse_reflectance(1.0 / eta) as f64;
        for (to, ti) in [(0.0, 30.0), (45.0, 60.0), (80.0, 10.0)] {
            let (wo, wi) = (dir(to, 0.0), dir(ti, 140.0));
            let t = |w: Vec3| 1.0 - fresnel_dielectric(w.z, eta) as f64;
            let rho = rho as f64;
            let want = t(wo) * t(wi) * rho / (std::f64::consts::PI * (eta * eta) as f64 * (1.0 - rho * fdr));
            seed += 1;
            let (mean, se) = walks(&l, wo, wi, 40_000, seed);
            let what = format!("rho {rho} eta {eta}, {to} -> {ti} degrees");
            assert_within_se(&what, mean, se, want, 1e-4 * want, 4.0);
        }
    }
}

/// A white base under a smooth coating, with nothing between or with a white scattering
/// medium, keeps every bit of the light: every sampled walk leaves with weight exactly 1
/// (radiance's 1/η² in and η² out cancel), and eval integrates to 1 (cosine-weighted
/// directions, 100,000 of them, 4 standard errors).
#[test]
fn lossless_stacks_keep_all_the_energy() {
    let clear = over_diffuse(1.0, coat(1.5, None));
    let foggy = Layered {
        thickness: 0.5,
        albedo: Rgb::WHITE,
        g: 0.5,
        ..clear
    };
    for (name, l) in [("clear", clear), ("white medium", foggy)] {
        let mut u = Uniforms::new(3);
        for theta in [0.0, 50.0, 85.0] {
            let wo = dir(theta, 20.0);
            for _ in 0..20_000 {
                let s = l
                    .sample(wo, u.next_f32(), u.next_vec2(), RADIANCE)
                    .expect("a lossless walk leaves");
                assert!(s.wi.z > 0.0, "{name} from {theta}: left below");
                for c in [s.weight.r, s.weight.g, s.weight.b] {
                    assert!((c - 1.0).abs() < 1e-4, "{name} from {theta}: weight {c}");
                }
            }
            let mut m = MeanEstimate::default();
            for _ in 0..100_000 {
                let wi = penumbra_core::warp::cosine_hemisphere(u.next_vec2());
                m.push(if wi.z > 0.0 {
                    (l.eval(wo, wi, RADIANCE).r * PI) as f64
                } else {
                    0.0
                });
            }
            let f = fresnel_dielectric(wo.z, 1.5) as f64;
            let what = format!("{name} from {theta}: ∫ f cos + F");
            assert_within_se(&what, m.mean() + f, m.standard_error(), 1.0, 1e-4, 4.0);
        }
    }
}

/// f(wo, wi) = f(wi, wo) in expectation for a rough coating over rough gold with a
/// scattering medium between (100,000 walks each way, 4 combined standard errors).
#[test]
fn layered_bsdfs_are_reciprocal() {
    let (eta, k) = metal_ior("Au").unwrap();
    let l = Layered {
        coat: coat(1.5, Some(0.25)),
        base: LayerBase::Conductor(Conductor {
            fresnel: MetalFresnel::Complex {
                eta: eta / 1.5,
                k: k / 1.5,
            },
            specular: Rgb::WHITE,
            alpha: Ggx::new(0.3, 0.3),
        }),
        thickness: 0.2,
        albedo: Rgb::splat(0.6),
        g: 0.3,
        max_depth: 10,
        samples: 1,
    };
    for (a, b) in [(dir(20.0, 0.0), dir(50.0, 160.0)), (dir(70.0, 10.0), dir(5.0, 200.0))] {
        let (fab, se_ab) = walks(&l, a, b, 100_000, 1);
        let (fba, se_ba) = walks(&l, b, a, 100_000, 2);
        let se = (se_ab * se_ab + se_ba * se_ba).sqrt();
        assert_within_se("f(a, b) against f(b, a)", fab, se, fba, 1e-5, 4.0);
        assert!(fab > 0.0);
    }
}

/// A smooth coating over a smooth metal is a mirror whose weight is a geometric series;
/// the sampled walks' mean weight is that series (200,000 samples, 4 standard errors),
/// truncated where the walks are (an odd `max_depth`, and 1, where no light gets back out),
/// and with a scattering medium the unscattered (delta) part still is.
#[test]
fn a_smooth_coat_over_a_smooth_metal_is_the_series() {
    let (eta, k) = metal_ior("Cu").unwrap();
    let metal = Layered {
        coat: coat(1.5, None),
        base: LayerBase::Conductor(Conductor {
            fresnel: MetalFresnel::Complex {
                eta: eta / 1.5,
                k: k / 1.5,
            },
            specular: Rgb::WHITE,
            alpha: None,
        }),
        thickness: 0.05,
        albedo: Rgb::BLACK,
        g: 0.0,
        max_depth: 10,
        samples: 1,
    };
    let foggy = Layered {
        albedo: Rgb::splat(0.7),
        thickness: 0.3,
        ..metal
    };
    let short = |max_depth: u32| Layered { max_depth, ..metal };
    let cases = [
        ("clear", metal),
        ("medium", foggy),
        ("clear, max_depth 7", short(7)),
        ("clear, max_depth 1 (no way out of the layer)", short(1)),
    ];
    for (name, l) in cases {
        assert_eq!(l.has_smooth(), name == "medium");
        for theta in [0.0, 60.0, 85.0] {
            let wo = dir(theta, 30.0);
            let mut rays = SpecularRays::default();
            l.specular_rays(wo, RADIANCE, &mut rays);
            let want = rays.as_slice()[0].weight;
            assert!((rays.as_slice()[0].wi - reflect_z(wo)).length() < 1e-6);
            let mut u = Uniforms::new(8);
            let mut m = [MeanEstimate::default(), MeanEstimate::default()];
            for _ in 0..200_000 {
                let s = l.sample(wo, u.next_f32(), u.next_vec2(), RADIANCE).filter(|s| s.delta);
                m[0].push(s.map_or(0.0, |s| s.weight.r as f64));
                m[1].push(s.map_or(0.0, |s| s.weight.b as f64));
            }
            for (m, w) in m.iter().zip([want.r, want.b]) {
                let what = format!("{name} from {theta}");
                assert_within_se(&what, m.mean(), m.standard_error(), w as f64, 1e-4, 4.0);
            }
        }
    }
}

/// The coated material's parameters reach the BSDF: the metal's index is taken relative
/// to the coating's, the coating is two-sided, and every field has pbrt-v4's default.
#[test]
fn coated_materials_build_the_layered_bsdf() {
    let d = Coated::default();
    assert_eq!(
        (d.eta, d.thickness, d.g, d.max_depth, d.samples),
        (1.5, 0.01, 0.0, 10, 1)
    );
    let m = Material::Coated(Coated {
        base: CoatedBase::Conductor {
            fresnel: MetalFresnel::Complex {
                eta: Rgb::splat(2.0),
                k: Rgb::splat(3.0),
            },
            specular: Texture::Constant(Rgb::WHITE),
            roughness: Some(Roughness::isotropic(0.2)),
        },
        eta: 1.6,
        ..Coated::default()
    });
    let b = m.bsdf(Vec2::ZERO);
    assert!(b.two_sided && b.stochastic());
    let BsdfKind::Layered(l) = b.kind else {
        panic!("not layered: {:?}", b.kind)
    };
    let LayerBase::Conductor(c) = l.base else {
        panic!("not a metal base")
    };
    assert_eq!(
        c.fresnel,
        MetalFresnel::Complex {
            eta: Rgb::splat(2.0 / 1.6),
            k: Rgb::splat(3.0 / 1.6)
        }
    );
    assert!(c.alpha.is_some() && l.coat.alpha.is_none() && l.coat.eta == 1.6);
    // From below, the two-sided coating reflects as from above.
    let below = Vec3::new(0.3, 0.1, -0.9).normalize();
    let above = Vec3::new(below.x, below.y, -below.z);
    let wi = dir(40.0, 100.0);
    let flipped = Vec3::new(wi.x, wi.y, -wi.z);
    let f = b.eval(above, wi, RADIANCE);
    assert!(f.r > 0.0, "{f:?}");
    assert_eq!(b.eval(below, flipped, RADIANCE), f);
}
