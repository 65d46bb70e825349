//! The `direct` integrator against closed forms, end to end (scene file, builder, lights,
//! integrator): the radiance reflected by a Lambertian floor of albedo ρ at a point under a
//! disk or a sphere light of radiance L is ρ E / π, with the irradiance E of the view
//! factor formulas: πL r²/(h² + r²) for a disk of radius r facing the point from height h,
//! πL (r/d)² for a sphere of radius r whose centre is at distance d straight above.
//!
//! Every random strategy must agree within 3 standard errors of the mean of 40,000
//! independent estimates (the standard error is measured from the same estimates); `grid`
//! is deterministic and must converge as k grows. Variance claims are asserted with margins.

use penumbra::math::{PixelSampler, Ray, SamplerKind, UVec2, Vec3};
use penumbra::renderer::integrators::{DirectOptions, IntegratorKind, IntegratorOptions, LightSampling, MisHeuristic};
use penumbra::renderer::lights::LightSelection;
use penumbra::renderer::{RayCounts, Scene};
use penumbra::scene::{build_scene, SourceFile};
use penumbra_testkit::{assert_within_3se, assert_within_se, MeanEstimate};

const ALBEDO: f32 = 0.5;
const RADIANCE: f32 = 2.0;

/// A floor of albedo 0.5 through the origin and `light` (a TOML shape table body).
fn scene(light: &str, floor_material: &str) -> Scene {
    scene_with(
        &format!("[[shape]]\nmaterial = \"black\"\nemission = {RADIANCE}\n{light}"),
        floor_material,
    )
}

/// A floor of albedo 0.5 through the origin and the TOML tables `lights`.
fn scene_with(lights: &str, floor_material: &str) -> Scene {
    let text = format!(
        r#"
[[material]]
name = "floor"
{floor_material}

[[material]]
name = "black"
diffuse = 0

[[shape]]
type = "quad"
corner = [-20, 0, 20]
edge1 = [40, 0, 0]
edge2 = [0, 0, -40]
material = "floor"

{lights}
"#
    );
    let desc = penumbra::scene::formats::native::read(&SourceFile::new("test.toml", text)).unwrap();
    build_scene(&desc).unwrap()
}

fn lambertian_floor() -> String {
    format!("diffuse = {ALBEDO}")
}

/// A camera ray from the side, under the light, to the origin.
const PROBE: Vec3 = Vec3::new(3.0, 0.2, 0.5);

/// Mean and standard error of `n` independent estimates of the radiance along the probe ray.
fn estimate(scene: &Scene, direct: DirectOptions, n: u32) -> (f64, f64) {
    estimate_from(PROBE, scene, direct, n)
}

/// [`estimate`] for the ray from `origin` to the origin.
fn estimate_from(origin: Vec3, scene: &Scene, direct: DirectOptions, n: u32) -> (f64, f64) {
    let ray = Ray::new(origin, -origin.normalize());
    let integrator = IntegratorKind::Direct.create(IntegratorOptions {
        direct,
        ..IntegratorOptions::default()
    });
    let mut sampler = PixelSampler::new(SamplerKind::Independent, 7, n);
    let mut counts = RayCounts::default();
    let mut m = MeanEstimate::default();
    for i in 0..n {
        sampler.start(UVec2::new(i % 997, i / 997), i);
        m.push(integrator.li(scene, &ray, &mut sampler, &mut counts, &mut Vec::new()).g as f64);
    }
    (m.mean(), m.standard_error())
}

fn options(sampling: LightSampling, light_samples: u32) -> DirectOptions {
    DirectOptions {
        sampling,
        light_samples,
        heuristic: MisHeuristic::Power,
        selection: LightSelection::Power,
    }
}

