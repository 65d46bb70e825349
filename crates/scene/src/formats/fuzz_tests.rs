//! Robustness of the readers on malformed input, a bounded fuzz run in every test run
//! (proptest, fixed seed): each reader gets valid scenes cut short, with bytes flipped,
//! slices repeated and stray tokens inserted, and must answer with a scene or an error,
//! never a panic or a hang. Crashers found are kept as cases in `regressions` below.

use super::read_scene;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

const MITSUBA: &str = r#"<scene version="3.0.0">
    <default name="spp" value="4"/>
    <sensor type="perspective"><float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
    </sensor>
    <bsdf type="roughplastic" id="p"><rgb name="diffuse_reflectance" value="0.5, 0.2, 0.1"/></bsdf>
    <shape type="rectangle"><transform name="to_world"><scale value="2"/><rotate x="1" angle="-90"/></transform><ref id="p"/></shape>
    <shape type="sphere"><float name="radius" value="0.3"/><emitter type="area"><spectrum name="radiance" value="400:1, 700:2"/></emitter></shape>
    <emitter type="constant"><rgb name="radiance" value="0.1"/></emitter>
</scene>"#;

const PBRT: &str = r#"LookAt 0 1 5  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" 8 "integer yresolution" [ 8 ]
Sampler "sobol" "integer pixelsamples" 4
WorldBegin
MakeNamedMaterial "m" "string type" "coateddiffuse" "rgb reflectance" [ 0.5 0.2 0.1 ] "float roughness" 0.1
AttributeBegin
  AreaLightSource "diffuse" "blackbody L" [ 5000 ]
  Translate 0 2 0
  Shape "sphere" "float radius" 0.3
AttributeEnd
NamedMaterial "m"
Shape "trianglemesh" "point3 P" [ -1 0 -1  1 0 -1  1 0 1  -1 0 1 ] "integer indices" [ 0 1 2 0 2 3 ]
ObjectBegin "o"
Shape "disk" "float radius" 0.5
ObjectEnd
ObjectInstance "o"
"#;

const PLY: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n4 0 2 3 1\n";

const OBJ: &str = "mtllib none.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nusemtl a\nf 1/1/1 2/1/1 3/1/1 4/1/1\nusemtl b\nf 1/1/1 3/1/1 4/1/1\n";

const NATIVE: &str = "[render]\nwidth = 8\nheight = 8\nspp = 2\nintegrator = \"path\"\n\n[[material]]\nname = \"m\"\ntype = \"diffuse\"\nreflectance = [0.5, 0.5, 0.5]\n\n[[shape]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\nemission = [1, 1, 1]\n";

/// One malformation of `text`.
fn mutate(text: &'static [u8]) -> impl Strategy<Value = Vec<u8>> {
    let len = text.len();
    prop_oneof![
        (0..len).prop_map(move |cut| text[..cut].to_vec()),
        prop::collection::vec((0..len, any::<u8>()), 1..6).prop_map(move |flips| {
            let mut b = text.to_vec();
            for (i, v) in flips {
                b[i] = v;
            }
            b
        }),
        (0..len, 0..len, 1..4usize).prop_map(move |(a, b, times)| {
            let (lo, hi) = (a.min(b), a.max(b));
            let mut out = text[..hi].to_vec();
            for _ in 0..times {
                out.extend_from_slice(&text[lo..hi]);
            }
            out.extend_from_slice(&text[hi..]);
            out
        }),
        (
            0..len,
            prop::sample::select(vec![
                "[",
                "]",
                "\"",
                "<",
                "/>",
                "-1",
                "1e39",
                "nan",
                "4294967296",
                "99999999999",
                " Shape ",
                "<include filename=\"x.xml\"/>",
                "element vertex 1000000000000\n",
                "f 9 9 9\n",
                "$spp",
                "65535",
                "\"mode\": 6, ",
                "\"children\": [0], "
            ])
        )
            .prop_map(move |(at, tok)| {
                let mut b = text[..at].to_vec();
                b.extend_from_slice(tok.as_bytes());
                b.extend_from_slice(&text[at..]);
                b
            }),
    ]
}

