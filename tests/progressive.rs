//! Long renders the way users run them: progressive passes, a time budget, checkpoints,
//! Ctrl-C, resuming to exactly the uninterrupted image, and AOVs.

mod common;

use common::{penumbra, text};
use penumbra::renderer::driver::Stop;
use penumbra::renderer::{Film, IntegratorKind};
use penumbra::scene::SourceFile;
use penumbra::state::{read_state, write_state};
use penumbra::RenderControl;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};

/// A small path-traced Cornell-like box, 48 x 32, with a splatting filter (so that tiles
/// share pixels) and a glossy sphere.
const SCENE: &str = r#"
[render]
width = 48
height = 32
spp = 12
integrator = "path"
max_depth = 6
sampler = "sobol"
filter = { type = "gaussian", radius = 2.0, sigma = 0.5 }

[camera]
position = [0, 1, 4]
target = [0, 1, 0]
fov = 50

[[material]]
name = "white"
type = "diffuse"
reflectance = 0.7

[[material]]
name = "metal"
type = "conductor"
metal = "Cu"
roughness = 0.2

[[shape]]
type = "quad"
corner = [-2, 0, 2]
edge1 = [4, 0, 0]
edge2 = [0, 0, -4]
material = "white"

[[shape]]
type = "sphere"
center = [0, 0.6, 0]
radius = 0.6
material = "metal"

[[shape]]
type = "quad"
corner = [-0.5, 2.5, -0.5]
edge1 = [1, 0, 0]
edge2 = [0, 0, 1]
material = "white"
emission = 5
"#;

fn desc() -> penumbra::scene::SceneDesc {
    penumbra::scene::formats::native::read(&SourceFile::new("box.toml", SCENE.to_string())).unwrap()
}

fn bits(film: &Film) -> Vec<u64> {
    film.pixels()
        .iter()
        .flat_map(|p| [p.sum[0], p.sum[1], p.sum[2], p.weight])
        .chain(film.splats.iter().flatten().copied())
        .map(f64::to_bits)
        .collect()
}

/// Stopped after any number of passes (by cancelling from the pass callback), saved,
/// read back and resumed, the render ends bit for bit where an uninterrupted one does:
/// for the path tracer, and for bidirectional path tracing, whose splat layer the state
/// keeps too.
#[test]
fn a_resumed_render_equals_an_uninterrupted_one_bit_for_bit() {
    for integrator in [IntegratorKind::Path, IntegratorKind::Bdpt] {
        let mut desc = desc();
        desc.render.integrator = integrator;
        resume_equals_uninterrupted(&desc);
    }
}

fn resume_equals_uninterrupted(desc: &penumbra::scene::SceneDesc) {
    let desc = desc.clone();
    let bdpt = desc.render.integrator == IntegratorKind::Bdpt;
    let full = penumbra::render(&desc, RenderControl::default()).unwrap();
    assert_eq!(full.film.samples_per_pixel, 12);
    assert_eq!(full.stats.stop, Stop::Done);
    assert_eq!(!full.film.splats.is_empty(), bdpt, "splats from bdpt only");
    let dir = tempfile::tempdir().unwrap();
    for stop_after in [1u32, 5, 11] {
        let cancel = AtomicBool::new(false);
        let passes = AtomicU32::new(0);
        let after = |_: &Film| {
            if passes.fetch_add(1, Ordering::SeqCst) + 1 == stop_after {
                cancel.store(true, Ordering::SeqCst);
            }
        };
        let part = penumbra::render(
            &desc,
            RenderControl {
                cancel: &cancel,
                after_pass: Some(&after),
                ..RenderControl::default()
            },
        )
        .unwrap();
        assert_eq!(part.stats.stop, Stop::Cancelled);
        assert_eq!(part.film.samples_per_pixel, stop_after);
        let path = dir.path().join("state");
        write_state(&path, &part.film, 12, 42).unwrap();
        let saved = read_state(&path).unwrap();
        assert_eq!((saved.planned_spp, saved.fingerprint), (12, 42));
        assert!(saved.film == part.film, "the state round-trips exactly");
        let resumed = penumbra::render(
            &desc,
            RenderControl {
                resume: Some(saved.film),
                ..RenderControl::default()
            },
        )
        .unwrap();
        assert_eq!(resumed.stats.samples, (12 - stop_after) as u64 * 48 * 32);
        assert!(
            bits(&resumed.film) == bits(&full.film),
            "stopped after {stop_after}: images differ"
        );
    }
}

