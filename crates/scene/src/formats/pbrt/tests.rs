//! The pbrt-v4 reader on small scenes written here: the transform stack, the camera's
//! handedness, materials and area lights by attribute, instancing, warnings, and errors
//! that point at the file, line and column at fault.

use super::read;
use crate::desc::ShapeKind;
use crate::formats::test_files::{error_at, folder};
use glam::Vec3;
use penumbra_render::materials::{ConductorMaterial, DiffuseMaterial};
use penumbra_render::Material;

const SCENE: &str = r#"LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" 40 "integer yresolution" [ 30 ]
Sampler "halton" "integer pixelsamples" 8
Integrator "path" "integer maxdepth" [ 4 ]
WorldBegin
MakeNamedMaterial "red" "string type" "diffuse" "rgb reflectance" [ 0.5 0.1 0.1 ]
AttributeBegin
  Translate 1 0 0
  Scale 2 2 2
  AreaLightSource "diffuse" "blackbody L" [ 6500 ] "float scale" 3
  NamedMaterial "red"
  Shape "trianglemesh" "point3 P" [ 0 0 0  1 0 0  0 1 0 ]
AttributeEnd
ObjectBegin "ball"
  Shape "sphere" "float radius" 0.5
ObjectEnd
Translate 0 2 0
ObjectInstance "ball"
Shape "disk"
"#;

#[test]
fn transforms_attributes_camera_and_instances() {
    let dir = folder(&[("a.pbrt", SCENE)]);
    let desc = read(&dir.path().join("a.pbrt")).unwrap();
    assert_eq!((desc.render.width, desc.render.height, desc.render.spp), (40, 30, 8));
    assert_eq!(desc.render.max_depth, 5, "pbrt's maxdepth 4 is 5 segments");
    // LookAt gives a left-handed camera: rendered mirrored relative to our look-at.
    assert!(desc.camera.mirrored);
    assert!(desc.camera.position.abs_diff_eq(Vec3::new(0.0, 0.0, 5.0), 1e-5));
    assert!((desc.camera.target - desc.camera.position)
        .normalize()
        .abs_diff_eq(Vec3::NEG_Z, 1e-5));
    assert_eq!(desc.shapes.len(), 3);
    // Translate then Scale: a point is scaled first, then moved.
    let tri = &desc.shapes[0];
    assert!(tri
        .transform
        .point(Vec3::new(1.0, 0.0, 0.0))
        .abs_diff_eq(Vec3::new(3.0, 0.0, 0.0), 1e-6));
    let e = tri.emission.clone().expect("an area light");
    let y = 0.2126 * e.radiance.r + 0.7152 * e.radiance.g + 0.0722 * e.radiance.b;
    assert!(
        (y - 3.0).abs() < 1e-3,
        "a blackbody of unit luminance times the scale: {y}"
    );
    let Material::TwoSided(inner) = &desc.materials[tri.material.unwrap()].material else {
        panic!("pbrt's diffuse reflects on both sides");
    };
    assert!(matches!(**inner, Material::Diffuse(DiffuseMaterial { .. })));
    // The instance is placed by the transform at ObjectInstance; attributes were restored.
    let ball = &desc.shapes[1];
    assert!(matches!(ball.kind, ShapeKind::Sphere { radius, .. } if radius == 0.5));
    assert!(ball
        .transform
        .point(Vec3::ZERO)
        .abs_diff_eq(Vec3::new(0.0, 2.0, 0.0), 1e-6));
    assert!(ball.emission.is_none());
}

