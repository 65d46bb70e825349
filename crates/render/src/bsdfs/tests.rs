//! Every BSDF against its own claims: sampling fits the density (chi-square over the
//! sphere, with the density's integral checked), the sample weight is f |cos| / pdf, and
//! furnace tests of the directional albedo, E[weight] = ∫ f |cos θi| dωi.

use super::microfacet::Ggx;
use super::*;
use crate::materials::{metal_ior, Coated, CoatedBase, Roughness};
use crate::materials::{ConductorMaterial, DielectricMaterial, DiffuseMaterial};
use crate::{Material, Texture};
use penumbra_testkit::{assert_within_3se, chi2_directions, MeanEstimate, Uniforms};

pub(super) fn grey(v: f32) -> Texture {
    Texture::Constant(Rgb::splat(v))
}

pub(super) fn rough(alpha: f32) -> Option<Roughness> {
    Some(Roughness::isotropic(alpha))
}

pub(super) fn view(theta_degrees: f32) -> Vec3 {
    let t = theta_degrees.to_radians();
    Vec3::new(t.sin(), 0.1 * t.sin(), t.cos()).normalize()
}

/// The materials under test, named, each with the views to test it from (degrees from
/// the normal; beyond 90 is from below).
pub(super) fn cases() -> Vec<(String, Material, Vec<f32>)> {
    let (au_eta, au_k) = metal_ior("Au").unwrap();
    let conductor = |ax: f32, ay: f32| {
        Material::Conductor(ConductorMaterial {
            fresnel: MetalFresnel::Complex { eta: au_eta, k: au_k },
            specular: grey(1.0),
            roughness: Some(Roughness {
                alpha_u: grey(ax),
                alpha_v: grey(ay),
            }),
        })
    };
    let dielectric = |eta: f32, alpha: f32| {
        Material::Dielectric(DielectricMaterial {
            eta,
            reflectance: grey(1.0),
            transmittance: grey(1.0),
            roughness: rough(alpha),
        })
    };
    vec![
        (
            "diffuse".into(),
            Material::Diffuse(DiffuseMaterial { reflectance: grey(0.7) }),
            vec![0.0, 60.0],
        ),
        (
            "two-sided diffuse".into(),
            Material::TwoSided(Box::new(Material::Diffuse(DiffuseMaterial { reflectance: grey(0.7) }))),
            vec![30.0, 150.0],
        ),
        (
            "phong glossy + diffuse + glass".into(),
            Material::Phong(crate::materials::Phong {
                diffuse: grey(0.3),
                specular: Rgb::splat(0.4),
                exponent: 8.0,
                transmission: Rgb::splat(0.3),
                ..Default::default()
            }),
            vec![20.0, 70.0, 130.0],
        ),
        ("rough gold 0.2".into(), conductor(0.2, 0.2), vec![0.0, 45.0, 80.0]),
        ("rough gold 0.6".into(), conductor(0.6, 0.6), vec![30.0, 75.0]),
        (
            "anisotropic gold 0.1 x 0.5".into(),
            conductor(0.1, 0.5),
            vec![10.0, 60.0],
        ),
        (
            "rough glass 0.2".into(),
            dielectric(1.5, 0.2),
            vec![0.0, 50.0, 140.0, 170.0],
        ),
        ("rough glass 0.5".into(), dielectric(1.5, 0.5), vec![30.0, 80.0, 120.0]),
        (
            "rough water 0.3, inverted".into(),
            dielectric(1.0 / 1.33, 0.3),
            vec![40.0, 150.0],
        ),
        (
            "smooth plastic".into(),
            Material::plastic(grey(0.5), grey(1.0), 1.5, None),
            vec![0.0, 70.0],
        ),
        (
            "rough plastic 0.3".into(),
            Material::plastic(grey(0.5), grey(1.0), 1.5, rough(0.3)),
            vec![20.0, 75.0],
        ),
        (
            "coated diffuse, smooth coating".into(),
            Material::Coated(Coated::default()),
            vec![0.0, 60.0, 150.0],
        ),
        (
            "coated diffuse, rough coating 0.3, scattering medium".into(),
            Material::Coated(Coated {
                roughness: rough(0.3),
                thickness: 0.3,
                albedo: grey(0.8),
                g: 0.4,
                ..Coated::default()
            }),
            vec![20.0, 75.0],
        ),
        (
            "coated rough gold 0.2 under a rough coating 0.1".into(),
            Material::Coated(Coated {
                base: CoatedBase::Conductor {
                    fresnel: MetalFresnel::Complex { eta: au_eta, k: au_k },
                    specular: grey(1.0),
                    roughness: rough(0.2),
                },
                roughness: rough(0.1),
                ..Coated::default()
            }),
            vec![10.0, 65.0],
        ),
        (
            "blend diffuse / rough gold".into(),
            Material::Blend {
                a: Box::new(Material::Diffuse(DiffuseMaterial { reflectance: grey(0.8) })),
                b: Box::new(conductor(0.3, 0.3)),
                weight: grey(0.4),
            },
            vec![0.0, 60.0],
        ),
    ]
}

