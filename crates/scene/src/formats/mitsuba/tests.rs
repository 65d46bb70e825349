//! The Mitsuba reader on small scenes written here: parameters, includes, references,
//! transforms, warnings, and errors that point at the file, line and column at fault.

use super::read;
use crate::desc::ShapeKind;
use crate::formats::test_files::{error_at, error_at_in, folder};
use glam::Vec3;
use penumbra_render::materials::DiffuseMaterial;
use penumbra_render::{Material, Texture};

const MAIN: &str = r#"<scene version="3.0.0">
    <default name="w" value="32"/>
    <include filename="parts/bsdfs.xml"/>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <string name="fov_axis" value="y"/>
        <transform name="to_world">
            <lookat origin="0, 1, 5" target="0, 1, 0" up="0, 1, 0"/>
        </transform>
        <film type="hdrfilm">
            <integer name="width" value="$w"/>
            <integer name="height" value="24"/>
            <rfilter type="box"/>
        </film>
        <sampler type="independent"><integer name="sample_count" value="9"/></sampler>
    </sensor>
    <integrator type="path"><integer name="max_depth" value="-1"/></integrator>
    <shape type="rectangle">
        <transform name="to_world">
            <scale x="2"/>
            <rotate x="1" angle="90"/>
            <translate y="-1"/>
        </transform>
        <ref id="red"/>
    </shape>
    <shape type="sphere">
        <point name="center" x="0" y="2" z="0"/>
        <float name="radius" value="0.5"/>
        <ref id="lamp"/>
    </shape>
    <emitter type="area" id="lamp"><rgb name="radiance" value="4, 5, 6"/></emitter>
</scene>"#;

const BSDFS: &str = r#"<scene version="3.0.0">
    <bsdf type="twosided" id="red">
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.1, 0.1"/></bsdf>
    </bsdf>
</scene>"#;

#[test]
fn parameters_includes_references_and_transforms() {
    let dir = folder(&[("main.xml", MAIN), ("parts/bsdfs.xml", BSDFS)]);
    let main = dir.path().join("main.xml");
    let desc = read(&main, &[]).unwrap();
    assert_eq!((desc.render.width, desc.render.height, desc.render.spp), (32, 24, 9));
    assert_eq!(desc.render.max_depth, penumbra_render::integrators::MAX_DEPTH_LIMIT);
    assert!(matches!(desc.render.filter, penumbra_render::Filter::Box { .. }));
    assert_eq!(desc.camera.position, Vec3::new(0.0, 1.0, 5.0));
    assert!((desc.camera.target - desc.camera.position)
        .normalize()
        .abs_diff_eq(Vec3::NEG_Z, 1e-6));
    // Scale x by 2, then a quarter turn about x (y -> z), then down by 1: the corner
    // (1, 1, 0) goes to (2, 1, 0), then (2, 0, 1), then (2, -1, 1).
    let rect = &desc.shapes[0];
    assert!(matches!(rect.kind, ShapeKind::Mesh(_)));
    assert!(rect
        .transform
        .point(Vec3::new(1.0, 1.0, 0.0))
        .abs_diff_eq(Vec3::new(2.0, -1.0, 1.0), 1e-6));
    let Material::TwoSided(inner) = &desc.materials[rect.material.unwrap()].material else {
        panic!("twosided expected");
    };
    assert!(
        matches!(**inner, Material::Diffuse(DiffuseMaterial { reflectance: Texture::Constant(c) }) if c.g == 0.1f32)
    );
    // A reference to an area emitter defined after the shape.
    let sphere = &desc.shapes[1];
    assert!(matches!(sphere.kind, ShapeKind::Sphere { radius, .. } if radius == 0.5));
    assert_eq!(sphere.emission.as_ref().unwrap().radiance.b, 6.0);
    // -D overrides the default.
    let desc = read(&main, &[("w".into(), "16".into())]).unwrap();
    assert_eq!(desc.render.width, 16);
}

