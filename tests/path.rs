//! The path tracer against closed forms.
//!
//! Furnace: a camera inside a closed sphere whose inside emits radiance Le and reflects
//! diffusely with albedo ρ sees L = Le (1 + ρ + ... + ρ^(D-1)) = Le (1 - ρ^D) / (1 - ρ) when
//! paths have at most D segments (Mitsuba's `max_depth`): every bounce adds one more
//! reflection of the same emission. Next-event estimation, MIS and Russian roulette must
//! leave the mean unchanged.

use penumbra::math::{PixelSampler, Ray, SamplerKind, UVec2, Vec2, Vec3};
use penumbra::renderer::integrators::{IntegratorKind, IntegratorOptions};
use penumbra::renderer::{RayCounts, Scene};
use penumbra::scene::{build_scene, SourceFile};
use penumbra_testkit::{assert_within_3se, MeanEstimate};

fn furnace(albedo: f32) -> Scene {
    furnace_with(albedo, "")
}

/// [`furnace`] with more shapes inside (`extra`, native-format text).
fn furnace_with(albedo: f32, extra: &str) -> Scene {
    let text = format!(
        "[[material]]\nname = \"wall\"\ndiffuse = {albedo}\n\n\
         [[shape]]\ntype = \"sphere\"\nradius = 2\nmaterial = \"wall\"\nemission = 1\ntwo_sided = true\n{extra}"
    );
    let desc = penumbra::scene::formats::native::read(&SourceFile::new("furnace.toml", text)).unwrap();
    build_scene(&desc).unwrap()
}

/// Mean and standard error of `n` path-traced estimates from points inside the sphere.
fn estimate(scene: &Scene, max_depth: u32, n: u32) -> (f64, f64) {
    let options = IntegratorOptions {
        max_depth,
        ..IntegratorOptions::default()
    };
    let (mean, se, _) = estimate_with(scene, options, n);
    (mean, se)
}

/// [`estimate`] with any options; also the rays traced.
fn estimate_with(scene: &Scene, options: IntegratorOptions, n: u32) -> (f64, f64, RayCounts) {
    let integrator = IntegratorKind::Path.create(options);
    let mut sampler = PixelSampler::new(SamplerKind::Independent, 11, n);
    let mut counts = RayCounts::default();
    let mut m = MeanEstimate::default();
    for i in 0..n {
        sampler.start(UVec2::new(i % 1009, i / 1009), i);
        // Rays from off-centre points in varied directions.
        let (a, b) = (i as f32 * 0.618_034, i as f32 * 0.414_214);
        let origin = Vec3::new(a.sin(), b.cos(), (a + b).sin()) * 0.8;
        let dir = Vec3::new((3.0 * a).cos(), (5.0 * b).sin(), (7.0 * a).sin() + 0.1);
        m.push(
            integrator
                .li(
                    scene,
                    &Ray::new(origin, dir),
                    &mut sampler,
                    &mut counts,
                    &mut Vec::new(),
                )
                .r as f64,
        );
    }
    (m.mean(), m.standard_error(), counts)
}

#[test]
fn furnace_sphere_gives_the_geometric_series_for_every_max_depth() {
    for albedo in [0.5f32, 0.9] {
        let scene = furnace(albedo);
        for depth in [1u32, 2, 3, 5, 8, 40] {
            let rho = albedo as f64;
            let expected = (1.0 - rho.powi(depth as i32)) / (1.0 - rho);
            let (mean, se) = estimate(&scene, depth, 20_000);
            println!("albedo {albedo}, max depth {depth}: {mean:.5} +- {se:.5}, expected {expected:.5}");
            if depth <= 2 {
                // Emission only, then emission + one reflection: NEE and MIS, no roulette.
                assert_within_3se(&format!("depth {depth}"), mean, se, expected, 1e-4);
            } else {
                assert!(se > 0.0 && se < 0.01 * expected, "depth {depth}: standard error {se}");
                let what = format!("albedo {albedo}, depth {depth}");
                assert_within_3se(&what, mean, se, expected, 1e-4 * expected);
            }
        }
    }
}

