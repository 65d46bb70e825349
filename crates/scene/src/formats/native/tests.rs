//! The native reader against hand-checked descriptions.

use super::read;
use crate::desc::{CameraKind, LightDesc, ShapeKind};
use crate::SourceFile;
use glam::Vec3;
use penumbra_core::Rgb;
use penumbra_render::materials::{ConductorMaterial, DielectricMaterial, DiffuseMaterial, PlasticMaterial};
use penumbra_render::{Filter, Material, Texture};

pub(super) fn parse(text: &str) -> crate::SceneDesc {
    read(&SourceFile::new("test.toml", text.to_string())).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn every_shape_light_and_setting() {
    let d = parse(
        r#"
        [render]
        width = 320
        height = 200
        spp = 9
        seed = 12
        max_depth = 7
        min_weight = 0.01
        sampler = "independent"
        accel = "list"
        filter = { type = "tent", radius = 2 }

        [camera]
        type = "orthographic"
        position = [1, 2, 3]
        height = 4

        [world]
        background = 0.5
        ambient = [0.1, 0.2, 0.3]

        [[material]]
        name = "a"
        diffuse = { type = "checker", even = 1, odd = [0, 0, 1], size = 2 }
        mirror = 0.5

        [[mesh]]
        name = "tri"
        positions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
        indices = [[0, 1, 2]]

        [[shape]]
        type = "sphere"
        radius = 2
        material = "a"
        [[shape]]
        type = "plane"
        [[shape]]
        type = "quad"
        [[shape]]
        type = "disk"
        normal = [0, 0, 1]
        [[shape]]
        type = "box"
        min = [0, 0, 0]
        max = [1, 2, 3]
        [[shape]]
        type = "mesh"
        positions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
        indices = [[0, 1, 2]]
        smooth = true
        [[shape]]
        type = "instance"
        mesh = "tri"

        [[light]]
        type = "point"
        position = [0, 5, 0]
        [[light]]
        type = "spot"
        position = [0, 5, 0]
        cone_angle = 20
        [[light]]
        type = "directional"
        direction = [0, -2, 0]
        irradiance = 3
        "#,
    );
    let r = &d.render;
    assert_eq!((r.width, r.height, r.spp, r.seed, r.max_depth), (320, 200, 9, 12, 7));
    assert_eq!(r.filter, Filter::Tent { radius: 2.0 });
    assert_eq!(d.camera.kind, CameraKind::Orthographic { height: 4.0 });
    assert_eq!(d.camera.position, Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(d.background, Rgb::splat(0.5));
    let Material::Phong(m) = &d.materials[0].material else {
        panic!("a phong material")
    };
    assert_eq!(
        m.diffuse,
        Texture::Checker(penumbra_render::texture::Checker {
            even: Rgb::WHITE,
            odd: Rgb::new(0.0, 0.0, 1.0),
            size: 2.0
        })
    );
    assert_eq!(m.mirror, Rgb::splat(0.5));
    assert_eq!(d.shapes.len(), 7);
    assert!(matches!(d.shapes[0].kind, ShapeKind::Sphere { radius: 2.0, .. }));
    assert_eq!(d.shapes[0].material, Some(0));
    assert_eq!(d.shapes[1].material, None);
    match &d.shapes[5].kind {
        ShapeKind::Mesh(m) => assert!(m.normals.is_some(), "smooth = true computes normals"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(d.shapes[6].kind, ShapeKind::Instance { mesh: 0 }));
    assert_eq!(
        d.lights[1],
        LightDesc::Spot {
            position: Vec3::new(0.0, 5.0, 0.0),
            target: Vec3::new(0.0, 4.0, 0.0),
            intensity: Rgb::WHITE,
            cone_angle: 20.0,
            falloff_start: 20.0,
        }
    );
    assert_eq!(
        d.lights[2],
        LightDesc::Directional {
            direction: Vec3::new(0.0, -2.0, 0.0),
            irradiance: Rgb::splat(3.0)
        }
    );
}

#[test]
fn transform_steps_apply_in_order() {
    let d = parse(
        r#"
        [[shape]]
        type = "sphere"
        transform = [{ scale = 2 }, { rotate = 90, axis = [0, 0, 1] }, { translate = [1, 0, 0] }]
        [[shape]]
        type = "sphere"
        transform = { matrix = [1, 0, 0, 5,  0, 1, 0, 6,  0, 0, 1, 7,  0, 0, 0, 1] }
        "#,
    );
    // (1, 0, 0) -> scaled (2, 0, 0) -> rotated (0, 2, 0) -> translated (1, 2, 0).
    let p = d.shapes[0].transform.point(Vec3::X);
    assert!((p - Vec3::new(1.0, 2.0, 0.0)).length() < 1e-5, "{p}");
    // Matrices are written row by row: the last column is the translation.
    assert_eq!(d.shapes[1].transform.point(Vec3::ZERO), Vec3::new(5.0, 6.0, 7.0));
}

#[test]
fn defaults_when_tables_are_absent() {
    let d = parse("");
    assert_eq!(d.render, crate::desc::RenderDesc::default());
    assert!(d.shapes.is_empty() && d.lights.is_empty());
}

#[test]
fn degenerate_triangles_are_skipped_with_a_warning_naming_the_mesh() {
    let d = parse(
        r#"
        [[mesh]]
        name = "thin"
        positions = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0]]
        indices = [[0, 1, 2], [0, 1, 3], [1, 1, 2]]

        [[mesh]]
        name = "flat"
        positions = [[0, 0, 0], [1, 0, 0], [2, 0, 0]]
        indices = [[0, 1, 2]]

        [[shape]]
        type = "instance"
        mesh = "flat"
        "#,
    );
    assert_eq!(d.meshes[0].indices, vec![[0, 1, 2]]);
    assert!(d.meshes[1].indices.is_empty());
    assert_eq!(d.warnings.len(), 2, "{:?}", d.warnings);
    assert_eq!(
        d.warnings[0],
        "test.toml:2: mesh `thin`: skipped 2 of 3 triangles with zero area"
    );
    assert_eq!(
        d.warnings[1],
        "test.toml:7: mesh `flat` has no triangle with area (1 degenerate): it draws nothing"
    );
    // The scene with its empty mesh still builds and renders nothing in its place.
    let scene = crate::build_scene(&d).unwrap();
    let ray = penumbra_core::Ray::new(Vec3::new(0.5, 0.1, 1.0), Vec3::NEG_Z);
    assert!(scene.intersect(&ray, f32::INFINITY).is_none());
}

#[test]
fn huge_coordinates_are_an_error_naming_the_vertex() {
    let e = read(&SourceFile::new(
        "test.toml",
        "[[mesh]]\nname = \"m\"\npositions = [[0, 0, 0], [1, 0, 0], [0, 1e35, 0]]\nindices = [[0, 1, 2]]\n".into(),
    ))
    .unwrap_err();
    let text = format!("{e}");
    assert!(text.contains("vertex 2") && text.contains("1e35"), "{text}");
    assert_eq!(e.location().map(|l| l.file.line_col(l.span.start).0), Some(4));
}

/// The message and line of the error reading `text` gives, or of building the scene.
pub(super) fn error_of(text: &str) -> (String, Option<usize>) {
    let file = SourceFile::new("test.toml", text.to_string());
    let e = match read(&file) {
        Err(e) => e,
        Ok(d) => match crate::build_scene(&d) {
            Err(e) => e,
            Ok(_) => panic!("no error for:\n{text}"),
        },
    };
    (format!("{e}"), e.location().map(|l| l.file.line_col(l.span.start).0))
}

#[test]
fn emitters_and_direct_settings_are_read() {
    let d = parse(
        r#"
        [render]
        integrator = "direct"
        light_sampling = "grid"
        light_samples = 9
        mis_heuristic = "balance"
        light_selection = "all"

        [[shape]]
        type = "quad"
        emission = [1, 2, 3]
        two_sided = true

        [[shape]]
        type = "sphere"
        emission = 4
        "#,
    );
    use penumbra_render::integrators::{DirectOptions, LightSampling, MisHeuristic};
    assert_eq!(
        d.render.direct,
        DirectOptions {
            sampling: LightSampling::Grid,
            light_samples: 9,
            heuristic: MisHeuristic::Balance,
            selection: penumbra_render::lights::LightSelection::All,
        }
    );
    let e: Vec<_> = d.shapes.iter().map(|s| s.emission.clone().unwrap()).collect();
    assert_eq!((e[0].radiance, e[0].two_sided), (Rgb::new(1.0, 2.0, 3.0), true));
    assert_eq!((e[1].radiance, e[1].two_sided), (Rgb::splat(4.0), false));
    let scene = crate::build_scene(&d).unwrap();
    assert_eq!(scene.lights.len(), 2);
}

#[test]
fn bad_emitters_and_light_settings_are_errors_naming_the_line() {
    let cases: &[(&str, &str, usize)] = &[
        ("[[shape]]\ntype = \"quad\"\nemission = [1, -1, 1]\n", "must not be negative", 3),
        ("[[shape]]\ntype = \"plane\"\nemission = 1\n", "only quads, disks, spheres and meshes", 3),
        ("[[shape]]\ntype = \"box\"\nemission = 1\n", "only quads, disks, spheres and meshes", 3),
        ("[[shape]]\ntype = \"quad\"\ntwo_sided = true\n", "emitting shapes only", 3),
        (
            "[[shape]]\ntype = \"sphere\"\nemission = 1\ntransform = { scale = [1, 2, 1] }\n",
            "must stay a sphere",
            1,
        ),
        (
            "[[shape]]\ntype = \"quad\"\nemission = 1\ntransform = { scale = [1e-30, 1e-30, 1] }\n",
            "degenerate",
            1,
        ),
        (
            "[[shape]]\ntype = \"mesh\"\npositions = [[0, 0, 0], [1, 0, 0], [2, 0, 0]]\nindices = [[0, 1, 2]]\nemission = 1\n",
            "no triangles with area",
            1,
        ),
        ("[[shape]]\ntype = \"quad\"\nemission = [1, inf, 1]\n", "finite", 3),
        ("[render]\nlight_samples = 0\n", "from 1 to 65536", 2),
        ("[render]\nlight_sampling = \"grid\"\nlight_samples = 8\n", "square number", 3),
        ("[render]\nlight_sampling = \"random\"\n", "unknown light sampling", 2),
        ("[render]\nmis_heuristic = \"max\"\n", "unknown MIS heuristic", 2),
        ("[render]\nlight_selection = \"some\"\n", "unknown light selection", 2),
    ];
    for (text, message, line) in cases {
        let (e, at) = error_of(text);
        assert!(e.contains(message), "{text}: `{e}` does not say `{message}`");
        assert_eq!(at, Some(*line), "{text}: {e}");
    }
}

#[test]
fn zero_emission_is_a_warning() {
    let d = parse("[[shape]]\ntype = \"disk\"\nemission = 0\n");
    assert_eq!(
        d.warnings,
        vec!["test.toml:3: this shape's emission is zero: it gives no light"]
    );
}

#[test]
fn bad_materials_are_errors_naming_the_line() {
    let m = "[[material]]\nname = \"m\"\n";
    let cases: Vec<(String, &str, usize)> = vec![
        (
            format!("{m}type = \"conductor\"\nroughness = 1.5\n"),
            "must lie in [0, 1], found 1.5",
            4,
        ),
        (
            format!("{m}type = \"dielectric\"\nroughness = -0.1\n"),
            "must lie in [0, 1]",
            4,
        ),
        (
            format!("{m}type = \"plastic\"\nroughness = {{ type = \"checker\", even = 0.2, odd = 2 }}\n"),
            "found 2",
            4,
        ),
        (format!("{m}type = \"conductor\"\nalpha_u = 0.1\n"), "go together", 1),
        (
            format!("{m}type = \"conductor\"\nroughness = 0.1\nalpha_u = 0.1\nalpha_v = 0.2\n"),
            "not both",
            4,
        ),
        (
            format!("{m}type = \"conductor\"\nmetal = \"Pt\"\n"),
            "unknown metal `Pt`",
            4,
        ),
        (format!("{m}type = \"conductor\"\neta = 1\n"), "go together", 4),
        (format!("{m}type = \"dielectric\"\nior = 0\n"), "positive", 4),
        (
            format!("{m}type = \"blend\"\na = \"x\"\nb = \"m\"\n"),
            "no material `x` is defined above",
            4,
        ),
        (format!("{m}type = \"blend\"\nweight = 1.2\n"), "must lie in [0, 1]", 4),
        (format!("{m}type = \"velvet\"\n"), "unknown material type `velvet`", 3),
        (format!("{m}type = \"coated\"\ng = 1.5\n"), "must lie in (-1, 1)", 4),
        (format!("{m}type = \"coated\"\nmax_depth = -1\n"), "", 4),
        (
            format!("{m}type = \"coated\"\nmetal = \"Cu\"\nmetal_roughness = 2\n"),
            "must lie in [0, 1]",
            5,
        ),
        (
            format!("{m}type = \"diffuse\"\nroughness = 0.2\n"),
            "unknown key `roughness`",
            4,
        ),
    ];
    for (text, message, line) in &cases {
        let (e, at) = error_of(text);
        assert!(e.contains(message), "{text}: `{e}` does not say `{message}`");
        assert_eq!(at, Some(*line), "{text}: {e}");
    }
}

#[test]
fn every_material_type_reads() {
    let d = parse(
        "[[material]]\nname = \"d\"\ntype = \"diffuse\"\nreflectance = 0.3\ntwo_sided = false\n\n\
         [[material]]\nname = \"c\"\ntype = \"conductor\"\nmetal = \"Cu\"\nalpha_u = 0.1\nalpha_v = 0.3\n\n\
         [[material]]\nname = \"g\"\ntype = \"dielectric\"\nior = 1.33\nroughness = 0.2\n\n\
         [[material]]\nname = \"p\"\ntype = \"plastic\"\ndiffuse = [0.1, 0.2, 0.3]\n\n\
         [[material]]\nname = \"b\"\ntype = \"blend\"\na = \"d\"\nb = \"c\"\nweight = 0.25\n\n\
         [[material]]\nname = \"w\"\ntype = \"coated\"\nreflectance = 0.4\nroughness = 0.1\nthickness = 0.1\n\n\
         [[material]]\nname = \"au\"\ntype = \"coated\"\nmetal = \"Au\"\nmetal_roughness = 0.2\nsamples = 2\n",
    );
    let kinds: Vec<&str> = d
        .materials
        .iter()
        .map(|m| match &m.material {
            Material::Diffuse(DiffuseMaterial { .. }) => "diffuse",
            Material::TwoSided(inner) => match **inner {
                Material::Conductor(ConductorMaterial { .. }) => "two-sided conductor",
                Material::Plastic(PlasticMaterial { .. }) => "two-sided plastic",
                Material::Blend { .. } => "two-sided blend",
                _ => "two-sided other",
            },
            Material::Blend { .. } => "blend",
            Material::Coated(c) => match &c.base {
                penumbra_render::materials::CoatedBase::Diffuse { .. } => "coated diffuse",
                penumbra_render::materials::CoatedBase::Conductor { roughness, .. } => {
                    assert!(roughness.is_some() && c.samples == 2 && c.roughness.is_none());
                    "coated metal"
                }
            },
            Material::Dielectric(DielectricMaterial { eta, .. }) => {
                assert!((eta - 1.33).abs() < 1e-6);
                "dielectric"
            }
            _ => "other",
        })
        .collect();
    assert_eq!(
        kinds,
        [
            "diffuse",
            "two-sided conductor",
            "dielectric",
            "two-sided plastic",
            "blend",
            "coated diffuse",
            "coated metal"
        ]
    );
}

#[test]
fn bad_environments_are_errors_naming_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let garbage = dir.path().join("sky.exr");
    std::fs::write(&garbage, b"not an image").unwrap();
    let odd = dir.path().join("sky.bmp");
    std::fs::write(&odd, b"BM").unwrap();
    let missing = dir.path().join("missing.hdr");
    let env = |rest: &str| format!("[environment]\n{rest}");
    let cases: Vec<(String, String, usize)> = vec![
        (env("radiance = 1\nfile = \"a.exr\"\n"), "not both".into(), 3),
        (env("scale = 2\n"), "needs `file`".into(), 1),
        (env("radiance = [1, -1, 1]\n"), "must not be negative".into(), 2),
        (
            env("radiance = 1\ntransform = { scale = 2 }\n"),
            "can only be rotated".into(),
            3,
        ),
        (
            format!("[world]\nbackground = 1\n\n{}", env("radiance = 1\n")),
            "remove `background`".into(),
            4,
        ),
        (
            env(&format!("file = \"{}\"\n", missing.display())),
            format!("cannot read the environment map {}", missing.display()),
            1,
        ),
        (
            env(&format!("file = \"{}\"\n", garbage.display())),
            format!("{}: not a readable OpenEXR image", garbage.display()),
            1,
        ),
        (
            env(&format!("file = \"{}\"\n", odd.display())),
            "unsupported image format".into(),
            1,
        ),
    ];
    for (text, message, line) in &cases {
        let (e, at) = error_of(text);
        assert!(e.contains(message.as_str()), "{text}: `{e}` does not say `{message}`");
        assert_eq!(at, Some(*line), "{text}: {e}");
    }
}