/// Every random strategy, as (name, options).
fn strategies() -> Vec<(String, DirectOptions)> {
    let mut v = Vec::new();
    for (sampling, n) in [
        (LightSampling::Uniform, 1),
        (LightSampling::Stratified, 4),
        (LightSampling::SolidAngle, 1),
        (LightSampling::Bsdf, 1),
        (LightSampling::Mis, 1),
    ] {
        v.push((format!("{sampling:?} x{n}"), options(sampling, n)));
    }
    let balance = DirectOptions {
        heuristic: MisHeuristic::Balance,
        selection: LightSelection::All,
        ..options(LightSampling::Mis, 2)
    };
    v.push(("Mis balance x2, all lights".into(), balance));
    v
}

fn disk_light(h: f32, r: f32) -> (Scene, f64) {
    let light = format!("type = \"disk\"\ncenter = [0, {h}, 0]\nnormal = [0, -1, 0]\nradius = {r}");
    let expected = ALBEDO * RADIANCE * r * r / (h * h + r * r);
    (scene(&light, &lambertian_floor()), expected as f64)
}

fn sphere_light(d: f32, r: f32) -> (Scene, f64) {
    let light = format!("type = \"sphere\"\ncenter = [0, {d}, 0]\nradius = {r}");
    let expected = ALBEDO * RADIANCE * (r / d) * (r / d);
    (scene(&light, &lambertian_floor()), expected as f64)
}

#[test]
fn every_strategy_matches_the_closed_forms_within_3_standard_errors() {
    let n = 40_000;
    let cases = [
        ("disk h 1 r 0.5", disk_light(1.0, 0.5)),
        ("disk h 0.3 r 1", disk_light(0.3, 1.0)),
        ("sphere d 2 r 0.5", sphere_light(2.0, 0.5)),
        ("sphere d 0.8 r 0.6", sphere_light(0.8, 0.6)),
    ];
    for (what, (scene, expected)) in &cases {
        for (name, o) in strategies() {
            let (mean, se) = estimate(scene, o, n);
            println!("{what}, {name}: {mean:.5} +- {se:.5} (expected {expected:.5})");
            assert!(se > 0.0 && se < 0.05 * expected, "{what}, {name}: standard error {se}");
            assert_within_3se(&format!("{what}, {name}"), mean, se, *expected, 1e-5 * expected);
        }
    }
}

#[test]
fn grid_of_point_lights_converges_as_k_grows() {
    for (what, (scene, expected)) in [("disk", disk_light(1.0, 0.5)), ("sphere", sphere_light(0.8, 0.6))] {
        let errors: Vec<f64> = [1, 2, 4, 8, 16, 32]
            .iter()
            .map(|&k| {
                let (mean, se) = estimate(&scene, options(LightSampling::Grid, k * k), 2);
                assert_eq!(se, 0.0, "grid is deterministic");
                (mean - expected).abs() / expected
            })
            .collect();
        println!("{what}: relative error of grid k = 1, 2, 4, 8, 16, 32: {errors:.5?}");
        assert!(errors[0] > 0.02, "{what}: one point should be visibly off: {errors:?}");
        assert!(
            errors[5] < 0.005,
            "{what}: 32 x 32 points should be within 0.5%: {errors:?}"
        );
        if what == "disk" {
            // The midpoint rule on the disk: the error falls with every refinement.
            assert!(
                errors.windows(2).all(|w| w[1] < w[0]),
                "{what}: not converging: {errors:?}"
            );
        }
        // On a sphere the grid covers the whole surface and only the points on the visible
        // cap count, so small grids are erratic (k = 4 puts no point on the cap here).
    }
}

#[test]
fn solid_angle_sampling_beats_area_sampling_for_a_nearby_sphere() {
    let (scene, _) = sphere_light(0.8, 0.6);
    let (_, se_area) = estimate(&scene, options(LightSampling::Uniform, 1), 20_000);
    let (_, se_cone) = estimate(&scene, options(LightSampling::SolidAngle, 1), 20_000);
    println!("standard error: area {se_area:.5}, solid angle {se_cone:.5}");
    assert!(se_cone < 0.5 * se_area, "area {se_area}, solid angle {se_cone}");
}

