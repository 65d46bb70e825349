//! The `penumbra` command end to end: the default render, the example scenes, output
//! formats, determinism across thread counts, and every kind of bad input.

mod common;

use common::{penumbra, text};
use std::path::PathBuf;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn default_render_writes_render_png_and_says_where() {
    let dir = tempfile::tempdir().unwrap();
    let out = penumbra(dir.path(), &[]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("wrote render.png"));
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("Mrays/s") && stderr.contains("Msamples/s"),
        "summary line: {stderr}"
    );
    let bytes = std::fs::read(dir.path().join("render.png")).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
}

#[test]
fn example_scenes_render() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = [
        "whitted",
        "cornell",
        "refraction",
        "spheres",
        "box-light",
        "veach-mis",
        "bunny",
        "bunny-10k",
        "teapot-stadium",
    ];
    for scene in scenes {
        let path = repo().join("scenes").join(format!("{scene}.toml"));
        let needs_shared = scene.starts_with("bunny") || scene == "teapot-stadium";
        if needs_shared && !repo().join("../shared/scenes").exists() {
            println!("note: skipping {scene}.toml: ../shared/scenes is not beside the repository");
            continue;
        }
        let png = dir.path().join(format!("{scene}.png"));
        let out = penumbra(
            dir.path(),
            &[
                "render",
                path.to_str().unwrap(),
                "-o",
                png.to_str().unwrap(),
                "--res",
                "80x60",
                "--spp",
                "2",
                "--quiet",
            ],
        );
        assert!(out.status.success(), "{scene}: {}", text(&out.stderr));
        assert!(text(&out.stderr).is_empty(), "--quiet prints nothing on stderr");
        assert!(png.exists());
    }
}

#[test]
fn output_formats_and_thread_count_determinism() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/refraction.toml");
    let run = |out: &str, threads: &str| {
        let o = penumbra(
            dir.path(),
            &[
                "render",
                scene.to_str().unwrap(),
                "-o",
                out,
                "--res",
                "64x36",
                "--threads",
                threads,
                "-q",
            ],
        );
        assert!(o.status.success(), "{}", text(&o.stderr));
        std::fs::read(dir.path().join(out)).unwrap()
    };
    let one = run("one.pfm", "1");
    let two = run("two.pfm", "2");
    assert_eq!(one, two, "--threads 1 and --threads 2 give the same image");
    assert!(one.starts_with(b"PF\n64 36\n"));
    let exr = run("img.exr", "2");
    assert_eq!(&exr[..4], &[0x76, 0x2f, 0x31, 0x01], "OpenEXR magic number");
}

/// Writes `scene` to a file, renders it, and expects exit code 2 with an error naming
/// `line` of the file and containing `needle`.
fn expect_scene_error(scene: &str, line: usize, needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), scene).unwrap();
    std::fs::write(
        dir.path().join("broken.ply"),
        b"ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2",
    )
    .unwrap();
    let out = penumbra(
        dir.path(),
        &["render", "scene.toml", "-o", "out.png", "--res", "8x8", "-q"],
    );
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{needle}: {stderr}");
    assert!(
        stderr.contains(&format!("scene.toml:{line}:")),
        "{needle}: no line {line} in {stderr}"
    );
    assert!(stderr.contains(needle), "expected `{needle}` in {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!dir.path().join("out.png").exists(), "no image for a failed render");
}