#[test]
fn errors_name_the_file_line_and_column() {
    let bad_float = r#"<scene version="3.0.0">
    <shape type="sphere">
        <float name="radius" value="wide"/>
    </shape>
</scene>"#;
    for (files, at, needle) in [
        (vec![("a.xml", bad_float)], "a.xml:3:37", "expected a number"),
        (
            vec![("a.xml", "<scene version=\"3.0.0\">\n  <include filename=\"b.xml\"/>\n</scene>"), ("b.xml", bad_float)],
            "b.xml:3:37",
            "expected a number",
        ),
        (
            vec![("a.xml", "<scene version=\"3.0.0\">\n <film type=\"hdrfilm\"/>\n <sensor type=\"perspective\">\n  <film type=\"hdrfilm\"><integer name=\"width\" value=\"$res\"/></film>\n </sensor>\n</scene>")],
            "a.xml:4:53",
            "`$res` is not defined",
        ),
        (
            vec![("a.xml", "<scene version=\"3.0.0\">\n  <include filename=\"b.xml\"/>\n</scene>"), ("b.xml", "<scene version=\"3.0.0\">\n  <include filename=\"a.xml\"/>\n</scene>")],
            "b.xml:2:22",
            "includes itself",
        ),
        (
            vec![("a.xml", "<scene version=\"3.0.0\">\n  <include filename=\"missing.xml\"/>\n</scene>")],
            "a.xml:2:22",
            "cannot read",
        ),
        (
            vec![("a.xml", "<scene version=\"3.0.0\">\n  <shape type=\"cube\">\n    <ref id=\"nothing\"/>\n  </shape>\n</scene>")],
            "a.xml:3:5",
            "no bsdf or area emitter has the id `nothing`",
        ),
        (vec![("a.xml", "<scene>\n</scene>")], "a.xml:1:1", "needs a `version`"),
        (vec![("a.xml", "<scene version=\"3.0.0\">\n  <shape type=\"cube\">\n</scene>")], "a.xml:3:1", "not well-formed"),
        (
            vec![("a.xml", "<scene version=\"3.0.0\">\n  <shape type=\"obj\">\n    <string name=\"filename\" value=\"none.obj\"/>\n  </shape>\n</scene>")],
            "a.xml:3:36",
            "none.obj",
        ),
        (
            vec![("a.xml", "<scene version=\"3.0.0\">\n  <shape type=\"cube\">\n    <transform name=\"to_world\"><scale value=\"0\"/></transform>\n  </shape>\n</scene>")],
            "a.xml:3:32",
            "singular",
        ),
        (
            vec![("a.xml", "<scene version=\"3.0.0\">\n  <bsdf type=\"diffuse\">\n    <texture type=\"bitmap\" name=\"reflectance\">\n      <string name=\"filename\" value=\"t.png\"/>\n      <string name=\"wrap_mode\" value=\"spiral\"/>\n    </texture>\n  </bsdf>\n</scene>")],
            "a.xml:5:39",
            "unknown wrap_mode `spiral`",
        ),
    ] {
        let got = error_at(&files, |p| read(p, &[]));
        assert!(got.starts_with(at) && got.contains(needle), "expected {at} ... {needle}, got {got}");
    }
}

#[test]
fn unsupported_kinds_warn_once_each() {
    let scene = r#"<scene version="3.0.0">
    <shape type="serialized"/>
    <shape type="serialized"/>
    <shape type="cube"><float name="glow" value="1"/></shape>
    <shape type="cube"><float name="glow" value="2"/></shape>
    <integrator type="ptracer"/>
</scene>"#;
    let dir = folder(&[("a.xml", scene)]);
    let desc = read(&dir.path().join("a.xml"), &[]).unwrap();
    let count = |needle: &str| desc.warnings.iter().filter(|w| w.contains(needle)).count();
    assert_eq!(count("serialized"), 1, "{:?}", desc.warnings);
    assert_eq!(count("`glow`"), 1, "{:?}", desc.warnings);
    assert_eq!(count("ptracer"), 1, "{:?}", desc.warnings);
    assert!(
        desc.warnings.iter().all(|w| w.contains("a.xml:")),
        "{:?}",
        desc.warnings
    );
    assert_eq!(desc.shapes.len(), 2);
}