#[test]
fn mis_has_lower_variance_than_the_worse_of_light_and_bsdf_sampling() {
    // A glossy floor (Phong, exponent 200) under a large disk light and a small sphere light:
    // BSDF sampling is poor for the small light, light sampling poor for the glossy lobe
    // under the large one (Veach's plates in miniature).
    // Seen from `eye`, the glossy lobe points along the mirror direction r = (-0.70, 0.70,
    // -0.11); the lights sit on it.
    let floor = "diffuse = 0.05\nspecular = 0.8\nexponent = 200";
    let eye = Vec3::new(2.0, 2.0, 0.3);
    let lights = [
        "type = \"disk\"\ncenter = [-1.41, 1.41, -0.21]\nnormal = [0.70, -0.70, 0.11]\nradius = 1.5",
        "type = \"sphere\"\ncenter = [-1.06, 1.06, -0.16]\nradius = 0.05",
    ];
    for light in lights {
        let scene = scene(light, floor);
        let n = 20_000;
        let (l_mean, se_light) = estimate_from(eye, &scene, options(LightSampling::SolidAngle, 1), n);
        let (b_mean, se_bsdf) = estimate_from(eye, &scene, options(LightSampling::Bsdf, 1), n);
        let (m_mean, se_mis) = estimate_from(eye, &scene, options(LightSampling::Mis, 1), n);
        println!("light {l_mean:.4}+-{se_light:.4}, bsdf {b_mean:.4}+-{se_bsdf:.4}, mis {m_mean:.4}+-{se_mis:.4}");
        // The three estimate the same integral.
        let agree = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() <= 4.0 * (a.1 * a.1 + b.1 * b.1).sqrt();
        assert!(
            agree((m_mean, se_mis), (l_mean, se_light)) && agree((m_mean, se_mis), (b_mean, se_bsdf)),
            "{light}: the means differ"
        );
        // MIS spends two rays per sample; compare per ray: its variance times two.
        let worse = se_light.max(se_bsdf);
        assert!(
            se_mis * 2f64.sqrt() < 0.7 * worse,
            "{light}: MIS {se_mis} (x sqrt 2 per ray) vs light {se_light}, BSDF {se_bsdf}"
        );
        let better = se_light.min(se_bsdf);
        assert!(
            se_mis < 1.5 * better,
            "{light}: MIS {se_mis} much worse than the better strategy {better}"
        );
    }
}

/// Irradiance at `p` (normal `n`) from a polygon of unit radiance facing it: Lambert's
/// formula E = 1/2 Σ θ_i n · (v_i x v_i+1) / |v_i x v_i+1|, v_i the unit directions to the
/// vertices and θ_i the angle between neighbours (e.g. Arvo 1995, "Applications of
/// Irradiance Tensors", eq. 1).
fn polygon_irradiance(p: Vec3, n: Vec3, vertices: &[Vec3]) -> f64 {
    let v: Vec<Vec3> = vertices.iter().map(|q| (*q - p).normalize()).collect();
    let sum: f64 = (0..v.len())
        .map(|i| {
            let (a, b) = (v[i], v[(i + 1) % v.len()]);
            let theta = (a.dot(b) as f64).clamp(-1.0, 1.0).acos();
            theta * n.dot(a.cross(b).normalize()) as f64
        })
        .sum();
    0.5 * sum.abs()
}