#[test]
fn bad_scenes_name_the_line_and_exit_2() {
    expect_scene_error("[render]\nwidth = 3\n[camera\nfov = 3\n", 3, "TOML syntax error");
    expect_scene_error("[camera]\nfov = 30\nfovv = 30\n", 3, "unknown key `fovv`");
    expect_scene_error("[[shape]]\ntype = \"cylinder\"\n", 2, "unknown shape type `cylinder`");
    expect_scene_error(
        "[[shape]]\ntype = \"sphere\"\nradius = \"big\"\n",
        3,
        "expected a number, found string",
    );
    expect_scene_error("[[shape]]\ntype = \"sphere\"\n\nradius = -1\n", 4, "must be positive");
    expect_scene_error("[camera]\nposition = [0, 0, 5]\nup = [0, 0, 0]\n", 3, "zero-length");
    expect_scene_error(
        "[camera]\nposition = [0, 5, 0]\ntarget = [0, 0, 0]\n",
        1,
        "parallel to `up`",
    );
    expect_scene_error(
        "[[material]]\nname = \"red\"\n[[shape]]\ntype = \"sphere\"\nmaterial = \"blue\"\n",
        5,
        "no material named `blue`",
    );
    expect_scene_error(
        "[[shape]]\ntype = \"mesh\"\nfile = \"missing.obj\"\n",
        3,
        "mesh file not found",
    );
    expect_scene_error(
        "[[shape]]\ntype = \"mesh\"\nfile = \"broken.ply\"\n",
        3,
        "cannot load mesh",
    );
    expect_scene_error("[render]\nspp = 0\n", 2, "expected a whole number from 1 to");
    expect_scene_error("[render]\nwidth = 100000\n", 2, "from 1 to 65536");
    expect_scene_error("[render]\nmax_depth = 1000\n", 2, "from 0 to 256");
    expect_scene_error("[render]\nrr_depth = 0\n", 2, "from 1 to 256");
    expect_scene_error("[render]\nwidth = 60000\nheight = 60000\n", 3, "pixels");
    expect_scene_error("[[shape]]\ntype = \"sphere\"\nradius = 1e39\n", 3, "finite");
    expect_scene_error("[[shape]]\ntype = \"sphere\"\nradius = 1e-40\n", 1, "degenerate");
    expect_scene_error(
        "[[shape]]\ntype = \"mesh\"\npositions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\nindices = [[0, 1, -2]]\n",
        4,
        "expected a whole number",
    );
    expect_scene_error(
        "[[shape]]\ntype = \"quad\"\nedge1 = [1, 0, 0]\nedge2 = [2, 0, 0]\n",
        4,
        "must not be parallel",
    );
    expect_scene_error(
        "[[light]]\ntype = \"spot\"\nposition = [0, 1, 0]\nfalloff_start = 40\n",
        4,
        "`falloff_start` must be",
    );
    expect_scene_error(
        "[[light]]\ntype = \"point\"\nposition = [1, 2]\n",
        3,
        "expected 3 numbers",
    );
    expect_scene_error(
        "[[shape]]\ntype = \"instance\"\nmesh = \"bunny\"\n",
        3,
        "no mesh named `bunny`",
    );
}

#[test]
fn bad_arguments_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    for (args, needle) in [
        (vec!["render", "--spp", "0"], "--spp"),
        (vec!["render", "--res", "0x10"], "--res"),
        (vec!["render", "--res", "wide"], "--res"),
        (vec!["render", "--bogus"], "--bogus"),
        (vec!["render", "--threads", "0"], "--threads"),
        (vec!["render", "--max-depth", "300"], "--max-depth"),
        (vec!["render", "--rr-depth", "0"], "--rr-depth"),
        (
            vec![
                "bench",
                "render",
                "scenes/cbox-mitsuba.toml",
                "--rr-depth",
                "2",
                "--mitsuba",
            ],
            "not be comparable",
        ),
        (vec!["render", "--exposure", "NaN"], "--exposure"),
        (vec!["render", "--res", "60000x60000"], "pixels"),
        (vec!["render", "-o", "image.bmp"], "unknown image format"),
        (vec!["render", "--integrator", "magic"], "unknown value `magic`"),
        (vec!["render", "does-not-exist.toml"], "cannot read does-not-exist.toml"),
        (vec!["render", "scene.obj"], "scene.obj"),
        (vec!["render", "scene.fbx"], "unsupported scene format"),
        (vec!["render", "scene.gltf"], "cannot read scene.gltf"),
        (vec!["render", "-D", "spp=4"], "no scene file was given"),
        (vec!["render", "scene.xml", "-D", "bad-name=4"], "not a parameter name"),
        (
            vec!["render", "scenes/cornell.toml", "-D", "spp=4"],
            "-D sets parameters",
        ),
        (vec!["render", "--light-samples", "0"], "at least one shadow ray"),
        (
            vec!["render", "--light-sampling", "grid", "--light-samples", "3"],
            "square number",
        ),
        (vec!["render", "--light-sampling", "random"], "unknown value `random`"),
        (vec!["render", "--mis-heuristic", "max"], "unknown value `max`"),
        (vec!["render", "--light-selection", "some"], "unknown value `some`"),
    ] {
        let out = penumbra(dir.path(), &args);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: expected `{needle}` in {stderr}");
        assert!(!stderr.contains("panicked"));
    }
    assert!(!dir.path().join("render.png").exists());
}

