//! The media scenes of `scenes/media/` and the spectral Cornell box against Mitsuba 3's
//! references of them (`tests/data/media/`, `tests/data/spectral/`, made by
//! `scenes/media/make_references.py`: Mitsuba 3.9.1, `llvm_ad_rgb` with `volpath` for
//! media, `llvm_ad_spectral` for spectra, 64x64, 16,384 spp): ours reach at most 1.2 times
//! the relative MSE Mitsuba's own renders reach at equal samples, and each channel's mean
//! lies within 0.5% of the reference's ([`converges`]).

use penumbra::metrics::compare;
use penumbra::scene::image_io::read_image;
use penumbra::scene::read_scene_with;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The number after `"key":` in the reference's JSON notes.
fn number(json: &str, key: &str) -> f64 {
    let at = json.find(&format!("\"{key}\":")).unwrap_or_else(|| panic!("no {key}")) + key.len() + 3;
    let rest = json[at..].trim_start();
    let end = rest.find([',', '\n', '}']).unwrap();
    rest[..end].trim().parse().unwrap()
}

fn converges_to_mitsuba(name: &str) {
    converges(&root().join(format!("scenes/media/{name}.xml")), "media", name, false);
}

/// Our renders of `scene` against Mitsuba's reference `tests/data/{folder}/{name}`: at 256
/// spp with four seeds, as Mitsuba's own relMSE was measured (a single render's relMSE is
/// dominated by its rarest bright samples, and a seed's figure swings by ±20%), the mean
/// of the four within 1.2 times Mitsuba's mean; the four averaged (1,024 spp) have each
/// channel's mean within 0.5% of the reference's.
fn converges(scene: &std::path::Path, folder: &str, name: &str, spectral: bool) {
    let data = root().join("tests/data").join(folder);
    let json = std::fs::read_to_string(data.join(format!("{name}.json"))).unwrap();
    let reference = read_image(&data.join(format!("{name}.exr"))).unwrap();
    let defines = [("res".to_string(), "64".to_string())];
    let mut desc = read_scene_with(scene, &defines).unwrap();
    assert!(desc.warnings.is_empty(), "{name}: {:?}", desc.warnings);
    desc.render.spectral |= spectral;
    let mut sum = vec![penumbra::math::Rgb::BLACK; reference.pixels.len()];
    let mut rel_mse = 0.0;
    for seed in 1..=4 {
        (desc.render.spp, desc.render.seed) = (256, seed);
        let image = penumbra::render(&desc, penumbra::RenderControl::default())
            .unwrap()
            .film
            .image();
        rel_mse += compare(&image, &reference.pixels).rel_mse / 4.0;
        for (s, p) in sum.iter_mut().zip(&image) {
            *s += *p * 0.25;
        }
    }
    let errors = compare(&sum, &reference.pixels);
    let mitsuba = number(&json, "mitsuba_relmse_256spp");
    println!(
        "{name}: relMSE at 256 spp {rel_mse:.3e} (Mitsuba's {mitsuba:.3e}, {:.2}x); 1,024 spp {errors:?}",
        rel_mse / mitsuba
    );
    assert!(rel_mse < 1.2 * mitsuba, "{name}: {rel_mse:.3e} against {mitsuba:.3e}");
    assert!(
        errors.mean_ratio.iter().all(|r| (r - 1.0).abs() < 0.005),
        "{name}: {errors:?}"
    );
}

/// Fog filling the Cornell box: a homogeneous, isotropic medium of coloured albedo
/// behind null boundaries, lit by the box's light through it.
#[test]
fn fog_in_the_cornell_box_converges_to_mitsuba() {
    converges_to_mitsuba("fog-cbox");
}

/// A forward-scattering ball behind a null boundary and a milky glass ball (the medium
/// behind a refracting boundary) in the Cornell box.
#[test]
fn scattering_balls_converge_to_mitsuba() {
    converges_to_mitsuba("media-spheres");
}

/// A heterogeneous cloud (`scenes/media/cloud.vol`, a 40³ density grid read from
/// Mitsuba's `.vol` format, forward Henyey-Greenstein, coloured albedo) behind a null box in
/// the Cornell box: grid media, their majorants and the file reader against Mitsuba.
#[test]
fn a_grid_cloud_converges_to_mitsuba() {
    converges_to_mitsuba("cloud-cbox");
}

/// Mitsuba's spectral Cornell box (`../shared/scenes/mitsuba-cbox/cbox-spectral.xml`:
/// measured reflectance spectra and a sampled emission spectrum) rendered spectrally (the
/// scene's spectra by wavelength ask for it) against Mitsuba's `llvm_ad_spectral`. Skipped
/// with a note where `../shared` is absent.
#[test]
fn the_spectral_cornell_box_converges_to_mitsuba() {
    let scene = root().join("../shared/scenes/mitsuba-cbox/cbox-spectral.xml");
    if !scene.exists() {
        println!(
            "skipped: {} is absent (../shared is not beside the repository)",
            scene.display()
        );
        return;
    }
    converges(&scene, "spectral", "cbox-spectral", false);
}

/// Rough gold and smooth copper spheres (measured η and k by wavelength) in the Cornell
/// box, its RGB walls and light uplifted to spectra (reflectances, and D65 times a smooth
/// spectrum for the light), rendered with `--spectral`, against `llvm_ad_spectral`.
#[test]
fn spectral_metals_and_uplifted_colours_converge_to_mitsuba() {
    converges(
        &root().join("scenes/spectral/metals-cbox.xml"),
        "spectral",
        "metals-cbox",
        true,
    );
}

/// A smooth and a frosted glass sphere in the Cornell box under a white light (caustics
/// through both), its RGB colours uplifted, rendered with `--spectral`, against
/// `llvm_ad_spectral`. (Mitsuba's dielectric takes one index: dispersion itself is checked
/// by the furnace in `tests/volpath.rs`.)
#[test]
fn spectral_glass_converges_to_mitsuba() {
    converges(
        &root().join("scenes/spectral/glass-cbox.xml"),
        "spectral",
        "glass-cbox",
        true,
    );
}