/// Reads `bytes` as a file with extension `ext`: a scene or an error, never a panic.
fn read_as(ext: &str, bytes: &[u8]) -> Result<(), TestCaseError> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("scene.{ext}"));
    std::fs::write(&path, bytes).unwrap();
    if let Ok(desc) = read_scene(&path) {
        // What reads must also build or fail cleanly.
        let _ = crate::build_scene(&desc);
    }
    Ok(())
}

/// Runs `cases` malformations of `seed_text` through the reader of `ext`; returns the
/// number of inputs tried.
fn fuzz(ext: &str, seed_text: &'static [u8], cases: u32) -> u32 {
    assert!(read_scene_ok(ext, seed_text), "the unmutated {ext} seed must read");
    let config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner = TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]));
    runner.run(&mutate(seed_text), |bytes| read_as(ext, &bytes)).unwrap();
    cases
}

fn read_scene_ok(ext: &str, text: &[u8]) -> bool {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("scene.{ext}"));
    std::fs::write(&path, text).unwrap();
    read_scene(&path).is_ok()
}

#[test]
fn readers_survive_malformed_input() {
    // The glTF seeds: the tests' quad with a light and a camera, its buffer a data URI
    // (so that flipped bytes reach the accessors), and as a GLB.
    let gltf = |uri: &str| {
        super::gltf::tests::quad_gltf(
            uri,
            r#", "children": [1]}, {"camera": 0, "translation": [0, 0, 3]"#,
            r#"{"pbrMetallicRoughness": {"metallicFactor": 0.5}, "emissiveFactor": [1, 1, 1]}"#,
            r#""cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}],"#,
        )
    };
    let buffer = super::gltf::tests::quad_buffer();
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::Engine::encode(&base64::engine::general_purpose::STANDARD, &buffer)
    );
    let gltf_text: &'static [u8] = gltf(&uri).into_bytes().leak();
    let glb: &'static [u8] =
        super::gltf::tests::glb(&gltf(&uri).replace(&format!(r#", "uri": "{uri}""#), ""), &buffer).leak();
    for (ext, seed) in [
        ("xml", MITSUBA.as_bytes()),
        ("pbrt", PBRT.as_bytes()),
        ("ply", PLY.as_bytes()),
        ("obj", OBJ.as_bytes()),
        ("toml", NATIVE.as_bytes()),
        ("gltf", gltf_text),
        ("glb", glb),
    ] {
        let n = fuzz(ext, seed, 1000);
        println!("{ext}: {n} malformed inputs, no panic");
    }
}

/// Crashers found, kept: each must now read to a scene or a clean error. The coverage-guided
/// fuzzer's (`cargo fuzz`, see fuzz/) are the files under fuzz/regressions/<target>/.
#[test]
fn regressions() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/regressions");
    let mut n = 0;
    for (target, ext) in [
        ("gltf", "gltf"),
        ("glb", "glb"),
        ("mitsuba", "xml"),
        ("pbrt", "pbrt"),
        ("ply", "ply"),
        ("obj", "obj"),
        ("native", "toml"),
    ] {
        let Ok(files) = std::fs::read_dir(root.join(target)) else {
            continue;
        };
        for f in files {
            let bytes = std::fs::read(f.unwrap().path()).unwrap();
            read_as(ext, &bytes).unwrap();
            n += 1;
        }
    }
    assert!(n >= 2, "the kept crashers are missing from {}", root.display());
    // tobj overflowed multiplying a negative texture-coordinate index gone past the start
    // (found with the token 65535 inserted after a `-`): now refused, located, before tobj.
    let obj = OBJ.replace("f 1/1/1 3/1/1 4/1/1", "f 1/1/1 3/-65535/1 4/1/1");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.obj");
    std::fs::write(&path, &obj).unwrap();
    let e = read_scene(&path).expect_err("out of range").to_string();
    assert!(
        e.contains("line 11, column 9: texture coordinate index -65535 is out of range: 1 defined before it"),
        "{e}"
    );
    // A malformed number is located too (tobj's own error has no place).
    std::fs::write(&path, OBJ.replace("v 1 1 0", "v 1 1e 0")).unwrap();
    let e = read_scene(&path).expect_err("not a number").to_string();
    assert!(
        e.contains("line 4, column 5: `1e` in a `v` line is not a number"),
        "{e}"
    );
}