#[test]
fn broken_states_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("state");
    let film = penumbra::render(&desc(), RenderControl::default()).unwrap().film;
    write_state(&path, &film, 12, 1).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..bytes.len() - 3]).unwrap();
    assert!(read_state(&path).err().unwrap().to_string().contains("truncated"));
    std::fs::write(&path, b"hello").unwrap();
    assert!(read_state(&path).err().unwrap().to_string().contains("too short"));
    let mut extra = bytes.clone();
    extra.push(0);
    std::fs::write(&path, extra).unwrap();
    assert!(read_state(&path).err().unwrap().to_string().contains("past its end"));
}

/// The AOVs of a known view: a white-ish floor 3 units below the camera, looked at
/// straight down.
#[test]
fn aovs_give_albedo_normal_and_depth_of_the_first_hit() {
    let text = "[render]\nwidth = 8\nheight = 8\nspp = 2\nintegrator = \"path\"\n\
                [camera]\nposition = [0, 3, 0]\ntarget = [0, 0, 0]\nup = [0, 0, -1]\nfov = 10\n\
                [[material]]\nname = \"m\"\ntype = \"diffuse\"\nreflectance = [0.2, 0.4, 0.6]\n\
                [[shape]]\ntype = \"quad\"\ncorner = [-5, 0, 5]\nedge1 = [10, 0, 0]\nedge2 = [0, 0, -10]\nmaterial = \"m\"\n";
    let desc = penumbra::scene::formats::native::read(&SourceFile::new("aov.toml", text.into())).unwrap();
    let result = penumbra::render(
        &desc,
        RenderControl {
            aovs: true,
            ..RenderControl::default()
        },
    )
    .unwrap();
    let aovs = result.film.aov_images().unwrap();
    let centre = 4 * 8 + 4;
    let [r, g, b, nx, ny, nz, depth] = [0, 1, 2, 3, 4, 5, 6].map(|c| aovs[c][centre]);
    assert!((r - 0.2).abs() < 1e-5 && (g - 0.4).abs() < 1e-5 && (b - 0.6).abs() < 1e-5);
    assert!(nx.abs() < 1e-5 && (ny - 1.0).abs() < 1e-5 && nz.abs() < 1e-5);
    // 10 degrees of view: the rays splatted into the centre pixel are within 3 degrees of
    // straight down.
    assert!(depth > 3.0 && depth < 3.0 / (3.0f32.to_radians().cos()), "{depth}");
}

/// The command line: `--time` stops early and saves the state, `--resume` finishes it to
/// the same bytes as an uninterrupted render; a mismatched resume is refused; `--aovs`
/// writes EXR layers and needs an .exr output.
#[test]
fn time_budget_resume_and_aovs_on_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("box.toml"), SCENE).unwrap();
    let full = penumbra(d, &["render", "box.toml", "--spp", "200", "-o", "full.pfm", "-q"]);
    assert!(full.status.success(), "{}", text(&full.stderr));
    let part = penumbra(
        d,
        &["render", "box.toml", "--spp", "200", "--time", "0.05", "-o", "part.pfm"],
    );
    assert!(part.status.success(), "{}", text(&part.stderr));
    assert!(
        text(&part.stderr).contains("time budget spent at"),
        "{}",
        text(&part.stderr)
    );
    assert!(d.join("part.pfm.state").exists());
    // Other settings than the saved render's: refused.
    let wrong = penumbra(
        d,
        &[
            "render",
            "box.toml",
            "--sampler",
            "stratified",
            "--resume",
            "-o",
            "part.pfm",
        ],
    );
    assert_eq!(wrong.status.code(), Some(2));
    assert!(text(&wrong.stderr).contains("another scene"), "{}", text(&wrong.stderr));
    let resumed = penumbra(
        d,
        &["render", "box.toml", "--spp", "200", "--resume", "-o", "part.pfm", "-q"],
    );
    assert!(resumed.status.success(), "{}", text(&resumed.stderr));
    assert_eq!(
        std::fs::read(d.join("full.pfm")).unwrap(),
        std::fs::read(d.join("part.pfm")).unwrap()
    );
    // Resuming what is missing: a clear error.
    let missing = penumbra(d, &["render", "box.toml", "--resume", "-o", "other.pfm"]);
    assert_eq!(missing.status.code(), Some(2));
    assert!(
        text(&missing.stderr).contains("other.pfm.state"),
        "{}",
        text(&missing.stderr)
    );
    let aov = penumbra(
        d,
        &["render", "box.toml", "--spp", "1", "--aovs", "-o", "aov.exr", "-q"],
    );
    assert!(aov.status.success(), "{}", text(&aov.stderr));
    let bytes = std::fs::read(d.join("aov.exr")).unwrap();
    for name in ["albedo.R", "normal.Z", "depth.Z"] {
        assert!(bytes.windows(name.len()).any(|w| w == name.as_bytes()), "{name}");
    }
    let png = penumbra(d, &["render", "box.toml", "--aovs", "-o", "aov.png"]);
    assert_eq!(png.status.code(), Some(2));
    assert!(text(&png.stderr).contains("OpenEXR"), "{}", text(&png.stderr));
}