/// Russian roulette from any depth leaves the mean unchanged and cuts work: at albedo 0.9
/// and up to 40 segments (expected 9.85), roulette from depth 1, 2 and 5 and none at all
/// (`rr_depth` = `max_depth`: every path then gives the series exactly) all give the series
/// within 3 standard errors (about 0.35% of it at 50,000 paths with roulette), and the
/// earlier roulette starts, the fewer rays.
#[test]
fn russian_roulette_from_any_depth_keeps_the_furnace_sum() {
    let scene = furnace(0.9);
    let expected = (1.0 - 0.9f64.powi(40)) / (1.0 - 0.9);
    const N: u32 = 50_000;
    let mut rays = Vec::new();
    for rr_depth in [1u32, 2, 5, 40] {
        let options = IntegratorOptions {
            max_depth: 40,
            rr_depth,
            ..IntegratorOptions::default()
        };
        let (mean, se, counts) = estimate_with(&scene, options, N);
        println!("rr_depth {rr_depth}: {mean:.4} +- {se:.4} (expected {expected:.4}), {counts:?}");
        assert!(se < 0.01 * expected, "rr_depth {rr_depth}: standard error {se}");
        assert_within_3se(&format!("rr_depth {rr_depth}"), mean, se, expected, 1e-4 * expected);
        rays.push(counts.secondary);
    }
    assert!(
        rays.windows(2).all(|w| w[0] < w[1]),
        "secondary rays by rr_depth: {rays:?}"
    );
}

/// The path tracer treats `light_selection = "all"` as selection by power (one shadow ray
/// per vertex), with consistent MIS weights: the furnace still sums to the series. A second,
/// small emitting sphere of the same emission and albedo inside makes the two lights'
/// probabilities differ between selections (by power, 1:100 or so; within each light
/// object, 1), which is what broke the weights before.
#[test]
fn furnace_with_every_light_selection() {
    use penumbra::renderer::lights::LightSelection;
    let scene = furnace_with(
        0.5,
        "\n[[shape]]\ntype = \"sphere\"\ncenter = [0, -1.5, 0]\nradius = 0.3\nmaterial = \"wall\"\nemission = 1\n",
    );
    for selection in [LightSelection::All, LightSelection::Uniform, LightSelection::Power] {
        let integrator = IntegratorKind::Path.create(IntegratorOptions {
            max_depth: 3,
            direct: penumbra::renderer::integrators::DirectOptions {
                selection,
                ..Default::default()
            },
            ..IntegratorOptions::default()
        });
        let mut sampler = PixelSampler::new(SamplerKind::Independent, 13, 1);
        let mut counts = RayCounts::default();
        let mut m = MeanEstimate::default();
        for i in 0..20_000u32 {
            sampler.start(UVec2::new(i, 2), 0);
            let (a, b) = (i as f32 * 0.618_034, i as f32 * 0.414_214);
            let origin = Vec3::new(a.sin(), b.cos(), (a + b).sin()) * 0.8;
            let dir = Vec3::new((3.0 * a).cos(), (5.0 * b).sin(), (7.0 * a).sin() + 0.1);
            m.push(
                integrator
                    .li(
                        &scene,
                        &Ray::new(origin, dir),
                        &mut sampler,
                        &mut counts,
                        &mut Vec::new(),
                    )
                    .r as f64,
            );
        }
        assert_within_3se(&format!("{selection:?}"), m.mean(), m.standard_error(), 1.75, 1e-4);
    }
}