#[test]
fn quad_and_mesh_lights_match_lamberts_polygon_formula() {
    // A tilted rectangle above the origin, facing down; as a quad, as a two-triangle mesh,
    // as a mesh wound the other way whose vertex normals still face down, and as a
    // two-sided quad turned to face up.
    let (c, e1, e2) = (
        Vec3::new(-0.2, 1.0, -0.5),
        Vec3::new(1.0, 0.2, 0.0),
        Vec3::new(0.0, 0.0, 0.8),
    );
    let corners = [c, c + e1, c + e1 + e2, c + e2];
    let expected =
        ALBEDO as f64 / std::f64::consts::PI * RADIANCE as f64 * polygon_irradiance(Vec3::ZERO, Vec3::Y, &corners);
    let v = |p: Vec3| format!("[{}, {}, {}]", p.x, p.y, p.z);
    let positions = corners.iter().map(|&p| v(p)).collect::<Vec<_>>().join(", ");
    let down = v(e1.cross(e2).normalize());
    let lights = [
        ("quad", format!("type = \"quad\"\ncorner = {}\nedge1 = {}\nedge2 = {}", v(c), v(e1), v(e2))),
        ("mesh", format!("type = \"mesh\"\npositions = [{positions}]\nindices = [[0, 1, 2], [0, 2, 3]]")),
        (
            "mesh wound the other way, normals down",
            format!(
                "type = \"mesh\"\npositions = [{positions}]\nindices = [[0, 2, 1], [0, 3, 2]]\nnormals = [{down}, {down}, {down}, {down}]"
            ),
        ),
        (
            "two-sided quad facing up",
            format!(
                "type = \"quad\"\ncorner = {}\nedge1 = {}\nedge2 = {}\ntwo_sided = true",
                v(c),
                v(e2),
                v(e1)
            ),
        ),
    ];
    let mut cases: Vec<(&str, String, f64)> = lights.iter().map(|(w, l)| (*w, l.clone(), expected)).collect();
    // Mirrored in x by its transform: the rectangle is mirrored and still faces down.
    let mirrored: Vec<Vec3> = corners.iter().map(|p| Vec3::new(-p.x, p.y, p.z)).collect();
    cases.push((
        "quad mirrored by its transform",
        format!("{}\ntransform = {{ scale = [-1, 1, 1] }}", lights[0].1),
        ALBEDO as f64 / std::f64::consts::PI * RADIANCE as f64 * polygon_irradiance(Vec3::ZERO, Vec3::Y, &mirrored),
    ));
    for (what, light, expected) in &cases {
        let (what, expected) = (*what, *expected);
        let scene = scene(light, &lambertian_floor());
        for (name, o) in strategies() {
            let (mean, se) = estimate(&scene, o, 20_000);
            assert!(se > 0.0 && se < 0.05 * expected, "{what}, {name}: standard error {se}");
            // 5 lights x 7 strategies: 4 standard errors each (see `assert_within_se`).
            assert_within_se(&format!("{what}, {name}"), mean, se, expected, 1e-5 * expected, 4.0);
        }
    }
    // One-sided and facing away: no light at all.
    let away = format!(
        "type = \"quad\"\ncorner = {}\nedge1 = {}\nedge2 = {}",
        v(c),
        v(e2),
        v(e1)
    );
    let (mean, _) = estimate(&scene(&away, &lambertian_floor()), options(LightSampling::Mis, 1), 1000);
    assert_eq!(mean, 0.0);
}

#[test]
fn the_camera_sees_an_emitter_s_radiance_from_its_front_only() {
    let light = "type = \"quad\"\ncorner = [-1, 1, -1]\nedge1 = [2, 0, 0]\nedge2 = [0, 0, 2]";
    let scene = scene(light, &lambertian_floor());
    let up = Ray::new(Vec3::new(0.1, 0.5, 0.2), Vec3::Y);
    let down = Ray::new(Vec3::new(0.1, 3.0, 0.2), Vec3::NEG_Y);
    for kind in [IntegratorKind::Whitted, IntegratorKind::Direct] {
        let integrator = kind.create(IntegratorOptions::default());
        let mut sampler = PixelSampler::new(SamplerKind::Independent, 1, 1);
        let mut counts = RayCounts::default();
        let front = integrator.li(&scene, &up, &mut sampler, &mut counts, &mut Vec::new());
        assert_eq!(front, penumbra::math::Rgb::splat(RADIANCE), "{kind:?} from below");
        // From above, the back of the (black) light: no emission, no reflection.
        let back = integrator.li(&scene, &down, &mut sampler, &mut counts, &mut Vec::new());
        assert_eq!(back, penumbra::math::Rgb::BLACK, "{kind:?} from above");
    }
}