/// A scene text `text` in a temporary folder beside the image `name` of `pixels` (8-bit RGB).
fn with_image(
    name: &str,
    width: u32,
    pixels: Vec<u8>,
    text: &str,
) -> (
    tempfile::TempDir,
    std::result::Result<crate::SceneDesc, crate::SceneError>,
) {
    let dir = tempfile::tempdir().unwrap();
    let height = pixels.len() as u32 / (3 * width);
    image::RgbImage::from_raw(width, height, pixels)
        .unwrap()
        .save(dir.path().join(name))
        .unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let desc = crate::read_scene(&path);
    (dir, desc)
}

#[test]
fn image_textures_decode_srgb_for_colours_only() {
    // Pixel values 0, 128, 255: colours are sRGB-decoded (128 -> 0.2158), roughness is not.
    let text = "[[material]]\nname = \"c\"\ntype = \"diffuse\"\nreflectance = { type = \"image\", file = \"t.png\" }\n\n\
                [[material]]\nname = \"r\"\ntype = \"conductor\"\nroughness = { type = \"image\", file = \"t.png\", scale = 2 }\n";
    let (_dir, desc) = with_image("t.png", 1, vec![0, 128, 255], text);
    let desc = desc.unwrap();
    let texel = |m: &Material| -> (Rgb, f32) {
        let tex = match m {
            Material::TwoSided(inner) => match &**inner {
                Material::Diffuse(DiffuseMaterial { reflectance }) => reflectance.clone(),
                Material::Conductor(ConductorMaterial { roughness, .. }) => roughness.as_ref().unwrap().alpha_u.clone(),
                other => panic!("{other:?}"),
            },
            other => panic!("{other:?}"),
        };
        let Texture::Image(penumbra_render::texture::ImageTexture { image, scale }) = tex else {
            panic!("not an image")
        };
        (image.pixels[0], scale)
    };
    let (c, scale) = texel(&desc.materials[0].material);
    assert_eq!(scale, 1.0);
    assert!(
        c.r == 0.0 && (c.g - 0.2158).abs() < 1e-3 && (c.b - 1.0).abs() < 1e-6,
        "{c:?}"
    );
    let (r, scale) = texel(&desc.materials[1].material);
    assert_eq!(scale, 2.0);
    assert!((r.g - 128.0 / 255.0).abs() < 1e-6, "{r:?}");
}