const MODE: TransportMode = TransportMode::Radiance;

#[test]
fn sampling_fits_the_density_for_every_bsdf() {
    let cases = cases();
    let tests: usize = cases
        .iter()
        .filter(|c| !c.1.bsdf(Vec2::ZERO).stochastic())
        .map(|c| c.2.len())
        .sum();
    let mut seed = 0;
    for (name, material, views) in &cases {
        let bsdf = material.bsdf(Vec2::ZERO);
        if bsdf.stochastic() {
            // Its density is an estimate, not the sampling's own: see
            // `stochastic_sampling_agrees_with_eval`.
            continue;
        }
        for &theta in views {
            seed += 1;
            let wo = view(theta);
            let mut lobe = Uniforms::new(1000 + seed);
            let r = chi2_directions(
                seed,
                400_000,
                |u| {
                    bsdf.sample(wo, lobe.next_f32(), u, MODE)
                        .filter(|s| !s.delta)
                        .map(|s| s.wi)
                },
                |wi| bsdf.pdf(wo, wi, MODE),
            );
            r.assert_fits(&format!("{name} seen from {theta} degrees"), tests);
            assert!(r.integral <= 1.0 + 2e-3, "{name} at {theta}: {}", r.describe());
        }
    }
}

#[test]
fn sample_weights_are_f_cos_over_pdf() {
    for (name, material, views) in cases() {
        let bsdf = material.bsdf(Vec2::ZERO);
        if bsdf.stochastic() {
            continue;
        }
        for theta in views {
            let wo = view(theta);
            let mut u = Uniforms::new(7);
            for _ in 0..2000 {
                let Some(s) = bsdf.sample(wo, u.next_f32(), u.next_vec2(), MODE) else {
                    continue;
                };
                if s.delta {
                    continue;
                }
                let pdf = bsdf.pdf(wo, s.wi, MODE);
                let want = bsdf.eval(wo, s.wi, MODE) * (s.wi.z.abs() / pdf);
                assert!(
                    (s.pdf - pdf).abs() <= 2e-3 * pdf,
                    "{name} at {theta}: pdf {} vs {pdf}",
                    s.pdf
                );
                for (a, b) in [(s.weight.r, want.r), (s.weight.g, want.g), (s.weight.b, want.b)] {
                    assert!(
                        (a - b).abs() <= 2e-3 * b.max(1e-3),
                        "{name} at {theta}: weight {a} vs {b}"
                    );
                }
            }
        }
    }
}

/// The directional albedo E[weight] (red channel) from `wo`, with its standard error.
fn albedo(bsdf: &Bsdf, wo: Vec3, mode: TransportMode, n: usize, seed: u64) -> (f64, f64) {
    let mut u = Uniforms::new(seed);
    let mut m = MeanEstimate::default();
    for _ in 0..n {
        let w = bsdf
            .sample(wo, u.next_f32(), u.next_vec2(), mode)
            .map_or(0.0, |s| s.weight.r);
        m.push(w as f64);
    }
    (m.mean(), m.standard_error())
}