#[test]
fn unwritable_output_is_an_internal_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = penumbra(
        dir.path(),
        &["render", "-o", "no/such/dir/out.png", "--res", "8x8", "-q"],
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    assert!(text(&out.stderr).contains("cannot write no/such/dir/out.png"));
}

#[test]
fn help_documents_every_flag() {
    let dir = tempfile::tempdir().unwrap();
    let out = penumbra(dir.path(), &["render", "--help"]);
    assert!(out.status.success());
    let help = text(&out.stdout);
    for flag in [
        "--output",
        "--spp",
        "--threads",
        "--seed",
        "--integrator",
        "--max-depth",
        "--res",
        "--quiet",
        "--exposure",
        "--light-sampling",
        "--light-samples",
        "--mis-heuristic",
        "--light-selection",
        "--sampler",
        "--camera",
    ] {
        assert!(help.contains(flag), "{flag} missing from --help");
    }
}

#[test]
fn every_accelerator_renders_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    // (The bunny scenes would take minutes with `list`; the agreement tests cover meshes.)
    for scene in ["whitted", "cornell", "refraction", "spheres", "box-light", "veach-mis"] {
        let path = repo().join("scenes").join(format!("{scene}.toml"));
        let images: Vec<Vec<u8>> = ["list", "bvh", "grid", "nested-grid", "octree", "octree-keep", "kdtree"]
            .iter()
            .map(|accel| {
                let out = format!("{scene}-{accel}.pfm");
                let o = penumbra(
                    dir.path(),
                    &[
                        "render",
                        path.to_str().unwrap(),
                        "-o",
                        &out,
                        "--res",
                        "48x32",
                        "--accel",
                        accel,
                        "-q",
                    ],
                );
                assert!(o.status.success(), "{}", text(&o.stderr));
                std::fs::read(dir.path().join(out)).unwrap()
            })
            .collect();
        assert!(
            images.windows(2).all(|w| w[0] == w[1]),
            "{scene}: accelerators disagree"
        );
    }
}

#[test]
fn bench_accel_races_every_accelerator_and_writes_cost_maps() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/whitted.toml");
    let maps = dir.path().join("maps/new");
    let out = penumbra(
        dir.path(),
        &[
            "bench",
            "accel",
            scene.to_str().unwrap(),
            "--repeats",
            "1",
            "--aov",
            "cost",
            "--out-dir",
            maps.to_str().unwrap(),
        ],
    );
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", text(&out.stderr));
    for name in ["list", "bvh", "grid", "nested-grid", "octree", "octree-keep", "kdtree"] {
        assert!(
            stdout.lines().any(|l| l.starts_with(&format!("{name} "))),
            "{name}: {stdout}"
        );
        let png = std::fs::read(maps.join(format!("cost-{name}.png"))).unwrap();
        assert_eq!(&png[1..4], b"PNG");
    }
}