/// Integrators that keep state of their own (mlt's chains, sppm's pixel statistics, env
/// smc's particles) declare it: a render of theirs stopped by `--time` or checkpointed
/// leaves no state file that could not continue it, `--resume` is refused naming what is
/// not kept, and `--aovs` is refused; a pixel-sampling integrator keeps its state.
#[test]
fn integrators_with_state_of_their_own_leave_no_state_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let env = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/glossy-env.toml");
    let env = env.to_str().unwrap();
    std::fs::write(d.join("box.toml"), SCENE).unwrap();
    let cases: [(&[&str], &str); 4] = [
        (&["box.toml", "--integrator", "mlt"], "Markov chains"),
        (&["box.toml", "--integrator", "sppm"], "pixel statistics"),
        (
            &[env, "--integrator", "env", "--env-sampling", "smc", "--res", "32x24"],
            "particles",
        ),
        (&["box.toml", "--integrator", "path"], ""),
    ];
    for (k, (scene, kept)) in cases.iter().enumerate() {
        let out = format!("o{k}.pfm");
        let mut args = vec!["render"];
        args.extend_from_slice(scene);
        args.extend_from_slice(&[
            "--spp",
            "100000",
            "--time",
            "0.3",
            "--checkpoint",
            "0.01",
            "-q",
            "-o",
            &out,
        ]);
        let r = penumbra(d, &args);
        assert!(r.status.success(), "{scene:?}: {}", text(&r.stderr));
        assert_eq!(d.join(format!("{out}.state")).exists(), kept.is_empty(), "{scene:?}");
        let mut resume = vec!["render"];
        resume.extend_from_slice(scene);
        resume.extend_from_slice(&["--resume", "--time", "0.3", "-q", "-o", &out]);
        let r = penumbra(d, &resume);
        if kept.is_empty() {
            assert!(r.status.success(), "{scene:?}: {}", text(&r.stderr));
            continue;
        }
        assert_eq!(r.status.code(), Some(2), "{scene:?}");
        assert!(text(&r.stderr).contains(kept), "{scene:?}: {}", text(&r.stderr));
        let mut aovs = vec!["render"];
        aovs.extend_from_slice(scene);
        aovs.extend_from_slice(&["--aovs", "-o", "a.exr"]);
        let r = penumbra(d, &aovs);
        assert_eq!(r.status.code(), Some(2), "{scene:?}");
        assert!(text(&r.stderr).contains("--aovs"), "{scene:?}: {}", text(&r.stderr));
    }
}

/// Ctrl-C: the render finishes its pass, writes the image and the state, says how far it
/// got and exits 0; checkpoints have rewritten the image meanwhile.
#[cfg(unix)]
#[test]
fn interrupt_writes_what_is_done_and_exits_zero() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("box.toml"), SCENE).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .current_dir(d)
        .args([
            "render",
            "box.toml",
            "--spp",
            "1000000",
            "--res",
            "96x64",
            "--checkpoint",
            "0.2",
            "-o",
            "long.exr",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait for the first checkpoint.
    let start = std::time::Instant::now();
    while !(d.join("long.exr").exists() && d.join("long.exr.state").exists()) {
        assert!(start.elapsed().as_secs() < 60, "no checkpoint written");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    let mut stderr = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr).unwrap();
    assert_eq!(status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains("interrupted at") && stderr.contains("of 1000000 spp"),
        "{stderr}"
    );
    let saved = read_state(&d.join("long.exr.state")).unwrap();
    assert!(saved.film.samples_per_pixel >= 1);
}
