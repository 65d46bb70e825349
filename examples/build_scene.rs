//! Builds a scene in code, without a scene file, renders it and writes a PNG.
//!
//! `cargo run --release --example build_scene` writes `example.png`.

use glam::Vec3;
use penumbra::math::{Rgb, Transform};
use penumbra::renderer::materials::Phong;
use penumbra::renderer::{Material, Texture};
use penumbra::scene::desc::{CameraDesc, LightDesc, MaterialDesc, SceneDesc, ShapeDesc, ShapeKind};
use penumbra::scene::image_io::{write_image, Image};
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut scene = SceneDesc::empty();
    scene.render.width = 480;
    scene.render.height = 320;
    scene.render.spp = 9;
    scene.background = Rgb::new(0.05, 0.05, 0.08);
    scene.camera = CameraDesc {
        position: Vec3::new(0.0, 2.0, 7.0),
        target: Vec3::new(0.0, 0.8, 0.0),
        ..CameraDesc::default()
    };

    let mut material = |name: &str, m: Phong| {
        scene.materials.push(MaterialDesc {
            name: name.into(),
            material: Material::Phong(m),
            spectra: None,
        });
        Some(scene.materials.len() - 1)
    };
    let floor = material(
        "floor",
        Phong {
            diffuse: Texture::Checker(penumbra::renderer::texture::Checker {
                even: Rgb::splat(0.8),
                odd: Rgb::splat(0.2),
                size: 1.0,
            }),
            ..Phong::default()
        },
    );
    let gold = material(
        "gold",
        Phong {
            diffuse: Texture::Constant(Rgb::new(0.3, 0.2, 0.05)),
            mirror: Rgb::new(0.8, 0.6, 0.2),
            ..Phong::default()
        },
    );
    let glass = material(
        "glass",
        Phong {
            diffuse: Texture::Constant(Rgb::BLACK),
            transmission: Rgb::WHITE,
            ior: 1.5,
            ..Phong::default()
        },
    );

    let mut add = |kind, transform, material| {
        scene.shapes.push(ShapeDesc {
            kind,
            transform,
            material,
            emission: None,
            media: None,
            location: None,
        })
    };
    add(
        ShapeKind::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        },
        Transform::IDENTITY,
        floor,
    );
    // A ring of spheres alternating gold and glass.
    for i in 0..6 {
        let angle = i as f32 * 60.0;
        let place = Transform::translate(Vec3::new(2.0, 0.5, 0.0)).then(Transform::rotate(Vec3::Y, angle).unwrap());
        add(
            ShapeKind::Sphere {
                center: Vec3::ZERO,
                radius: 0.5,
            },
            place,
            if i % 2 == 0 { gold } else { glass },
        );
    }
    add(
        ShapeKind::Box {
            min: Vec3::new(-0.5, 0.0, -0.5),
            max: Vec3::new(0.5, 1.5, 0.5),
        },
        Transform::IDENTITY,
        gold,
    );
    scene.lights.push(LightDesc::Point {
        position: Vec3::new(3.0, 6.0, 4.0),
        intensity: Rgb::splat(80.0),
    });

    let result = penumbra::render(&scene, Default::default())?;
    let film = &result.film;
    let pixels = film.image();
    let path = Path::new("example.png");
    write_image(
        path,
        &Image {
            width: film.width,
            height: film.height,
            pixels: &pixels,
        },
        0.0,
    )?;
    println!(
        "wrote {} in {:.2} s",
        path.display(),
        result.stats.elapsed.as_secs_f64()
    );
    Ok(())
}