#[test]
fn bench_accel_counts_hits_that_differ_from_the_expected_ones() {
    // A unit square of two triangles; four rays down the z axis, two through the square and
    // two beside it. The expected-hit file gets one answer wrong on purpose.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("square.obj"),
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    let rays: [[f32; 6]; 4] = [
        [0.7, 0.2, 2.0, 0.0, 0.0, -1.0],
        [0.2, 0.7, 3.0, 0.0, 0.0, -1.0],
        [2.0, 2.0, 2.0, 0.0, 0.0, -1.0],
        [-1.0, 0.5, 2.0, 0.0, 0.0, -1.0],
    ];
    let bytes: Vec<u8> = rays.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
    std::fs::write(dir.path().join("rays_four.f32"), bytes).unwrap();
    // Right: triangle 0 at t 2, triangle 1 at t 3, a miss; wrong: a hit for the last miss.
    let hits: [(i32, f32); 4] = [(0, 2.0), (1, 3.0), (-1, 0.0), (0, 2.0)];
    let bytes: Vec<u8> = hits
        .iter()
        .flat_map(|(p, t)| p.to_le_bytes().into_iter().chain(t.to_le_bytes()))
        .collect();
    std::fs::write(dir.path().join("hits_four.bin"), bytes).unwrap();
    let out = penumbra(
        dir.path(),
        &[
            "bench",
            "accel",
            "square.obj",
            "--rays",
            "rays_four.f32",
            "--repeats",
            "1",
        ],
    );
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", text(&out.stderr));
    let rows: Vec<&str> = stdout
        .lines()
        .filter(|l| l.split_whitespace().any(|w| w == "four") && !l.contains("primitives"))
        .collect();
    assert_eq!(rows.len(), 7, "{stdout}");
    for row in rows {
        assert!(
            row.trim_end().ends_with(" 1") || row.contains(" 1 ("),
            "one mismatch: {row}"
        );
    }
}

#[test]
fn bench_render_reports_speed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/box-light.toml");
    let out = penumbra(
        dir.path(),
        &[
            "bench",
            "render",
            scene.to_str().unwrap(),
            "--spp",
            "1",
            "--repeats",
            "2",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("Msamples/s best") && stdout.contains("rays per sample"),
        "{stdout}"
    );
}

/// `--ref` measures the benchmark's image: against a render of the same scene, seed, sampler
/// and spp it must be exactly zero; a mismatched size and an unknown sampler are errors.
#[test]
fn bench_render_measures_its_error_against_a_reference() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/box-light.toml");
    let scene = scene.to_str().unwrap();
    let reference = dir.path().join("ref.exr");
    let args = [
        "render",
        scene,
        "--spp",
        "2",
        "--sampler",
        "sobol",
        "-o",
        reference.to_str().unwrap(),
    ];
    let out = penumbra(dir.path(), &args);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let bench = |extra: &[&str]| {
        let mut args = vec!["bench", "render", scene, "--spp", "2", "--repeats", "1"];
        args.extend_from_slice(extra);
        penumbra(dir.path(), &args)
    };
    let out = bench(&["--sampler", "sobol", "--ref", reference.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("relMSE against the reference: 0.0000e0"), "{stdout}");
    let out = bench(&["--sampler", "independent", "--ref", reference.to_str().unwrap()]);
    let stdout = text(&out.stdout);
    assert!(
        out.status.success() && stdout.contains("relMSE against the reference") && !stdout.contains("0.0000e0"),
        "{stdout}"
    );
    let out = bench(&["--sampler", "nope"]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("unknown sampler \"nope\""),
        "{}",
        text(&out.stderr)
    );
    let small = repo().join("scenes/cbox-mitsuba.toml");
    let out = penumbra(
        dir.path(),
        &[
            "bench",
            "render",
            small.to_str().unwrap(),
            "--spp",
            "1",
            "--repeats",
            "1",
            "--ref",
            reference.to_str().unwrap(),
        ],
    );
    assert!(!out.status.success(), "{}", text(&out.stdout));
    assert!(text(&out.stderr).contains("the reference is"), "{}", text(&out.stderr));
}