#[test]
fn lossless_materials_pass_the_furnace() {
    // Albedo-1 diffuse, smooth glass (importance: no 1/η² scaling), smooth plastic of white
    // base and coating (Mitsuba's model keeps all the energy: (1 - F_o) for the base, F_o for
    // the coating, by the identity 1 - F_dr,int = (1 - F_dr,ext)/η²), a blend of them, a
    // perfect Phong lobe at normal incidence: each returns 1 within 3 standard errors.
    let lossless = [
        (
            "white diffuse",
            Material::Diffuse(DiffuseMaterial { reflectance: grey(1.0) }),
            vec![0.0, 45.0, 85.0],
        ),
        (
            "smooth glass",
            Material::Dielectric(DielectricMaterial {
                eta: 1.5,
                reflectance: grey(1.0),
                transmittance: grey(1.0),
                roughness: None,
            }),
            vec![0.0, 60.0, 89.0, 120.0, 175.0],
        ),
        (
            "white smooth plastic",
            Material::plastic(grey(1.0), grey(1.0), 1.5, None),
            vec![0.0, 45.0, 80.0],
        ),
        (
            "blend",
            Material::Blend {
                a: Box::new(Material::Diffuse(DiffuseMaterial { reflectance: grey(1.0) })),
                b: Box::new(Material::plastic(grey(1.0), grey(1.0), 1.33, None)),
                weight: grey(0.5),
            },
            vec![10.0, 70.0],
        ),
    ];
    for (name, material, views) in lossless {
        let bsdf = material.bsdf(Vec2::ZERO);
        for theta in views {
            let (mean, se) = albedo(&bsdf, view(theta), TransportMode::Importance, 100_000, 3);
            assert_within_3se(&format!("{name} from {theta} degrees"), mean, se, 1.0, 1e-4);
        }
    }
    let phong = crate::materials::Phong {
        diffuse: grey(0.0),
        specular: Rgb::WHITE,
        exponent: 20.0,
        ..Default::default()
    }
    .bsdf(Vec2::ZERO);
    let (mean, se) = albedo(&Bsdf::one_sided(BsdfKind::Phong(phong)), Vec3::Z, MODE, 100_000, 4);
    assert_within_3se("Phong lobe at normal incidence", mean, se, 1.0, 1e-3);
}

#[test]
fn rough_surfaces_lose_energy_but_never_gain_it() {
    // A conductor reflecting everything (k huge: F = 1) and rough glass (importance mode):
    // single-scattering microfacets lose the light that would bounce between facets, more
    // with roughness and at grazing views, never gain; smooth-ish ones lose almost none.
    let mirror_metal = |alpha: f32| {
        Material::Conductor(ConductorMaterial {
            fresnel: MetalFresnel::Complex {
                eta: Rgb::splat(1.0),
                k: Rgb::splat(1e4),
            },
            specular: grey(1.0),
            roughness: rough(alpha),
        })
    };
    let glass = |alpha: f32| {
        Material::Dielectric(DielectricMaterial {
            eta: 1.5,
            reflectance: grey(1.0),
            transmittance: grey(1.0),
            roughness: rough(alpha),
        })
    };
    let plastic = |alpha: f32| Material::plastic(grey(1.0), grey(1.0), 1.5, rough(alpha));
    let mut seed = 10;
    for (name, make) in [
        ("conductor", &mirror_metal as &dyn Fn(f32) -> Material),
        ("glass", &glass),
        ("plastic", &plastic),
    ] {
        for alpha in [0.02, 0.1, 0.3, 0.6, 1.0] {
            let material = make(alpha);
            let bsdf = material.bsdf(Vec2::ZERO);
            for theta in [0.0, 40.0, 70.0, 85.0] {
                seed += 1;
                let (mean, se) = albedo(&bsdf, view(theta), TransportMode::Importance, 40_000, seed);
                assert!(
                    mean <= 1.0 + 3.0 * se + 1e-4,
                    "{name} alpha {alpha} at {theta}: albedo {mean} +- {se} gains energy"
                );
                // (Not plastic: its base under a rough coating loses more, as Mitsuba's
                // does; `rough_plastic_albedo_is_mitsubas` checks how much.)
                if alpha <= 0.1 && theta <= 40.0 && name != "plastic" {
                    assert!(
                        mean > 0.97,
                        "{name} alpha {alpha} at {theta}: albedo {mean} loses too much"
                    );
                }
            }
        }
    }
}

#[test]
fn smooth_conductor_reflects_the_fresnel_colour_of_gold() {
    // At normal incidence F = ((η-1)² + k²)/((η+1)² + k²) per channel.
    let (eta, k) = metal_ior("Au").unwrap();
    let gold = Material::Conductor(ConductorMaterial {
        fresnel: MetalFresnel::Complex { eta, k },
        specular: grey(1.0),
        roughness: None,
    });
    let s = gold
        .bsdf(Vec2::ZERO)
        .sample(Vec3::Z, 0.5, Vec2::splat(0.5), MODE)
        .unwrap();
    assert!(s.delta && (s.wi - Vec3::Z).length() < 1e-6);
    let want = |e: f32, k: f32| ((e - 1.0).powi(2) + k * k) / ((e + 1.0).powi(2) + k * k);
    assert!((s.weight.r - want(eta.r, k.r)).abs() < 1e-4, "{:?}", s.weight);
    assert!((s.weight.b - want(eta.b, k.b)).abs() < 1e-4, "{:?}", s.weight);
    assert!(
        s.weight.r > s.weight.g && s.weight.g > s.weight.b,
        "gold is yellow: {:?}",
        s.weight
    );
}