#[test]
fn bad_textures_are_errors_naming_the_file_and_line() {
    let m = "[[material]]\nname = \"m\"\ntype = \"diffuse\"\n";
    let cases = [
        (
            format!("{m}reflectance = {{ type = \"image\", file = \"missing.png\" }}\n"),
            "cannot read the texture",
            "missing.png",
            4,
        ),
        (
            format!("{m}reflectance = {{ type = \"image\", file = \"t.gif\" }}\n"),
            "unsupported image format",
            "t.gif",
            4,
        ),
        (
            format!("{m}reflectance = {{ type = \"image\", file = \"broken.png\" }}\n"),
            "cannot decode it",
            "broken.png",
            4,
        ),
        (
            format!("{m}normal_map = \"broken.png\"\n"),
            "cannot read the texture",
            "broken.png",
            4,
        ),
    ];
    for (text, message, file, line) in cases {
        let (dir, desc) = with_image("t.png", 1, vec![0, 128, 255], &text);
        std::fs::write(dir.path().join("broken.png"), b"\x89PNG\r\n\x1a\nbroken").unwrap();
        std::fs::write(dir.path().join("t.gif"), b"GIF89a").unwrap();
        // Read again now that the broken files exist.
        let desc = match desc {
            Err(_) | Ok(_) => crate::read_scene(&dir.path().join("scene.toml")),
        };
        let e = desc.expect_err(&text);
        let shown = format!("{e}");
        assert!(shown.contains(message) && shown.contains(file), "{text}: `{shown}`");
        assert_eq!(
            e.location().map(|l| l.file.line_col(l.span.start).0),
            Some(line),
            "{text}: {shown}"
        );
    }
}