/// A bare `.ply` or `.obj` renders framed by the default camera: the mesh covers the
/// image's centre (lit, brighter than nothing) and stays off its corners (the sky);
/// broken meshes exit 2 naming the file and the fault.
#[test]
fn bare_meshes_render_framed_and_broken_ones_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    // A tetrahedron far from the origin (ASCII PLY with an extra vertex property and a
    // quad face) and a cube of quads (OBJ, `f v//vn` syntax).
    let ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float confidence\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n\
               50 10 -3 1\n52 10 -3 1\n51 12 -3 1\n51 11 -1 1\n3 0 1 2\n3 0 1 3\n3 1 2 3\n3 2 0 3\n";
    let mut obj = String::new();
    for k in 0..8 {
        obj += &format!("v {} {} {}\n", k & 1, k >> 1 & 1, k >> 2 & 1);
    }
    obj += "vn 0 0 1\n";
    for f in ["1 2 4 3", "5 7 8 6", "1 5 6 2", "3 4 8 7", "1 3 7 5", "2 6 8 4"] {
        obj += &format!(
            "f {}\n",
            f.split(' ').map(|v| format!("{v}//1")).collect::<Vec<_>>().join(" ")
        );
    }
    for (name, body) in [("tetra.ply", ply), ("cube.obj", obj.as_str())] {
        let mesh = dir.path().join(name);
        std::fs::write(&mesh, body).unwrap();
        let out_path = dir.path().join(format!("{name}.pfm"));
        let out = penumbra(
            dir.path(),
            &[
                "render",
                mesh.to_str().unwrap(),
                "-o",
                out_path.to_str().unwrap(),
                "--res",
                "64x48",
                "--spp",
                "4",
            ],
        );
        assert!(out.status.success(), "{name}: {}", text(&out.stderr));
        let image = penumbra::scene::image_io::read_image(&out_path).unwrap();
        let at = |x: u32, y: u32| image.pixels[(y * image.width + x) as usize];
        // The sky's radiance is 0.3; the filter's weights sum to it within rounding.
        let is_sky = |c: penumbra::math::Rgb| [c.r, c.g, c.b].iter().all(|v| (v - 0.3).abs() < 1e-4);
        for (x, y) in [(0, 0), (63, 0), (0, 47), (63, 47)] {
            assert!(is_sky(at(x, y)), "{name}: corner ({x}, {y}) {:?}", at(x, y));
        }
        let centre = at(32, 24);
        assert!(
            !is_sky(centre) && centre.r > 0.05,
            "{name}: the mesh at the centre, {centre:?}"
        );
    }
    for (name, body, needle) in [
        ("missing.ply", None, "missing.ply"),
        ("range.ply", Some(ply.replace("3 2 0 3\n", "3 2 0 9\n")), "range.ply"),
        ("cut.ply", Some(ply[..ply.len() - 20].to_string()), "cut.ply"),
        ("empty.obj", Some("# nothing\n".to_string()), "no faces"),
    ] {
        let mesh = dir.path().join(name);
        if let Some(body) = body {
            std::fs::write(&mesh, body).unwrap();
        }
        let out = penumbra(dir.path(), &["render", mesh.to_str().unwrap(), "-o", "x.png"]);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
        assert!(stderr.contains(needle), "{name}: expected `{needle}` in {stderr}");
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
    }
}