#[test]
fn errors_name_the_file_line_and_column() {
    for (files, at, needle) in [
        (
            vec![("a.pbrt", "WorldBegin\n  Frobnicate 1\n")],
            "a.pbrt:2:3",
            "unknown directive `Frobnicate`",
        ),
        (
            vec![("a.pbrt", "Translate 1 2\nWorldBegin\n")],
            "a.pbrt:2:1",
            "Translate takes 3 numbers",
        ),
        (
            vec![("a.pbrt", "WorldBegin\nNamedMaterial \"wood\"\n")],
            "a.pbrt:2:1",
            "no material is named `wood`",
        ),
        (
            vec![("a.pbrt", "WorldBegin\nAttributeEnd\n")],
            "a.pbrt:2:1",
            "without a matching",
        ),
        (
            vec![
                ("a.pbrt", "WorldBegin\n Include \"b.pbrt\"\n"),
                ("b.pbrt", "Shape \"sphere\" \"float radius\" [ 1.2.3 ]\n"),
            ],
            "b.pbrt:1:33",
            "`1.2.3` is not a number",
        ),
        (
            vec![("a.pbrt", "WorldBegin\n Include \"a.pbrt\"\n")],
            "a.pbrt:2:2",
            "includes itself",
        ),
        (
            vec![("a.pbrt", "WorldBegin\nInclude \"nope.pbrt\"\n")],
            "a.pbrt:2:1",
            "cannot read",
        ),
        (
            vec![(
                "a.pbrt",
                "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"integer indices\" [ 0 1 3 ]\n",
            )],
            "a.pbrt:2:1",
            "index 3 is out of range",
        ),
        (
            vec![(
                "a.pbrt",
                "WorldBegin\nShape \"sphere\" \"float radius\" [ 1 ] \"bogus\" 2\n",
            )],
            "a.pbrt:2:37",
            "not a parameter declaration",
        ),
        (
            vec![("a.pbrt", "WorldBegin\nShape \"sphere\n")],
            "a.pbrt:2:7",
            "never ends",
        ),
    ] {
        let got = error_at(&files, read);
        assert!(
            got.starts_with(at) && got.contains(needle),
            "expected {at} ... {needle}, got {got}"
        );
    }
}

#[test]
fn unsupported_kinds_warn_once_each() {
    let scene = r#"WorldBegin
Shape "curve" "point3 P" [ 0 0 0 1 1 1 2 2 2 3 3 3 ]
Shape "curve" "point3 P" [ 0 0 0 1 1 1 2 2 2 3 3 3 ]
Shape "sphere" "float glow" 1
Shape "sphere" "float glow" 2
MakeNamedMedium "smoke" "string type" "nanovdb"
MakeNamedMedium "cloud" "string type" "nanovdb"
"#;
    let dir = folder(&[("a.pbrt", scene)]);
    let desc = read(&dir.path().join("a.pbrt")).unwrap();
    let count = |needle: &str| desc.warnings.iter().filter(|w| w.contains(needle)).count();
    assert_eq!(count("`curve`"), 1, "{:?}", desc.warnings);
    assert_eq!(count("`glow`"), 1, "{:?}", desc.warnings);
    assert_eq!(count("nanovdb"), 1, "{:?}", desc.warnings);
    assert_eq!(desc.shapes.len(), 2);
}