/// A top-level medium referred to by id, one nested as `exterior`, the sensor's medium,
/// the `null` BSDF and `volpath`; bad references and phase parameters name their place.
#[test]
fn media_are_read_where_mitsuba_puts_them() {
    use penumbra_render::integrators::IntegratorKind;
    use penumbra_render::media::{Homogeneous, Medium, MediumInterface};
    use penumbra_render::phase::{HenyeyGreenstein, Phase};
    let scene = r#"<scene version="3.0.0">
    <integrator type="volpathmis"/>
    <medium type="homogeneous" id="fog">
        <rgb name="albedo" value="0.5, 0.25, 1"/>
        <float name="sigma_t" value="2"/>
        <float name="scale" value="0.5"/>
        <phase type="hg"><float name="g" value="0.4"/></phase>
    </medium>
    <sensor type="perspective"><ref id="fog"/></sensor>
    <shape type="sphere">
        <bsdf type="null"/>
        <ref name="interior" id="fog"/>
        <medium type="homogeneous" name="exterior">
            <volume type="constvolume" name="albedo"><float name="value" value="0.5"/></volume>
        </medium>
    </shape>
</scene>"#;
    let dir = folder(&[("a.xml", scene)]);
    let desc = read(&dir.path().join("a.xml"), &[]).unwrap();
    assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
    assert_eq!(desc.render.integrator, IntegratorKind::Volpath);
    assert_eq!(desc.camera_medium, Some(0));
    assert_eq!(
        desc.media[0].medium,
        Medium::Homogeneous(Homogeneous::from_albedo(
            penumbra_core::Rgb::new(0.5, 0.25, 1.0),
            penumbra_core::Rgb::splat(1.0),
            Phase::HenyeyGreenstein(HenyeyGreenstein::new(0.4)),
        ))
    );
    assert_eq!(
        desc.media[1].medium,
        Medium::Homogeneous(Homogeneous::from_albedo(
            penumbra_core::Rgb::splat(0.5),
            penumbra_core::Rgb::splat(1.0),
            Phase::Isotropic,
        ))
    );
    assert_eq!(
        desc.shapes[0].media,
        Some(MediumInterface {
            inside: Some(0),
            outside: Some(1)
        })
    );
    assert!(desc.materials[desc.shapes[0].material.unwrap()].material.is_null());

    for (text, at, needle) in [
        (
            "<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n    <ref name=\"interior\" id=\"nope\"/>\n  </shape>\n</scene>",
            "a.xml:3:",
            "no medium with id `nope`",
        ),
        (
            "<scene version=\"3.0.0\">\n  <medium type=\"homogeneous\">\n    <phase type=\"hg\"><float name=\"g\" value=\"1\"/></phase>\n  </medium>\n</scene>",
            "a.xml:3:",
            "(-1, 1)",
        ),
        (
            "<scene version=\"3.0.0\">\n  <medium type=\"homogeneous\">\n    <rgb name=\"albedo\" value=\"2\"/>\n  </medium>\n</scene>",
            "a.xml:2:",
            "albedo must lie in [0, 1]",
        ),
    ] {
        let got = error_at(&[("a.xml", text)], |p| read(p, &[]));
        assert!(got.starts_with(at) && got.contains(needle), "expected {at} ... {needle}, got {got}");
    }
}