/// Direct lighting inside the furnace is 1 + ρ for every strategy, also for shading points
/// on the emitting sphere hit obliquely (where rounding once made the sphere's cone sampling
/// treat the point as outside: solid-angle sampling then lost 12% of the light).
#[test]
fn direct_strategies_inside_the_furnace_give_one_bounce() {
    use penumbra::renderer::integrators::{DirectOptions, LightSampling};
    let scene = furnace(0.5);
    for s in [
        LightSampling::Uniform,
        LightSampling::SolidAngle,
        LightSampling::Bsdf,
        LightSampling::Mis,
    ] {
        let integrator = IntegratorKind::Direct.create(IntegratorOptions {
            direct: DirectOptions {
                sampling: s,
                ..DirectOptions::default()
            },
            ..IntegratorOptions::default()
        });
        let mut sampler = PixelSampler::new(SamplerKind::Independent, 11, 1);
        let mut counts = RayCounts::default();
        let n = 10_000;
        for (o, d) in [
            (Vec3::ZERO, Vec3::new(0.3, 0.4, 0.5)),
            (Vec3::new(1.2, 0.0, 0.0), Vec3::Y),
        ] {
            let mut m = MeanEstimate::default();
            for i in 0..n {
                sampler.start(UVec2::new(i % 1009, i / 1009), i);
                m.push(
                    integrator
                        .li(&scene, &Ray::new(o, d), &mut sampler, &mut counts, &mut Vec::new())
                        .r as f64,
                );
            }
            let (mean, se) = (m.mean(), m.standard_error());
            assert_within_3se(&format!("{s:?} from {o}"), mean, se, 1.5, 1e-4);
        }
    }
}

/// The back of a one-sided emitting mesh, lit by nothing else, is black from every point:
/// a hit point that rounding puts on the emitting side must not see its own light (it once
/// did, at full strength, which biased Mitsuba's Cornell box near its light).
#[test]
fn the_back_of_a_one_sided_light_is_black_everywhere() {
    let text = "[[material]]\nname = \"white\"\ndiffuse = 0.9\n\n\
                [[shape]]\ntype = \"mesh\"\nmaterial = \"white\"\nemission = 10\n\
                positions = [[-0.23, 0.99, -0.18], [0.23, 0.99, -0.18], [-0.23, 0.99, 0.2], [0.23, 0.99, 0.2]]\n\
                indices = [[1, 2, 0], [1, 3, 2]]\n";
    let desc = penumbra::scene::formats::native::read(&SourceFile::new("back.toml", text.into())).unwrap();
    let scene = build_scene(&desc).unwrap();
    for kind in [IntegratorKind::Path, IntegratorKind::Direct, IntegratorKind::Whitted] {
        let integrator = kind.create(IntegratorOptions {
            max_depth: 3,
            ..IntegratorOptions::default()
        });
        let mut sampler = PixelSampler::new(SamplerKind::Independent, 5, 1);
        let mut counts = RayCounts::default();
        for i in 0..20_000u32 {
            sampler.start(UVec2::new(i, 0), 0);
            // Rays from above onto the light's back, at points spread over it.
            let (a, b) = ((i as f32 * 0.618_034).fract(), (i as f32 * 0.414_214).fract());
            let target = Vec3::new(-0.23 + 0.46 * a, 0.99, -0.18 + 0.38 * b);
            let origin = Vec3::new(0.1, 1.5, 0.05);
            let l = integrator.li(
                &scene,
                &Ray::new(origin, target - origin),
                &mut sampler,
                &mut counts,
                &mut Vec::new(),
            );
            assert_eq!(l, penumbra::math::Rgb::BLACK, "{kind:?}: ray {i} to {target}");
        }
    }
}