#[test]
fn many_lights_sum_up_for_every_light_selection() {
    // Two quads, a two-triangle mesh, a sphere and a point light of very different powers,
    // each in its own direction from the origin (none shadows another).
    let quad = |c: Vec3, e1: Vec3, e2: Vec3, radiance: f32| {
        let v = |p: Vec3| format!("[{}, {}, {}]", p.x, p.y, p.z);
        let toml = format!(
            "[[shape]]\ntype = \"quad\"\nmaterial = \"black\"\nemission = {radiance}\ncorner = {}\nedge1 = {}\nedge2 = {}\n",
            v(c),
            v(e1),
            v(e2)
        );
        (
            toml,
            radiance as f64 * polygon_irradiance(Vec3::ZERO, Vec3::Y, &[c, c + e1, c + e1 + e2, c + e2]),
        )
    };
    let (a, e_a) = quad(
        Vec3::new(-1.5, 1.0, -0.5),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
        2.0,
    );
    let (b, e_b) = quad(
        Vec3::new(0.6, 1.2, 0.6),
        Vec3::new(0.2, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.2),
        50.0,
    );
    let mesh = "[[shape]]\ntype = \"mesh\"\nmaterial = \"black\"\nemission = 3\n\
                positions = [[-0.3, 1, -1.5], [0.3, 1, -1.5], [0.3, 1, -0.8], [-0.3, 1, -0.8]]\n\
                indices = [[0, 1, 2], [0, 2, 3]]\n";
    let mesh_corners = [
        Vec3::new(-0.3, 1.0, -1.5),
        Vec3::new(0.3, 1.0, -1.5),
        Vec3::new(0.3, 1.0, -0.8),
        Vec3::new(-0.3, 1.0, -0.8),
    ];
    let e_mesh = 3.0 * polygon_irradiance(Vec3::ZERO, Vec3::Y, &mesh_corners);
    let sphere = "[[shape]]\ntype = \"sphere\"\nmaterial = \"black\"\nemission = 5\ncenter = [0, 2, 0]\nradius = 0.2\n";
    let e_sphere = std::f64::consts::PI * 5.0 * 0.01;
    let point = "[[light]]\ntype = \"point\"\nposition = [0.5, 1.5, -0.3]\nintensity = 0.8\n";
    let d2 = 0.25 + 2.25 + 0.09;
    let e_point = 0.8 * (1.5 / f64::sqrt(d2)) / d2;
    let scene = scene_with(&format!("{a}{b}{mesh}{sphere}{point}"), &lambertian_floor());
    assert_eq!((scene.lights.len(), scene.lights.groups()), (6, 5));
    let expected = ALBEDO as f64 / std::f64::consts::PI * (e_a + e_b + e_mesh + e_sphere + e_point);
    let samplings = [
        (LightSampling::Uniform, MisHeuristic::Power),
        (LightSampling::Stratified, MisHeuristic::Power),
        (LightSampling::SolidAngle, MisHeuristic::Power),
        (LightSampling::Bsdf, MisHeuristic::Power),
        (LightSampling::Mis, MisHeuristic::Power),
        (LightSampling::Mis, MisHeuristic::Balance),
    ];
    for selection in [LightSelection::Power, LightSelection::Uniform, LightSelection::All] {
        for (sampling, heuristic) in samplings {
            let o = DirectOptions {
                selection,
                heuristic,
                ..options(sampling, 2)
            };
            let (mean, se) = estimate(&scene, o, 40_000);
            println!("{selection:?} {sampling:?} {heuristic:?}: {mean:.5} +- {se:.5} (expected {expected:.5})");
            assert!(
                se > 0.0 && se < 0.05 * expected,
                "{selection:?}, {sampling:?}: standard error {se}"
            );
            let what = format!("{selection:?}, {sampling:?}");
            assert_within_3se(&what, mean, se, expected, 1e-5 * expected);
        }
    }
}
