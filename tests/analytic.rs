//! Renders checked against closed-form answers.

use glam::Vec3;
use penumbra::math::{Rgb, Transform};
use penumbra::renderer::materials::Phong;
use penumbra::renderer::{Filter, Material, Texture};
use penumbra::scene::desc::{CameraDesc, CameraKind, LightDesc, MaterialDesc, SceneDesc, ShapeDesc, ShapeKind};
use std::f32::consts::PI;

/// An orthographic camera at height `y` looking straight down, covering [-1, 1]^2 in x, z.
fn top_down_scene(y: f32, res: u32) -> SceneDesc {
    let mut d = SceneDesc::empty();
    d.render.width = res;
    d.render.height = res;
    d.render.spp = 4;
    // Samples at the pixel centre, so each pixel is the radiance at one known point.
    d.render.filter = Filter::Box { radius: 1e-3 };
    d.camera = CameraDesc {
        kind: CameraKind::Orthographic { height: 2.0 },
        position: Vec3::new(0.0, y, 0.0),
        target: Vec3::ZERO,
        up: Vec3::NEG_Z,
        mirrored: false,
        location: None,
    };
    d
}

/// World point seen at the centre of pixel (x, y) by `top_down_scene`.
fn pixel_point(x: u32, y: u32, res: u32) -> (f32, f32) {
    let ndc = |i: u32| 2.0 * (i as f32 + 0.5) / res as f32 - 1.0;
    (ndc(x), ndc(y))
}

fn add(d: &mut SceneDesc, kind: ShapeKind, material: Phong) {
    d.materials.push(MaterialDesc {
        name: format!("m{}", d.materials.len()),
        material: Material::Phong(material),
        spectra: None,
    });
    d.shapes.push(ShapeDesc {
        kind,
        transform: Transform::IDENTITY,
        emission: None,
        media: None,
        material: Some(d.materials.len() - 1),
        location: None,
    });
}

/// Clear glass of index 1.5.
fn glass() -> Phong {
    Phong {
        diffuse: Texture::Constant(Rgb::BLACK),
        transmission: Rgb::WHITE,
        ior: 1.5,
        ..Phong::default()
    }
}

fn diffuse(albedo: f32) -> Phong {
    Phong {
        diffuse: Texture::Constant(Rgb::splat(albedo)),
        ..Phong::default()
    }
}

#[test]
fn diffuse_plane_under_a_point_light() {
    // L = albedo / pi * I cos(theta) / r^2 at every visible point.
    let (res, albedo, intensity, h) = (32, 0.6, 5.0, 1.5);
    let mut d = top_down_scene(4.0, res);
    add(
        &mut d,
        ShapeKind::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        },
        diffuse(albedo),
    );
    d.lights.push(LightDesc::Point {
        position: Vec3::new(0.3, h, -0.2),
        intensity: Rgb::splat(intensity),
    });
    let film = penumbra::render(&d, Default::default()).unwrap().film;
    let mut worst = 0.0f32;
    for y in 0..res {
        for x in 0..res {
            let (px, pz) = pixel_point(x, y, res);
            let to_light = Vec3::new(0.3 - px, h, -0.2 - pz);
            let r2 = to_light.length_squared();
            let cos = h / r2.sqrt();
            let expected = albedo / PI * intensity * cos / r2;
            let got = film.pixel(x, y).value();
            assert_eq!(got.r, got.g);
            worst = worst.max((got.r - expected).abs() / expected);
        }
    }
    // Only float rounding separates the two (the pixel footprint is 2e-3 pixels wide).
    assert!(worst < 1e-4, "worst relative error {worst}");
}