/// Glass in a furnace: inside a closed sphere that emits radiance 1 everywhere (and reflects
/// nothing), a clear glass ball (index 1.5) must look exactly as bright as its surroundings
/// (radiance is conserved through lossless interfaces: the 1/η² of entering and the η² of
/// leaving cancel). Tests the Fresnel split, the radiance scaling and the path tracer's
/// choice among specular rays.
fn ball_in_furnace(material: &str, max_depth: u32, n: u32) -> (f64, f64) {
    // Materials a blend refers to are defined before the ball's.
    let parts = "[[material]]\nname = \"glass\"\ntype = \"dielectric\"\n\n\
                 [[material]]\nname = \"white\"\ntype = \"diffuse\"\nreflectance = 1\n\n";
    let text = format!(
        "{parts}[[material]]\nname = \"black\"\ndiffuse = 0\n\n\
         [[material]]\nname = \"ball\"\n{material}\n\n\
         [[shape]]\ntype = \"sphere\"\nradius = 3\nmaterial = \"black\"\nemission = 1\ntwo_sided = true\n\n\
         [[shape]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"ball\"\n"
    );
    let desc = penumbra::scene::formats::native::read(&SourceFile::new("ball.toml", text)).unwrap();
    let scene = build_scene(&desc).unwrap();
    let integrator = IntegratorKind::Path.create(IntegratorOptions {
        max_depth,
        ..IntegratorOptions::default()
    });
    let mut sampler = PixelSampler::new(SamplerKind::Independent, 3, 1);
    let mut counts = RayCounts::default();
    let mut m = MeanEstimate::default();
    for i in 0..n {
        sampler.start(UVec2::new(i, 0), 0);
        // From outside the ball towards points spread over its visible face.
        let (a, b) = (
            (i as f32 * 0.618_034).fract() - 0.5,
            (i as f32 * 0.414_214).fract() - 0.5,
        );
        let origin = Vec3::new(0.0, 0.0, 2.5);
        let dir = Vec3::new(1.6 * a, 1.6 * b, -2.5);
        m.push(
            integrator
                .li(
                    &scene,
                    &Ray::new(origin, dir),
                    &mut sampler,
                    &mut counts,
                    &mut Vec::new(),
                )
                .r as f64,
        );
    }
    (m.mean(), m.standard_error())
}

/// Glass in a furnace: inside a closed sphere that emits radiance 1 everywhere (and reflects
/// nothing), a clear glass ball (index 1.5) must look exactly as bright as its surroundings
/// (radiance is conserved through lossless interfaces: the 1/η² of entering and the η² of
/// leaving cancel). Likewise every lossless material: white diffuse, white smooth plastic
/// (Mitsuba's model keeps all the energy), a blend of them, glass as the `phong` material's
/// transmission. Tests the Fresnel splits, the radiance scaling, the BSDFs' lobe choices and
/// the path tracer's MIS over them.
#[test]
fn lossless_balls_vanish_in_a_furnace() {
    for (what, material) in penumbra_testkit::furnace::LOSSLESS_BALLS {
        let (mean, se) = ball_in_furnace(material, 40, 20_000);
        println!("{what}: {mean:.5} +- {se:.5}");
        assert_within_3se(what, mean, se, 1.0, 1e-3);
    }
}

/// Rough metal and rough glass balls in the furnace: darker than the surroundings (single
/// scattering loses energy), never brighter; smoother ones closer to 1. (Single-scattering
/// GGX loses much: 31% at normal incidence for α = 0.5, by quadrature of D G2 cos θm.)
#[test]
fn rough_balls_lose_energy_in_a_furnace() {
    for (what, material, at_least) in penumbra_testkit::furnace::ROUGH_BALLS {
        let (mean, se) = ball_in_furnace(material, 40, 20_000);
        println!("{what}: {mean:.5} +- {se:.5}");
        assert!(mean <= 1.0 + 3.0 * se + 1e-3, "{what} gains energy: {mean} +- {se}");
        assert!(mean >= at_least, "{what} loses too much: {mean} +- {se}");
    }
}