#[test]
fn one_sided_materials_are_black_from_behind() {
    let diffuse = Material::Diffuse(DiffuseMaterial { reflectance: grey(0.5) });
    let below = Vec3::new(0.3, 0.0, -0.9).normalize();
    let b = diffuse.bsdf(Vec2::ZERO);
    assert!(b.sample(below, 0.5, Vec2::splat(0.3), MODE).is_none());
    assert_eq!(b.eval(below, -Vec3::Z, MODE), Rgb::BLACK);
    let two = Material::TwoSided(Box::new(diffuse));
    let b = two.bsdf(Vec2::ZERO);
    let s = b.sample(below, 0.5, Vec2::splat(0.3), MODE).unwrap();
    assert!(s.wi.z < 0.0 && (s.weight.r - 0.5).abs() < 1e-6);
}

#[test]
fn ggx_normals_integrate_to_the_projected_area() {
    // ∫ D(m) cos θm dm = 1, and the visible normals' density integrates to 1, by midpoint
    // quadrature over the hemisphere in (cos θ, φ).
    for (ax, ay) in [(0.1, 0.1), (0.5, 0.5), (0.2, 0.8), (1.0, 1.0)] {
        let g = Ggx::new(ax, ay).unwrap();
        let wo = view(50.0);
        let (nz, nphi) = (2000, 400);
        let (mut projected, mut visible) = (0.0f64, 0.0f64);
        for i in 0..nz {
            // Cells denser near the pole, where the lobe peaks: z = 1 - t².
            let (t0, t1) = (i as f64 / nz as f64, (i + 1) as f64 / nz as f64);
            let (z0, z1) = (1.0 - t0 * t0, 1.0 - t1 * t1);
            let z = 0.5 * (z0 + z1);
            let r = (1.0 - z * z).sqrt();
            for j in 0..nphi {
                let phi = (j as f64 + 0.5) / nphi as f64 * std::f64::consts::TAU;
                let m = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                let cell = (z0 - z1) * std::f64::consts::TAU / nphi as f64;
                projected += (g.d(m) * m.z) as f64 * cell;
                visible += g.visible_pdf(wo, m) as f64 * cell;
            }
        }
        assert!((projected - 1.0).abs() < 5e-3, "alpha {ax} x {ay}: {projected}");
        assert!((visible - 1.0).abs() < 5e-3, "alpha {ax} x {ay}: {visible}");
    }
}

#[test]
fn blends_merge_their_specular_rays() {
    // Two Phong glasses (three rays each: mirror, Fresnel reflection, refraction) blended:
    // the rays along the same directions merge and keep the total weight.
    let glass = |mirror: f32| {
        Material::Phong(crate::materials::Phong {
            diffuse: grey(0.0),
            mirror: Rgb::splat(mirror),
            transmission: Rgb::splat(0.5),
            ..Default::default()
        })
    };
    let single = glass(0.2).bsdf(Vec2::ZERO).specular_rays(view(30.0), MODE);
    let blend = Material::Blend {
        a: Box::new(glass(0.2)),
        b: Box::new(glass(0.2)),
        weight: grey(0.5),
    };
    let merged = blend.bsdf(Vec2::ZERO).specular_rays(view(30.0), MODE);
    assert_eq!(merged.as_slice().len(), 2, "reflection and refraction");
    let total = |r: &SpecularRays| r.as_slice().iter().fold(Rgb::BLACK, |a, r| a + r.weight);
    let (a, b) = (total(&single), total(&merged));
    assert!((a.r - b.r).abs() < 1e-6, "{a:?} vs {b:?}");
}

/// A balanced tree of blends over `leaves` (equal weights at every level).
fn blend_tree(leaves: &[Material]) -> Material {
    match leaves {
        [one] => one.clone(),
        _ => {
            let (a, b) = leaves.split_at(leaves.len() / 2);
            Material::Blend {
                a: Box::new(blend_tree(a)),
                b: Box::new(blend_tree(b)),
                weight: grey(b.len() as f32 / leaves.len() as f32),
            }
        }
    }
}