#[test]
fn diffuse_sphere_under_a_point_light_has_no_shadow_acne() {
    // On a curved surface the shadow ray must leave the surface it starts on: without a
    // robust offset, some pixels shadow themselves. Each pixel sees the point
    // (x, sqrt(1 - x^2 - z^2), z) of a unit sphere with radiance albedo/pi I cos / r^2.
    let (res, albedo, intensity) = (48, 0.7, 9.0);
    let light = Vec3::new(0.4, 3.0, 0.3);
    let mut d = top_down_scene(4.0, res);
    add(
        &mut d,
        ShapeKind::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        },
        diffuse(albedo),
    );
    d.lights.push(LightDesc::Point {
        position: light,
        intensity: Rgb::splat(intensity),
    });
    let film = penumbra::render(&d, Default::default()).unwrap().film;
    let mut checked = 0;
    for y in 0..res {
        for x in 0..res {
            let (px, pz) = pixel_point(x, y, res);
            let h2 = 1.0 - px * px - pz * pz;
            if h2 < 0.2 {
                continue; // near the silhouette the footprint straddles the edge
            }
            let p = Vec3::new(px, h2.sqrt(), pz);
            let to_light = light - p;
            let cos = p.dot(to_light.normalize()).max(0.0);
            let expected = albedo / PI * intensity * cos / to_light.length_squared();
            let got = film.pixel(x, y).value().r;
            assert!(
                (got - expected).abs() <= 1e-3 * expected + 1e-5,
                "pixel ({x}, {y}): {got} vs {expected}"
            );
            checked += 1;
        }
    }
    assert!(checked > 1000);
}

#[test]
fn pixels_average_their_footprint() {
    // An edge between black and white through the middle of every pixel column: with a box
    // filter of one pixel, each pixel converges to the covered fraction. 64 stratified
    // samples estimate a half-covered pixel to within 1/64 (one stratum).
    let res = 8;
    let mut d = top_down_scene(2.0, res);
    d.render.spp = 64;
    d.render.filter = Filter::Box { radius: 0.5 };
    // Checks of side 2/8 + 1/8 offset put an edge at x = 1/8, inside pixel column 4.
    let checker = Phong {
        diffuse: Texture::Checker(penumbra::renderer::texture::Checker {
            even: Rgb::WHITE,
            odd: Rgb::BLACK,
            size: 10.0,
        }),
        ..Phong::default()
    };
    add(
        &mut d,
        ShapeKind::Plane {
            point: Vec3::new(0.125, 0.0, -5.0),
            normal: Vec3::Y,
        },
        checker,
    );
    d.ambient = Rgb::WHITE;
    let film = penumbra::render(&d, Default::default()).unwrap().film;
    // Plane texture coordinates run along the plane's own frame; find the column where the
    // value is strictly between black and white: it must be close to one half.
    let row: Vec<f32> = (0..res).map(|x| film.pixel(x, 3).value().r).collect();
    let partial: Vec<f32> = row.iter().copied().filter(|v| *v > 0.01 && *v < 0.99).collect();
    assert_eq!(partial.len(), 1, "{row:?}");
    assert!((partial[0] - 0.5).abs() <= 1.0 / 64.0 + 1e-4, "{row:?}");
}