/// Mean and standard error of the red radiance of `n` camera rays of a path-traced `scene`
/// from `origin` towards points spread over a square of side `spread` around `target`.
fn estimate_towards(scene: &Scene, origin: Vec3, target: Vec3, spread: f32, n: u32) -> (f64, f64) {
    let integrator = IntegratorKind::Path.create(IntegratorOptions {
        max_depth: 40,
        ..IntegratorOptions::default()
    });
    let mut sampler = PixelSampler::new(SamplerKind::Independent, 5, 1);
    let mut counts = RayCounts::default();
    let mut m = MeanEstimate::default();
    for i in 0..n {
        sampler.start(UVec2::new(i, 1), 0);
        let (a, b) = (
            (i as f32 * 0.618_034).fract() - 0.5,
            (i as f32 * 0.414_214).fract() - 0.5,
        );
        let dir = target + Vec3::new(spread * a, 0.0, spread * b) - origin;
        m.push(
            integrator
                .li(
                    scene,
                    &Ray::new(origin, dir),
                    &mut sampler,
                    &mut counts,
                    &mut Vec::new(),
                )
                .r as f64,
        );
    }
    (m.mean(), m.standard_error())
}

fn scene_from(text: &str) -> Scene {
    let desc = penumbra::scene::formats::native::read(&SourceFile::new("env.toml", text.to_string())).unwrap();
    build_scene(&desc).unwrap()
}

/// Furnace with an environment light: a white diffuse ball, white plastic, glass, under a
/// uniform environment of radiance 1, look exactly like their surroundings: within 3
/// standard errors and 0.5%. The environment is sampled as a light and reached by BSDF
/// samples, the two weighted by MIS.
#[test]
fn objects_vanish_in_a_uniform_environment() {
    for (what, material) in [
        ("white diffuse", "type = \"diffuse\"\nreflectance = 1"),
        ("white plastic", "type = \"plastic\"\ndiffuse = 1"),
        ("glass", "type = \"dielectric\""),
    ] {
        let scene = scene_from(&format!(
            "[environment]\nradiance = 1\n\n[[material]]\nname = \"m\"\n{material}\n\n\
             [[shape]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"m\"\n"
        ));
        let (mean, se) = estimate_towards(&scene, Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO, 1.2, 20_000);
        println!("{what} in a uniform environment: {mean:.5} +- {se:.5}");
        assert_within_3se(what, mean, se, 1.0, 1e-4);
        assert!((mean - 1.0).abs() < 0.005, "{what}: {mean}");
    }
}

/// An image environment, importance sampled: the upper half of the map is 2, the lower 0.5.
/// A white one-sided disk facing up reflects exactly the upper hemisphere: 2; the map turned
/// upside down by its transform: 0.5.
#[test]
fn a_disk_reflects_the_half_of_the_environment_map_above_it() {
    let dir = tempfile::tempdir().unwrap();
    let (width, height) = (32u32, 16u32);
    let pixels: Vec<penumbra::math::Rgb> = (0..width * height)
        .map(|i| penumbra::math::Rgb::splat(if i / width < height / 2 { 2.0 } else { 0.5 }))
        .collect();
    let path = dir.path().join("sky.pfm");
    let image = penumbra::scene::image_io::Image {
        width,
        height,
        pixels: &pixels,
    };
    penumbra::scene::image_io::write_image(&path, &image, 0.0).unwrap();
    for (transform, expected) in [("", 2.0), ("transform = { rotate = 180, axis = [1, 0, 0] }\n", 0.5)] {
        let scene = scene_from(&format!(
            "[environment]\nfile = \"{}\"\n{transform}\n\
             [[material]]\nname = \"m\"\ntype = \"diffuse\"\nreflectance = 1\ntwo_sided = false\n\n\
             [[shape]]\ntype = \"disk\"\ncenter = [0, 0, 0]\nnormal = [0, 1, 0]\nradius = 1\nmaterial = \"m\"\n",
            path.display()
        ));
        let (mean, se) = estimate_towards(&scene, Vec3::new(0.3, 2.0, 0.1), Vec3::ZERO, 1.0, 20_000);
        println!("disk under the map {transform:?}: {mean:.5} +- {se:.5}");
        assert_within_3se(&format!("disk {transform}"), mean, se, expected, 1e-4);
    }
}