/// An image `infinite` light: pbrt's equal-area octahedral map, turned by the transform in
/// force and scaled by `scale`. A map bright only at its centre (light-space +z) lights the
/// world from where the transform sends +z, twice as bright as the map, and not from +z.
#[test]
fn image_infinite_lights_read_pbrts_octahedral_maps() {
    let n = 16;
    let mut pfm = format!("PF\n{n} {n}\n-1.0\n").into_bytes();
    for row in 0..n {
        for col in 0..n {
            let (x, y) = (col as f32 + 0.5 - n as f32 / 2.0, row as f32 + 0.5 - n as f32 / 2.0);
            let v = if x.abs() < 2.0 && y.abs() < 2.0 { 5.0f32 } else { 0.01 };
            for _ in 0..3 {
                pfm.extend(v.to_le_bytes());
            }
        }
    }
    let scene = "WorldBegin\nAttributeBegin\nRotate 90 1 0 0\nLightSource \"infinite\" \"string filename\" \"env.pfm\" \"float scale\" 2\nAttributeEnd\nShape \"sphere\" \"float radius\" 0.1\n";
    let dir = folder(&[("a.pbrt", scene)]);
    std::fs::write(dir.path().join("env.pfm"), &pfm).unwrap();
    let desc = read(&dir.path().join("a.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    let env = desc.environment.as_ref().expect("an environment");
    assert!(matches!(env.source, crate::desc::EnvironmentSource::Octahedral(_)));
    let lit_from = env.transform.vector(Vec3::Z).normalize();
    assert!(
        (lit_from - Vec3::Z).length() > 1.0,
        "the light's transform turns the map"
    );
    let built = crate::build_scene(&desc).unwrap();
    let bright = built.escaped(lit_from);
    assert!((bright.r - 10.0).abs() < 1e-3, "{bright:?}");
    assert!(built.escaped(Vec3::Z).r < 0.1);
    assert!(built.escaped(-lit_from).r < 0.1);
    // A map that is not square is refused, naming it.
    let dir = folder(&[("a.pbrt", scene)]);
    std::fs::write(
        dir.path().join("env.pfm"),
        b"PF\n2 1\n-1.0\n\0\0\x80?\0\0\x80?\0\0\x80?\0\0\x80?\0\0\x80?\0\0\x80?",
    )
    .unwrap();
    let desc = read(&dir.path().join("a.pbrt")).unwrap();
    let e = crate::build_scene(&desc).err().expect("not square").to_string();
    assert!(e.contains("env.pfm") && e.contains("square"), "{e}");
}

/// Lights given as spectra are normalised to unit luminance before `scale`, as pbrt-v4
/// does: a constant spectrum of 7 is equal-energy white of luminance 1 (times 2 here),
/// reddish in sRGB (illuminant E is warmer than D65); as a reflectance it stays 0.7.
#[test]
fn constant_spectrum_lights_have_unit_luminance() {
    let scene = "WorldBegin\nLightSource \"point\" \"spectrum I\" [ 7 ] \"float scale\" 2\nMaterial \"diffuse\" \"spectrum reflectance\" [ 0.7 ]\nShape \"sphere\"\n";
    let dir = folder(&[("a.pbrt", scene)]);
    let desc = read(&dir.path().join("a.pbrt")).unwrap();
    let crate::desc::LightDesc::Point { intensity: i, .. } = desc.lights[0] else {
        panic!()
    };
    let y = 0.2126 * i.r + 0.7152 * i.g + 0.0722 * i.b;
    assert!((y - 2.0).abs() < 1e-3 && i.r > i.b, "{i:?}");
    let Material::TwoSided(m) = &desc.materials[0].material else {
        panic!()
    };
    assert!(
        matches!(**m, Material::Diffuse(DiffuseMaterial { reflectance: penumbra_render::Texture::Constant(c) }) if c == penumbra_core::Rgb::splat(0.7))
    );
}

/// A `scale` texture multiplies its `tex` (a named texture or a value) by `scale`.
#[test]
fn scale_textures_multiply() {
    let scene = "WorldBegin\nTexture \"c\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [ 0.8 0.6 0.4 ] \"rgb tex2\" [ 0.2 0.2 0.2 ]\nTexture \"s\" \"spectrum\" \"scale\" \"texture tex\" \"c\" \"float scale\" 0.5\nMaterial \"diffuse\" \"texture reflectance\" \"s\"\nShape \"sphere\"\n";
    let dir = folder(&[("a.pbrt", scene)]);
    let desc = read(&dir.path().join("a.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
    let Material::TwoSided(m) = &desc.materials[0].material else {
        panic!()
    };
    let Material::Diffuse(DiffuseMaterial {
        reflectance: penumbra_render::Texture::Checker(penumbra_render::texture::Checker { even, odd, .. }),
    }) = &**m
    else {
        panic!("{m:?}")
    };
    assert_eq!(
        (*even, *odd),
        (penumbra_core::Rgb::new(0.4, 0.3, 0.2), penumbra_core::Rgb::splat(0.1))
    );
}

/// Review finds: an escaped non-ASCII character in a string is read whole (it panicked
/// mid-character); a conductor given a `reflectance` reflects it at normal incidence
/// (Schlick) instead of copper; an explicit whole sphere does not warn.
#[test]
fn escapes_reflectance_conductors_and_whole_spheres() {
    let scene = "WorldBegin\nMakeNamedMaterial \"a\\é\" \"string type\" \"conductor\" \"rgb reflectance\" [ 0.9 0.6 0.3 ]\nNamedMaterial \"aé\"\nShape \"sphere\" \"float radius\" 2 \"float zmax\" 2 \"float phimax\" 360\n";
    let dir = folder(&[("a.pbrt", scene)]);
    let desc = read(&dir.path().join("a.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
    let Material::TwoSided(m) = &desc.materials[0].material else {
        panic!()
    };
    assert!(
        matches!(&**m, Material::Conductor(ConductorMaterial { fresnel: penumbra_render::bsdfs::MetalFresnel::Schlick, specular: penumbra_render::Texture::Constant(c), .. }) if *c == penumbra_core::Rgb::new(0.9, 0.6, 0.3)),
        "{m:?}"
    );
}

/// pbrt-v4's sensor scales the image by exposure time × ISO / 100: Film `iso` 150 with the
/// default shutter (0 to 1) makes every emitter 1.5 times brighter, and a shutter open
/// for half the time halves it again; a shutter that closes before it opens is an error.
#[test]
fn iso_and_shutter_scale_the_light() {
    let light = "WorldBegin\nLightSource \"point\" \"rgb I\" [ 2 2 2 ]\nAttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\nShape \"sphere\"\nAttributeEnd\n";
    for (head, ratio) in [
        ("", 1.0),
        ("Film \"rgb\" \"float iso\" 150\n", 1.5),
        ("Camera \"perspective\" \"float shutteropen\" 0.25 \"float shutterclose\" 0.75\nFilm \"rgb\" \"float iso\" 150\n", 0.75),
    ] {
        let dir = folder(&[("a.pbrt", &format!("{head}{light}"))]);
        let desc = read(&dir.path().join("a.pbrt")).unwrap();
        let crate::desc::LightDesc::Point { intensity, .. } = desc.lights[0] else {
            panic!()
        };
        assert!((intensity.g - 2.0 * ratio).abs() < 1e-6, "{head}: {intensity:?}");
        let radiance = desc.shapes[0].emission.as_ref().unwrap().radiance;
        assert!((radiance.g - ratio).abs() < 1e-6, "{head}: {radiance:?}");
        assert!(desc.warnings.iter().all(|w| !w.contains("iso")), "{:?}", desc.warnings);
    }
    let dir = folder(&[(
        "a.pbrt",
        "Camera \"perspective\" \"float shutteropen\" 1 \"float shutterclose\" 0.5\nWorldBegin\n",
    )]);
    let e = read(&dir.path().join("a.pbrt")).unwrap_err().to_string();
    assert!(e.contains("a.pbrt:1") && e.contains("shutterclose"), "{e}");
}

/// pbrt-v4's coated materials are the layered BSDF with their own parameters: the
/// interface's roughness remapped (sqrt) and index, the metal's index, the layer's
/// thickness, medium, depth and sample count; unset ones take pbrt-v4's defaults.
#[test]
fn coated_materials_keep_their_layers() {
    use penumbra_render::materials::{Coated, CoatedBase};
    let scene = r#"WorldBegin
MakeNamedMaterial "wood" "string type" "coateddiffuse" "rgb reflectance" [ 0.5 0.2 0.1 ] "float roughness" 0.04 "float thickness" 0.2 "rgb albedo" [ 0.3 0.3 0.3 ] "float g" 0.5 "integer maxdepth" 20 "integer nsamples" 4
MakeNamedMaterial "gold" "string type" "coatedconductor" "float interface.roughness" 0.01 "float interface.eta" 1.6 "rgb conductor.eta" [ 0.2 0.4 1.4 ] "rgb conductor.k" [ 3.9 2.4 1.8 ] "float conductor.roughness" 0.09
MakeNamedMaterial "bad" "string type" "coateddiffuse" "integer maxdepth" -3
NamedMaterial "wood"
Shape "sphere"
NamedMaterial "gold"
Shape "sphere"
"#;
    let dir = folder(&[("a.pbrt", scene)]);
    let err = read(&dir.path().join("a.pbrt")).unwrap_err().to_string();
    assert!(err.contains("a.pbrt:4") && err.contains("maxdepth"), "{err}");
    let scene = scene.replace("\"integer maxdepth\" -3", "");
    let dir = folder(&[("a.pbrt", &scene)]);
    let desc = read(&dir.path().join("a.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    let Material::Coated(wood) = &desc.materials[0].material else {
        panic!("{:?}", desc.materials[0].material)
    };
    assert!(matches!(&wood.base, CoatedBase::Diffuse { .. }));
    assert_eq!(
        (wood.eta, wood.thickness, wood.g, wood.max_depth, wood.samples),
        (1.5, 0.2, 0.5, 20, 4)
    );
    let alpha = wood.roughness.as_ref().map(|r| r.alpha_u.eval(glam::Vec2::ZERO).r);
    assert!((alpha.unwrap() - 0.2).abs() < 1e-6, "{alpha:?}");
    let Material::Coated(gold) = &desc.materials[1].material else {
        panic!("{:?}", desc.materials[1].material)
    };
    let CoatedBase::Conductor { fresnel, roughness, .. } = &gold.base else {
        panic!("{:?}", gold.base)
    };
    assert!(matches!(fresnel, penumbra_render::bsdfs::MetalFresnel::Complex { eta, .. } if eta.b == 1.4));
    assert!(roughness.is_some() && gold.roughness.is_some() && gold.eta == 1.6);
    let d = Coated::default();
    assert_eq!(
        (gold.thickness, gold.max_depth, gold.samples),
        (d.thickness, d.max_depth, d.samples)
    );
}

/// `MakeNamedMedium` (homogeneous, pbrt-v4's defaults of 1), `MediumInterface` with one or
/// two names, the camera's medium (the outside one when `Camera` comes), the `interface`
/// material and `volpath`; an unknown medium names its line.
#[test]
fn media_follow_the_graphics_state() {
    use penumbra_render::integrators::IntegratorKind;
    use penumbra_render::media::{Homogeneous, Medium, MediumInterface};
    use penumbra_render::phase::{HenyeyGreenstein, Phase};
    let scene = r#"Integrator "volpath"
MakeNamedMedium "gas" "string type" "homogeneous" "rgb sigma_a" [0.1 0.2 0.3] "float scale" 2 "float g" -0.5
MediumInterface "" "gas"
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
AttributeBegin
  MediumInterface "gas" ""
  Material "interface"
  Shape "sphere"
AttributeEnd
Shape "sphere"
"#;
    let dir = folder(&[("a.pbrt", scene)]);
    let desc = read(&dir.path().join("a.pbrt")).unwrap();
    assert_eq!(desc.render.integrator, IntegratorKind::Volpath);
    assert_eq!(desc.camera_medium, Some(0));
    assert_eq!(
        desc.media[0].medium,
        Medium::Homogeneous(Homogeneous {
            sigma_a: penumbra_core::Rgb::new(0.2, 0.4, 0.6),
            sigma_s: penumbra_core::Rgb::splat(2.0),
            phase: Phase::HenyeyGreenstein(HenyeyGreenstein::new(-0.5)),
        })
    );
    assert_eq!(
        desc.shapes[0].media,
        Some(MediumInterface {
            inside: Some(0),
            outside: None
        })
    );
    assert!(desc.materials[desc.shapes[0].material.unwrap()].material.is_null());
    // The interface in force outside the attribute block: inside "" and outside "gas".
    assert_eq!(
        desc.shapes[1].media,
        Some(MediumInterface {
            inside: None,
            outside: Some(0)
        })
    );
    let got = error_at(&[("a.pbrt", "WorldBegin\nMediumInterface \"fog\"\n")], read);
    assert!(
        got.starts_with("a.pbrt:2:") && got.contains("no medium is named `fog`"),
        "{got}"
    );
}

/// `uniformgrid`: the density array over `p0`-`p1` under the transform in force, σt = σa + σs
/// and the albedo σs/σt; a density array of the wrong size names its line.
#[test]
fn uniform_grids_are_read() {
    use penumbra_render::media::Medium;
    let scene = r#"WorldBegin
Translate 0 0 5
MakeNamedMedium "smoke" "string type" "uniformgrid" "integer nx" 2 "integer ny" 1 "integer nz" 1
    "float density" [0 2] "point3 p0" [-1 -1 -1] "point3 p1" [1 1 1] "rgb sigma_a" [1 1 1] "rgb sigma_s" [3 1 0] "float g" 0.5
"#;
    let dir = folder(&[("a.pbrt", scene)]);
    let desc = read(&dir.path().join("a.pbrt")).unwrap();
    let Medium::Grid(g) = &desc.media[0].medium else {
        panic!("{:?}", desc.media[0].medium)
    };
    assert_eq!(g.sigma_t, penumbra_core::Rgb::new(4.0, 2.0, 1.0));
    assert_eq!(g.albedo, penumbra_core::Rgb::new(0.75, 0.5, 0.0));
    // The grid's x runs from -1 to 1 at z = 5: density 0 at its first sample, 2 at its last.
    let at = |x: f32| desc.media[0].medium.at(Vec3::new(x, 0.0, 5.0)).sigma_t().r;
    assert!(at(-0.9).abs() < 1e-5 && (at(0.9) - 8.0).abs() < 1e-4 && (at(0.0) - 4.0).abs() < 1e-4);
    assert_eq!(at(0.0), desc.media[0].medium.at(Vec3::new(0.0, 0.9, 5.9)).sigma_t().r);
    assert_eq!(desc.media[0].medium.at(Vec3::new(0.0, 0.0, 0.0)).sigma_t().r, 0.0);

    let bad =
        "WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer nx\" 3 \"float density\" [1 2]\n";
    let got = error_at(&[("a.pbrt", bad)], read);
    assert!(got.starts_with("a.pbrt:2:") && got.contains("needs 3 values"), "{got}");
}