/// A heterogeneous medium over a `.vol` grid: the grid, its scale and its placement by
/// `to_world` (and by the file's box with `use_grid_bbox`); bad grids name their place.
#[test]
fn grid_media_read_vol_files() {
    use crate::formats::vol::{self, VolGrid};
    use glam::UVec3;
    use penumbra_render::media::Medium;
    let scene = |extra: &str| {
        format!(
            r#"<scene version="3.0.0">
    <medium type="heterogeneous" id="cloud">
        <volume type="gridvolume" name="sigma_t">
            <string name="filename" value="g.vol"/>
            <transform name="to_world"><scale value="2"/></transform>{extra}
        </volume>
        <float name="albedo" value="0.8"/>
        <float name="scale" value="10"/>
    </medium>
    <shape type="cube"><bsdf type="null"/><ref name="interior" id="cloud"/></shape>
</scene>"#
        )
    };
    let values: Vec<f32> = (0..8).map(|i| i as f32).collect();
    let grid = VolGrid {
        res: UVec3::new(2, 2, 2),
        channels: 1,
        bbox: [Vec3::splat(-1.0), Vec3::splat(1.0)],
        values,
    };
    let dir = folder(&[
        ("a.xml", &scene("")),
        ("b.xml", &scene("\n<boolean name=\"use_grid_bbox\" value=\"true\"/>")),
    ]);
    vol::write(&dir.path().join("g.vol"), &grid).unwrap();
    let sigma_t_at = |file: &str, p: Vec3| {
        let desc = read(&dir.path().join(file), &[]).unwrap();
        assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
        let Medium::Grid(m) = &desc.media[0].medium else {
            panic!("{:?}", desc.media[0].medium)
        };
        assert_eq!(m.albedo, penumbra_core::Rgb::splat(0.8));
        let point = desc.media[0].medium.at(p);
        point.sigma_a.r + point.sigma_s.r
    };
    // The cell centre of value 7 (x, y and z all high) is (0.75, 0.75, 0.75) of the cube.
    assert!((sigma_t_at("a.xml", Vec3::splat(1.5)) - 70.0).abs() < 1e-3);
    assert!((sigma_t_at("a.xml", Vec3::new(0.5, 0.5, 0.5)) - 0.0).abs() < 1e-3);
    // With the file's box [-1, 1]^3, scaled by 2: the same centre is at (1, 1, 1).
    assert!((sigma_t_at("b.xml", Vec3::splat(1.0)) - 70.0).abs() < 1e-3);

    let mut three = grid.clone();
    three.channels = 3;
    three.values = vec![0.5; 24];
    vol::write(&dir.path().join("rgb.vol"), &three).unwrap();
    let mut negative = grid.clone();
    negative.values[3] = -1.0;
    vol::write(&dir.path().join("neg.vol"), &negative).unwrap();
    let with_file = |file: &str| scene("").replace("g.vol", file);
    for (text, at, needle) in [
        (with_file("none.vol"), "a.xml:4:", "cannot open"),
        (with_file("rgb.vol"), "a.xml:4:", "3 channels"),
        (with_file("neg.vol"), "a.xml:4:", "density 3 is -1"),
        (
            scene("").replace(
                "<float name=\"albedo\" value=\"0.8\"/>",
                "<volume type=\"gridvolume\" name=\"albedo\"><string name=\"filename\" value=\"g.vol\"/></volume>",
            ),
            "a.xml:7:",
            "grid of albedo",
        ),
        (
            scene("<string name=\"filter_type\" value=\"nearest\"/>"),
            "a.xml:5:",
            "filter_type `nearest`",
        ),
    ] {
        let dir2 = folder(&[("a.xml", &text)]);
        for f in ["g.vol", "rgb.vol", "neg.vol"] {
            std::fs::copy(dir.path().join(f), dir2.path().join(f)).unwrap();
        }
        let got = error_at_in(&dir2, "a.xml", |p| read(p, &[]));
        assert!(
            got.starts_with(at) && got.contains(needle),
            "expected {at} ... {needle}, got {got}"
        );
    }
}