fn glasses(n: usize) -> Vec<Material> {
    (0..n)
        .map(|k| {
            Material::Dielectric(DielectricMaterial {
                eta: 1.3 + 0.1 * k as f32,
                reflectance: grey(1.0),
                transmittance: grey(1.0),
                roughness: None,
            })
        })
        .collect()
}

#[test]
fn a_blend_of_eight_glasses_keeps_every_specular_ray() {
    // One shared reflection (its Fresnel weights summed) and eight refractions: nine
    // distinct directions, all kept; the weights add up to the mixture's, each glass
    // being lossless for radiance up to its 1/eta^2 (checked against the parts).
    let parts = glasses(8);
    let tree = blend_tree(&parts);
    let rays = tree.bsdf(Vec2::ZERO).specular_rays(view(30.0), MODE);
    assert_eq!(rays.as_slice().len(), 9);
    assert_eq!(rays.dropped(), 0.0);
    let total = |r: &SpecularRays| r.as_slice().iter().fold(Rgb::BLACK, |a, r| a + r.weight);
    let expected = parts.iter().fold(Rgb::BLACK, |a, m| {
        a + total(&m.bsdf(Vec2::ZERO).specular_rays(view(30.0), MODE)) * (1.0 / 8.0)
    });
    let got = total(&rays);
    assert!((got.r - expected.r).abs() < 1e-5, "{got:?} vs {expected:?}");
}

#[test]
fn more_specular_rays_than_room_drop_the_weakest_and_say_so() {
    // Twenty glasses: 21 distinct directions for 16 places. The kept rays are the
    // strongest ones and the dropped weight is what is missing from the total.
    let parts = glasses(20);
    let rays = blend_tree(&parts).bsdf(Vec2::ZERO).specular_rays(view(30.0), MODE);
    assert_eq!(rays.as_slice().len(), MAX_SPECULAR_RAYS);
    assert!(rays.dropped() > 0.0);
    let mut all: Vec<f32> = parts
        .iter()
        .flat_map(|m| {
            let r = m.bsdf(Vec2::ZERO).specular_rays(view(30.0), MODE);
            r.as_slice()
                .iter()
                .skip(1)
                .map(|r| r.weight.max_component())
                .collect::<Vec<_>>()
        })
        .collect();
    all.sort_by(f32::total_cmp);
    // The 20 refractions each weigh 1/20 of a glass's; the dropped ones are the five
    // weakest refractions (the reflection, merged, outweighs them all).
    let weakest: f32 = all[..5].iter().sum::<f32>() / 20.0;
    assert!(
        (rays.dropped() - weakest).abs() < 1e-5,
        "dropped {} vs the five weakest {weakest}",
        rays.dropped()
    );
}

/// A white rough plastic's albedo is Mitsuba 3's `roughplastic`'s (GGX, default indices
/// 1.49 / 1.000277, white base), measured with Mitsuba's own `sample` (100,000 draws each,
/// scalar_rgb; standard errors about 0.002). Allowed: 0.015, our 40,000-draw standard error
/// (below 0.001) and Mitsuba's, plus the two quadratures of the coating's tables (Mitsuba's
/// Gauss-Legendre, our midpoint rule); seen: within 0.009 everywhere.
#[test]
fn rough_plastic_albedo_is_mitsubas() {
    let eta = 1.49 / 1.000277;
    let mitsuba = [
        (0.1, [(0.0, 0.910), (40.0, 0.909), (70.0, 0.904)]),
        (0.15, [(0.0, 0.854), (40.0, 0.852), (70.0, 0.839)]),
        (0.3, [(0.0, 0.695), (40.0, 0.688), (70.0, 0.660)]),
    ];
    let mut seed = 70;
    for (alpha, rows) in mitsuba {
        let material = Material::plastic(grey(1.0), grey(1.0), eta, rough(alpha));
        let bsdf = material.bsdf(Vec2::ZERO);
        for (theta, want) in rows {
            seed += 1;
            let (mean, se) = albedo(&bsdf, view(theta), TransportMode::Importance, 40_000, seed);
            println!("alpha {alpha} at {theta}: {mean:.4} +- {se:.4}, Mitsuba's {want}");
            assert!(
                (mean - want).abs() < 0.015,
                "alpha {alpha} at {theta}: albedo {mean} +- {se}, Mitsuba's {want}"
            );
        }
    }
}
