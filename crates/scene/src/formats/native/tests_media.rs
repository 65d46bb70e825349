//! The native reader's media: both forms of coefficients, references, grids and errors.

use super::tests::{error_of, parse};
use glam::Vec3;
use penumbra_core::Rgb;

/// `[[medium]]` in both forms, a shape's `interior`/`exterior`, the camera's `medium`, the
/// `null` material.
#[test]
fn media_are_read_and_referred_to() {
    use penumbra_render::media::{Homogeneous, Medium, MediumInterface};
    use penumbra_render::phase::{HenyeyGreenstein, Phase};
    let d = parse(
        r#"
        [camera]
        medium = "fog"

        [[medium]]
        name = "fog"
        sigma_a = [0.1, 0.2, 0.3]
        sigma_s = 2
        scale = 0.5

        [[medium]]
        name = "milk"
        albedo = 0.5
        sigma_t = 4
        phase = "hg"
        g = 0.3

        [[material]]
        name = "b"
        type = "null"

        [[shape]]
        type = "sphere"
        material = "b"
        interior = "milk"
        exterior = "fog"

        [[shape]]
        type = "sphere"
        "#,
    );
    assert_eq!(d.camera_medium, Some(0));
    assert_eq!(
        d.media[0].medium,
        Medium::Homogeneous(Homogeneous {
            sigma_a: Rgb::new(0.05, 0.1, 0.15),
            sigma_s: Rgb::splat(1.0),
            phase: Phase::Isotropic,
        })
    );
    assert_eq!(
        d.media[1].medium,
        Medium::Homogeneous(Homogeneous {
            sigma_a: Rgb::splat(2.0),
            sigma_s: Rgb::splat(2.0),
            phase: Phase::HenyeyGreenstein(HenyeyGreenstein::new(0.3)),
        })
    );
    assert_eq!(
        d.shapes[0].media,
        Some(MediumInterface {
            inside: Some(1),
            outside: Some(0)
        })
    );
    assert_eq!(d.shapes[1].media, None);
    assert!(d.materials[0].material.is_null());
}

#[test]
fn bad_media_are_errors_naming_the_line() {
    let m = "[[medium]]\nname = \"m\"\n";
    let cases: Vec<(String, &str, usize)> = vec![
        (format!("{m}sigma_a = 1\nalbedo = 0.5\n"), "not both", 1),
        (format!("{m}albedo = 1.5\n"), "at most 1", 3),
        (format!("{m}sigma_s = -1\n"), "must not be negative", 3),
        (format!("{m}phase = \"hg\"\ng = 1\n"), "(-1, 1)", 4),
        (format!("{m}phase = \"rayleigh\"\n"), "unknown phase function", 3),
        (format!("{m}type = \"cloud\"\n"), "unknown medium type", 3),
        (format!("{m}{m}"), "defined twice", 4),
        (
            "[[shape]]\ntype = \"sphere\"\ninterior = \"fog\"\n".into(),
            "no medium named `fog`",
            3,
        ),
        (format!("{m}[camera]\nmedium = \"n\"\n"), "no medium named `n`", 4),
        (format!("{m}type = \"grid\"\n"), "from `file`, or from `resolution`", 1),
        (
            format!("{m}type = \"grid\"\nresolution = [2, 1, 1]\ndensity = [1]\n"),
            "needs 2 densities, found 1",
            5,
        ),
        (
            format!("{m}type = \"grid\"\nresolution = [2, 1, 1]\ndensity = [1, -1]\n"),
            "density 1 is -1",
            5,
        ),
        (
            format!("{m}type = \"grid\"\nresolution = [100000, 1, 1]\ndensity = [1]\n"),
            "from 1 to 4096",
            4,
        ),
        (format!("{m}type = \"grid\"\nfile = \"none.vol\"\n"), "cannot open", 4),
    ];
    for (text, needle, line) in cases {
        let (message, at) = error_of(&text);
        assert!(message.contains(needle), "{text}: {message}");
        assert_eq!(at, Some(line), "{text}: {message}");
    }
}

/// A grid medium's densities inline and from a `.vol` file beside the scene, placed by
/// its `transform`, with σt and albedo from σa and σs.
#[test]
fn grid_media_read_inline_and_from_files() {
    use crate::formats::vol::{self, VolGrid};
    use penumbra_render::media::Medium;
    let text = |source: &str| {
        format!(
            "[[medium]]\nname = \"cloud\"\ntype = \"grid\"\n{source}\nsigma_a = 1\nsigma_s = 3\n\
             transform = {{ translate = [1, 0, 0] }}\n"
        )
    };
    let values: Vec<f32> = (0..8).map(|i| i as f32).collect();
    let inline = format!("resolution = [2, 2, 2]\ndensity = {values:?}");
    let dir = tempfile::tempdir().unwrap();
    vol::write(
        &dir.path().join("g.vol"),
        &VolGrid {
            res: glam::UVec3::splat(2),
            channels: 1,
            bbox: [Vec3::ZERO, Vec3::ONE],
            values,
        },
    )
    .unwrap();
    for source in [inline.as_str(), "file = \"g.vol\""] {
        let path = dir.path().join("scene.toml");
        std::fs::write(&path, text(source)).unwrap();
        let d = crate::read_scene(&path).unwrap();
        let Medium::Grid(g) = &d.media[0].medium else {
            panic!("{:?}", d.media[0].medium)
        };
        assert_eq!(g.albedo, Rgb::splat(0.75), "{source}");
        // Value 7's cell centre, (0.75, 0.75, 0.75) of the cube, moved by 1 along x.
        let p = d.media[0].medium.at(Vec3::new(1.75, 0.75, 0.75));
        assert!(((p.sigma_a + p.sigma_s).g - 28.0).abs() < 1e-4, "{source}: {p:?}");
        assert_eq!(d.media[0].medium.at(Vec3::splat(0.75)).sigma_s, Rgb::BLACK, "{source}");
    }
}