#[test]
fn mirror_reflects_a_lit_ceiling() {
    // A mirror floor (reflectance 0.8) under a diffuse ceiling lit from below: each pixel is
    // 0.8 times the ceiling's radiance straight above the point.
    let (res, albedo, intensity) = (16, 0.5, 2.0);
    let mut d = top_down_scene(1.5, res);
    let mirror = Phong {
        diffuse: Texture::Constant(Rgb::BLACK),
        mirror: Rgb::splat(0.8),
        ..Phong::default()
    };
    add(
        &mut d,
        ShapeKind::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        },
        mirror,
    );
    add(
        &mut d,
        ShapeKind::Plane {
            point: Vec3::new(0.0, 2.0, 0.0),
            normal: Vec3::NEG_Y,
        },
        diffuse(albedo),
    );
    d.lights.push(LightDesc::Point {
        position: Vec3::new(0.0, 1.0, 0.0),
        intensity: Rgb::splat(intensity),
    });
    let render = |d: &SceneDesc| penumbra::render(d, Default::default()).unwrap().film;
    let film = render(&d);
    for (x, y) in [(0, 0), (3, 9), (8, 8), (15, 2)] {
        let (px, pz) = pixel_point(x, y, res);
        let r2 = px * px + 1.0 + pz * pz;
        let expected = 0.8 * albedo / PI * intensity * (1.0 / r2.sqrt()) / r2;
        let got = film.pixel(x, y).value().r;
        assert!(
            (got - expected).abs() / expected < 1e-4,
            "pixel ({x}, {y}): {got} vs {expected}"
        );
    }
    // Termination: no bounce at max depth 0, nor when the weight 0.8 is below the threshold.
    let mut shallow = d.clone();
    shallow.render.max_depth = 0;
    assert_eq!(render(&shallow).pixel(8, 8).value(), Rgb::BLACK);
    let mut faint = d.clone();
    faint.render.min_weight = 0.9;
    assert_eq!(render(&faint).pixel(8, 8).value(), Rgb::BLACK);
}

#[test]
fn glass_slab_at_normal_incidence_transmits_one_minus_f_over_one_plus_f() {
    // A glass slab (n = 1.5, F = 0.04 at normal incidence) over a surface of radiance A seen
    // through it: the internal reflections sum to A (1 - F)^2 / (1 - F^2) = A (1 - F) / (1 + F).
    let res = 8;
    let mut d = top_down_scene(3.0, res);
    d.render.max_depth = 40;
    d.render.min_weight = 0.0;
    d.ambient = Rgb::splat(1.0);
    add(
        &mut d,
        ShapeKind::Box {
            min: Vec3::new(-5.0, 1.0, -5.0),
            max: Vec3::new(5.0, 1.5, 5.0),
        },
        glass(),
    );
    add(
        &mut d,
        ShapeKind::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        },
        diffuse(1.0),
    );
    let film = penumbra::render(&d, Default::default()).unwrap().film;
    let expected = (1.0 - 0.04) / (1.0 + 0.04);
    for (x, y) in [(0, 0), (4, 4), (7, 2)] {
        let got = film.pixel(x, y).value().r;
        assert!((got - expected).abs() < 1e-5, "{got} vs {expected}");
    }
}

#[test]
fn glass_in_a_uniform_background_conserves_energy() {
    // A furnace test: reflection plus refraction of a lossless dielectric sum to one, so a
    // glass ball and a tilted glass box in a uniform background B are invisible (radiance B),
    // including their total internal reflections.
    let mut d = SceneDesc::empty();
    d.render.width = 48;
    d.render.height = 32;
    d.render.spp = 2;
    d.render.max_depth = 60;
    d.render.min_weight = 0.0;
    d.background = Rgb::new(0.25, 0.5, 1.0);
    add(
        &mut d,
        ShapeKind::Sphere {
            center: Vec3::new(-1.0, 0.0, 0.0),
            radius: 1.0,
        },
        glass(),
    );
    add(
        &mut d,
        ShapeKind::Box {
            min: Vec3::splat(-0.6),
            max: Vec3::splat(0.6),
        },
        glass(),
    );
    d.shapes[1].transform = Transform::rotate(Vec3::new(1.0, 1.0, 0.0), 30.0)
        .unwrap()
        .then(Transform::translate(Vec3::X));
    let film = penumbra::render(&d, Default::default()).unwrap().film;
    for y in 0..32 {
        for x in 0..48 {
            let got = film.pixel(x, y).value();
            for (g, b) in got.to_array().iter().zip(d.background.to_array()) {
                // Rays trapped beyond 60 bounces lose a little; 1e-3 relative allows for it.
                assert!((g - b).abs() <= 1e-3 * b, "pixel ({x}, {y}): {got:?}");
            }
        }
    }
}