/// Paths at plain Lambertian surfaces take their bounce eight at a time
/// (`integrators/diffuse_lanes.rs`), in lanes that must give each path exactly what the
/// one-path-at-a-time code gives it: the same films, bit for bit, with the lanes on and
/// off. The scenes reach every branch: triangle lights sampled by area and (close up) by
/// solid angle in the scalar code, quad and sphere lights (scalar light samples beside
/// lane continuations), each with the Sobol and the independent sampler (the Sobol one
/// has lanes of its own), one- and two-sided diffuse seen from both sides, meshes with and
/// without vertex normals and UVs (normals against the winding too), glossy and glass
/// neighbours (paths leaving the lanes and coming back), Russian roulette from depth 1,
/// environments, whose light samples the lanes take (the mixed scene under a constant and
/// under an image map, beside lights of every other kind; glossy-env, whose quad floor
/// is not a mesh, for the other shading points' samples in lanes), a textured mesh (a
/// checker whose black checks take the one-path bounce).
#[test]
fn diffuse_lanes_equal_the_scalar_bounce() {
    use penumbra::renderer::integrators::PathTracer;
    use penumbra::renderer::Integrator;
    use penumbra::renderer::{render, Film, RenderOptions};
    let mixed = "[render]\nintegrator = \"path\"\nmax_depth = 7\nrr_depth = 1\n\
        [camera]\nposition = [0, 1.2, 4]\ntarget = [0, 0.6, 0]\nfov = 50\n\
        [[material]]\nname = \"front\"\ntype = \"diffuse\"\nreflectance = [0.7, 0.6, 0.5]\ntwo_sided = false\n\
        [[material]]\nname = \"both\"\ntype = \"diffuse\"\nreflectance = [0.3, 0.8, 0.4]\n\
        [[material]]\nname = \"glass\"\ntype = \"dielectric\"\nior = 1.5\n\
        [[material]]\nname = \"checks\"\ntype = \"diffuse\"\n\
        reflectance = { type = \"checker\", even = [0.6, 0.5, 0.2], odd = [0, 0, 0], size = 0.25 }\n\
        [[shape]]\ntype = \"quad\"\ncorner = [-3, 0, 3]\nedge1 = [6, 0, 0]\nedge2 = [0, 0, -6]\nmaterial = \"front\"\n\
        [[shape]]\ntype = \"quad\"\ncorner = [-3, 0, -1]\nedge1 = [0, 3, 0]\nedge2 = [6, 0, 0]\nmaterial = \"front\"\n\
        [[shape]]\ntype = \"mesh\"\nmaterial = \"both\"\npositions = [[-1, 0, 0], [0, 1.5, 0.5], [1, 0, 0]]\nindices = [[0, 1, 2]]\n\
        normals = [[0, 0.3, 1], [0.5, 0, 1], [-0.4, -0.2, 1]]\nuvs = [[0, 0], [0.5, 1], [1, 0.2]]\n\
        [[shape]]\ntype = \"mesh\"\nmaterial = \"front\"\npositions = [[1.6, 0, -0.5], [2.4, 0, -0.5], [2, 1.2, -0.2]]\nindices = [[0, 1, 2]]\n\
        normals = [[0, 0, -1], [0.2, 0, -1], [0, 0.3, -1]]\n\
        [[shape]]\ntype = \"mesh\"\nmaterial = \"checks\"\npositions = [[-2.5, 0.01, 0.5], [-0.5, 0.01, 0.5], [-1.5, 0.01, -0.8]]\n\
        indices = [[0, 1, 2]]\nuvs = [[0, 0], [1, 0], [0.5, 1]]\n\
        [[shape]]\ntype = \"sphere\"\ncenter = [1.2, 0.5, 1]\nradius = 0.4\nmaterial = \"glass\"\n\
        [[shape]]\ntype = \"mesh\"\nmaterial = \"both\"\npositions = [[-0.4, 2, -0.9], [0.4, 2, -0.9], [0, 2, -0.3]]\nindices = [[0, 1, 2]]\nemission = [8, 8, 8]\ntwo_sided = true\n\
        [[shape]]\ntype = \"sphere\"\ncenter = [-1.5, 1.5, 0.5]\nradius = 0.2\nmaterial = \"both\"\nemission = [5, 4, 3]\n\
        [[shape]]\ntype = \"quad\"\ncorner = [1.5, 2.2, 0]\nedge1 = [0.4, 0, 0]\nedge2 = [0, 0, 0.4]\nmaterial = \"both\"\nemission = [3, 3, 3]\n";
    let descs = [
        "cbox-mitsuba.toml",
        "materials.toml",
        "veach-mis.toml",
        "box-light.toml",
        "glossy-env.toml",
    ]
    .map(|name| {
        let path = format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR"));
        SourceFile::new(&path, std::fs::read_to_string(&path).unwrap())
    })
    .into_iter()
    .chain([
        SourceFile::new("mixed.toml", mixed.to_string()),
        SourceFile::new(
            "mixed-env.toml",
            format!("{mixed}[environment]\nradiance = [0.3, 0.4, 0.5]\n"),
        ),
        // In the repository's scenes folder, where its map `sky.pfm` is.
        SourceFile::new(
            format!("{}/scenes/mixed-sky.toml", env!("CARGO_MANIFEST_DIR")),
            format!("{mixed}[environment]\nfile = \"sky.pfm\"\n"),
        ),
    ]);
    for (file, sampler) in descs.flat_map(|f| [(f.clone(), SamplerKind::Sobol), (f, SamplerKind::Independent)]) {
        let mut desc = penumbra::scene::formats::native::read(&file).unwrap();
        (desc.render.width, desc.render.height) = (48, 40);
        let scene = build_scene(&desc).unwrap();
        let options = RenderOptions {
            spp: 3,
            seed: 5,
            sampler,
            ..RenderOptions::default()
        };
        let tracer = |eight_wide: bool| PathTracer {
            options: IntegratorOptions {
                max_depth: desc.render.max_depth.max(4),
                rr_depth: desc.render.rr_depth,
                ..IntegratorOptions::default()
            },
            eight_wide,
            lanes: Default::default(),
        };
        let film = |eight_wide: bool| {
            let cancel = std::sync::atomic::AtomicBool::new(false);
            let film = Film::new(scene.width, scene.height, false);
            render(&scene, &tracer(eight_wide), &options, film, &(), &cancel, &mut |_| {})
        };
        let (lanes, scalar) = (film(true), film(false));
        let name = format!("{} ({sampler:?})", file.path.display());
        assert_eq!(lanes.stats.rays, scalar.stats.rays, "{name}: rays");
        assert!(lanes.film == scalar.film, "{name}: the films differ");
        // `li` leaves the sampler where the one-path code does (the same dimensions used).
        let camera = scene.camera.generate_ray(Vec2::new(20.5, 17.5), Vec2::ZERO);
        for i in 0..64u32 {
            let next = |eight_wide: bool| {
                let mut s = PixelSampler::new(sampler, 3, 64);
                s.start(UVec2::new(i, 1), i);
                let t = tracer(eight_wide);
                t.prepare(&scene, &());
                let l = t.li(&scene, &camera, &mut s, &mut RayCounts::default(), &mut Vec::new());
                (l, s.next_1d())
            };
            assert_eq!(next(true), next(false), "{name}: sample {i}");
        }
        println!("{name}: identical ({:?})", lanes.stats.rays);
    }
}