/// `--camera N` picks one of a glTF file's cameras (the shared `Cameras.gltf` has a
/// perspective and an orthographic one); one past the last is a clear error.
#[test]
fn a_gltf_camera_can_be_chosen() {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes/gltf-Cameras/Cameras.gltf");
    if !scene.exists() {
        println!(
            "note: skipping: {} is not there (../shared is not beside the repository)",
            scene.display()
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let s = scene.to_str().unwrap();
    let mut images = Vec::new();
    for k in ["0", "1"] {
        let out = penumbra(
            dir.path(),
            &[
                "render", s, "--camera", k, "--spp", "2", "--res", "32x32", "-o", "c.pfm",
            ],
        );
        assert!(out.status.success(), "{}", text(&out.stderr));
        images.push(std::fs::read(dir.path().join("c.pfm")).unwrap());
    }
    assert_ne!(images[0], images[1], "the two cameras see the square differently");
    let out = penumbra(dir.path(), &["render", s, "--camera", "2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("--camera 2: the scene defines 2 cameras (0 to 1)"));
}

/// A Mitsuba scene: a sphere made of `bsdf` under a constant sky, 16x16 pixels.
fn sphere_of(bsdf: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
<sensor type="perspective"><float name="fov" value="40"/>
<transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
<film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>
<shape type="sphere">
{bsdf}
</shape>
<emitter type="constant"><rgb name="radiance" value="1"/></emitter>
</scene>
"#
    )
}

/// A balanced tree of `blendbsdf`s over `n` smooth glasses of indices 1.3, 1.4, ...
fn blended_glasses(n: usize, first: usize) -> String {
    if n == 1 {
        return format!(
            r#"<bsdf type="dielectric"><float name="int_ior" value="{}"/></bsdf>"#,
            1.3 + 0.1 * first as f32
        );
    }
    let half = n / 2;
    format!(
        r#"<bsdf type="blendbsdf"><float name="weight" value="{}"/>{}{}</bsdf>"#,
        (n - half) as f32 / n as f32,
        blended_glasses(half, first),
        blended_glasses(n - half, first + half)
    )
}

#[test]
fn blends_of_many_glasses_render_with_every_integrator() {
    // Eight glasses (nine specular rays) used to panic the Whitted integrator; twenty
    // (21 rays) drop the weakest with a warning; every integrator renders both.
    let dir = tempfile::tempdir().unwrap();
    for (n, warns) in [(8, false), (20, true)] {
        std::fs::write(dir.path().join("blend.xml"), sphere_of(&blended_glasses(n, 0))).unwrap();
        for integrator in ["whitted", "direct", "path", "bdpt", "photon"] {
            let out = penumbra(
                dir.path(),
                &[
                    "render",
                    "blend.xml",
                    "-o",
                    "out.exr",
                    "--spp",
                    "2",
                    "--integrator",
                    integrator,
                ],
            );
            let stderr = text(&out.stderr);
            assert!(out.status.success(), "{n} glasses, {integrator}: {stderr}");
            let warned = stderr.contains("distinct perfectly specular directions");
            if integrator == "whitted" {
                assert_eq!(warned, warns, "{n} glasses, {integrator}: {stderr}");
            }
        }
    }
    // Blends nested deeper than the renderer allows are refused with the shape's line.
    let mut deep = blended_glasses(1, 0);
    for _ in 0..40 {
        deep = format!(
            r#"<bsdf type="blendbsdf"><float name="weight" value="0.5"/>{deep}{}</bsdf>"#,
            blended_glasses(1, 1)
        );
    }
    std::fs::write(dir.path().join("deep.xml"), sphere_of(&deep)).unwrap();
    let out = penumbra(dir.path(), &["render", "deep.xml", "-o", "out.png", "-q"]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("deep.xml:6:") && stderr.contains("nests"), "{stderr}");
}

/// The media test scenes render with `volpath` (the integrator they name) without a
/// warning; another integrator renders their media as vacuum and says so.
#[test]
fn media_scenes_render_and_other_integrators_say_they_ignore_media() {
    let dir = tempfile::tempdir().unwrap();
    for (integrator, warned) in [(None, false), (Some("path"), true)] {
        let scene = repo().join("scenes/media/fog-cbox.xml");
        let png = dir.path().join("fog.png");
        let mut args = vec![
            "render",
            scene.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--spp",
            "2",
            "-D",
            "res=16",
        ];
        if let Some(name) = integrator {
            args.extend(["--integrator", name]);
        }
        let out = penumbra(dir.path(), &args);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let stderr = text(&out.stderr);
        assert_eq!(stderr.contains("as vacuum"), warned, "{integrator:?}: {stderr}");
        assert!(png.exists());
    }
}
