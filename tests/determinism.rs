//! The same scene, seed and sample count give the same image for any thread count and
//! tile order. (With filters wider than a pixel, samples are splatted into neighbouring
//! pixels, so a pixel's sum depends on how tiles group its neighbours: the tile size is
//! then part of the image's definition; it is fixed by the driver, not by the user.)

use penumbra::math::simd::{self, Level};
use penumbra::math::{Rgb, SamplerKind};
use penumbra::renderer::integrators::IntegratorOptions;
use penumbra::renderer::{render, Film, Integrator, RayCounts, RenderOptions, Scene};
use penumbra::scene::{build_scene, SceneDesc, SourceFile};

fn render_with(threads: usize, tile_size: u32, seed: u64) -> Film {
    let mut desc = penumbra::default_scene();
    desc.render.width = 96;
    desc.render.height = 64;
    render_desc(&desc, threads, tile_size, seed)
}

/// The default scene with a filter no wider than a pixel: each pixel gets its own samples only.
fn render_narrow(threads: usize, tile_size: u32) -> Film {
    let mut desc = penumbra::default_scene();
    desc.render.width = 96;
    desc.render.height = 64;
    desc.render.filter = penumbra::renderer::Filter::Tent { radius: 0.5 };
    render_desc(&desc, threads, tile_size, 3)
}

fn render_desc(desc: &SceneDesc, threads: usize, tile_size: u32, seed: u64) -> Film {
    let scene = build_scene(desc).unwrap();
    let integrator = desc.render.integrator.create(IntegratorOptions {
        direct: desc.render.direct,
        ..IntegratorOptions::default()
    });
    let options = RenderOptions {
        spp: 4,
        seed,
        tile_size,
        sampler: desc.render.sampler,
        ..RenderOptions::default()
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let film = Film::new(scene.width, scene.height, false);
    pool.install(|| render(&scene, integrator.as_ref(), &options, film, &(), &cancel, &mut |_| {}))
        .film
}

/// `scenes/NAME` at `width` x `height`.
fn repository_scene(name: &str, width: u32, height: u32) -> SceneDesc {
    let path = format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR"));
    let file = SourceFile::new(&path, std::fs::read_to_string(&path).unwrap());
    let mut desc = penumbra::scene::formats::native::read(&file).unwrap();
    desc.render.width = width;
    desc.render.height = height;
    desc
}

#[test]
fn identical_for_any_thread_count_and_tiling() {
    let reference = render_with(1, 16, 3);
    assert_eq!(reference, render_with(2, 16, 3), "1 vs 2 threads");
    assert_eq!(render_narrow(1, 16), render_narrow(2, 7), "16 vs 7 pixel tiles");
    assert_ne!(
        reference,
        render_with(2, 16, 4),
        "a different seed gives a different image"
    );
}

#[test]
fn direct_lighting_is_identical_for_any_thread_count() {
    let mut desc = repository_scene("box-light.toml", 80, 60);
    for sampler in penumbra::math::SamplerKind::ALL {
        desc.render.sampler = sampler;
        let reference = render_desc(&desc, 1, 16, 5);
        assert_eq!(reference, render_desc(&desc, 2, 16, 5), "{sampler:?}: 1 vs 2 threads");
    }
}

/// Returns NaN for some samples and infinity for others, 1 for the rest.
struct Broken;

impl Integrator for Broken {
    fn li(
        &self,
        _: &Scene,
        _: &penumbra::math::Ray,
        s: &mut penumbra::math::PixelSampler,
        _: &mut RayCounts,
        _: &mut Vec<penumbra::renderer::integrators::Splat>,
    ) -> Rgb {
        match s.next_1d() {
            u if u < 0.1 => Rgb::splat(f32::NAN),
            u if u < 0.2 => Rgb::new(1.0, f32::INFINITY, 0.0),
            _ => Rgb::WHITE,
        }
    }
}

#[test]
fn the_film_refuses_nan_and_infinite_samples_and_counts_them() {
    let mut desc = penumbra::default_scene();
    desc.render.width = 32;
    desc.render.height = 32;
    let scene = build_scene(&desc).unwrap();
    let options = RenderOptions {
        spp: 8,
        ..RenderOptions::default()
    };
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let film = Film::new(scene.width, scene.height, false);
    let film = render(&scene, &Broken, &options, film, &(), &cancel, &mut |_| {}).film;
    let total = 32 * 32 * 8;
    // About 20% of the samples are broken (binomial: 1638 +- 36).
    assert!((1400..1900).contains(&film.rejected), "{} rejected", film.rejected);
    assert_eq!(film.samples(), total, "every sample is counted, rejected or not");
    for p in film.image() {
        let white = (p.r - 1.0).abs() < 1e-6 && p.r == p.g && p.g == p.b;
        assert!(white || p == Rgb::BLACK, "{p:?}: a broken sample leaked into the image");
    }
}

/// The same radiance everywhere.
struct Constant;

impl Integrator for Constant {
    fn li(
        &self,
        _: &Scene,
        _: &penumbra::math::Ray,
        _: &mut penumbra::math::PixelSampler,
        _: &mut RayCounts,
        _: &mut Vec<penumbra::renderer::integrators::Splat>,
    ) -> Rgb {
        Rgb::new(0.25, 0.5, 2.0)
    }
}

#[test]
fn splatting_reproduces_a_constant_image_to_the_borders() {
    for filter in [
        penumbra::renderer::Filter::default(),
        penumbra::renderer::Filter::Gaussian {
            radius: 2.0,
            sigma: 0.5,
        },
        penumbra::renderer::Filter::Tent { radius: 1.0 },
        penumbra::renderer::Filter::Box { radius: 1.5 },
    ] {
        let mut desc = penumbra::default_scene();
        desc.render.width = 37;
        desc.render.height = 21;
        desc.render.filter = filter;
        let scene = build_scene(&desc).unwrap();
        let options = RenderOptions {
            spp: 3,
            tile_size: 8,
            ..RenderOptions::default()
        };
        let cancel = std::sync::atomic::AtomicBool::new(false);
        let film = Film::new(scene.width, scene.height, false);
        let film = render(&scene, &Constant, &options, film, &(), &cancel, &mut |_| {}).film;
        assert_eq!(film.samples(), 37 * 21 * 3);
        for (i, p) in film.image().iter().enumerate() {
            let close = |a: f32, b: f32| (a - b).abs() <= 1e-6 * b;
            assert!(
                close(p.r, 0.25) && close(p.g, 0.5) && close(p.b, 2.0),
                "{filter:?}: pixel {i} is {p:?}"
            );
        }
    }
}

/// The path tracer, through every material, gives the same image on 1 and 2 threads and
/// with every accelerator (they all report the same hits, so the paths cannot differ).
#[test]
fn path_tracing_is_identical_for_any_thread_count_and_accelerator() {
    let mut desc = repository_scene("materials.toml", 96, 36);
    let reference = render_desc(&desc, 1, 16, 9);
    assert_eq!(reference, render_desc(&desc, 2, 16, 9), "1 vs 2 threads");
    assert_ne!(
        reference,
        render_desc(&desc, 1, 16, 10),
        "a different seed gives a different image"
    );
    for accel in penumbra::geometry::AccelKind::ALL {
        desc.render.accel = accel;
        assert_eq!(reference, render_desc(&desc, 2, 16, 9), "{accel:?} vs bvh");
    }
}

/// Bidirectional path tracing, whose light paths splat to any pixel, gives the same image
/// (filtered sums and splat layer) on 1 and 2 threads: a pass's splats are added tile by
/// tile in tile order, whichever thread rendered the tile.
#[test]
fn bdpt_splats_are_identical_for_any_thread_count() {
    let mut desc = repository_scene("gap-room.toml", 48, 36);
    desc.render.integrator = penumbra::renderer::IntegratorKind::Bdpt;
    let reference = render_desc(&desc, 1, 16, 9);
    assert!(!reference.splats.is_empty(), "light tracing splatted");
    assert_eq!(reference, render_desc(&desc, 2, 16, 9), "1 vs 2 threads");
    assert_ne!(
        reference,
        render_desc(&desc, 2, 16, 10),
        "a different seed gives a different image"
    );
}

/// Metropolis light transport gives the same image on 1 and 2 threads: the bootstrap's
/// states and each chain's mutations come from their own random streams, and the chains'
/// splats are added in chain order.
#[test]
fn mlt_is_identical_for_any_thread_count() {
    let mut desc = repository_scene("gap-room.toml", 48, 36);
    desc.render.integrator = penumbra::renderer::IntegratorKind::Mlt;
    desc.render.spp = 4;
    desc.render.mlt.bootstrap = 2000;
    desc.render.mlt.chains = 40;
    same_on_one_and_two_threads(&desc);
}

/// Renders `desc` on 1 and 2 threads (same seed: identical films) and with another seed
/// (a different image).
fn same_on_one_and_two_threads(desc: &SceneDesc) {
    let render = |threads: usize, seed: u64| {
        let mut desc = desc.clone();
        desc.render.seed = seed;
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            penumbra::render(&desc, penumbra::RenderControl::default())
                .unwrap()
                .film
        })
    };
    let reference = render(1, 3);
    assert!(reference.image().iter().any(|p| p.r > 0.0), "the chains found light");
    assert_eq!(reference, render(2, 3), "1 vs 2 threads");
    assert_ne!(reference, render(2, 4), "a different seed gives a different image");
}

/// The photon mappers give the same image on 1 and 2 threads: photons are traced in fixed
/// chunks of their own random streams and concatenated in emission order, the k-d tree is
/// built by a fixed rule, and each pixel sums its photons in the tree's order.
#[test]
fn photon_mapping_is_identical_for_any_thread_count() {
    let mut desc = repository_scene("refraction.toml", 40, 30);
    desc.render.spp = 3;
    desc.render.photon.photons = 20_000;
    desc.render.photon.caustic_photons = 5_000;
    desc.render.photon.lookup = 20;
    for kind in [
        penumbra::renderer::IntegratorKind::Sppm,
        penumbra::renderer::IntegratorKind::Photon,
    ] {
        desc.render.integrator = kind;
        same_on_one_and_two_threads(&desc);
    }
}

/// The `env` integrator's sequential Monte Carlo pass gives the same image on 1 and 2
/// threads: rows in parallel, each pixel sample's numbers its own (pixel sampler and a
/// stream of the pixel, pass and frame), added to the film in pixel order.
#[test]
fn smc_environment_sampling_is_identical_for_any_thread_count() {
    let mut desc = repository_scene("glossy-env.toml", 40, 30);
    desc.render.spp = 3;
    desc.render.env.sampling = penumbra::renderer::integrators::EnvSampling::Smc;
    same_on_one_and_two_threads(&desc);
}

/// `desc` at `spp` samples per pixel with the kernels of `level`.
fn render_at(level: Level, desc: &SceneDesc, spp: u32) -> Film {
    simd::set_level(level).unwrap();
    let scene = build_scene(desc).unwrap();
    let integrator = desc.render.integrator.create(IntegratorOptions {
        direct: desc.render.direct,
        ..IntegratorOptions::default()
    });
    let options = RenderOptions {
        spp,
        seed: 11,
        sampler: desc.render.sampler,
        ..RenderOptions::default()
    };
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let film = Film::new(scene.width, scene.height, false);
    render(&scene, integrator.as_ref(), &options, film, &(), &cancel, &mut |_| {}).film
}

/// Images are bit-identical whichever SIMD kernels run (`penumbra::math::simd`): each
/// level this CPU runs renders the same scenes, through the kernels compiled per level (the
/// BVH's slab test, the Sobol sampler's lanes, the eight-lane Lambertian bounce), and the
/// films must agree bit for bit. A level the CPU lacks is skipped with a note. (The level is
/// global: other tests of this file running meanwhile see it change, which, by this very
/// claim, changes none of their images.)
#[test]
fn every_level_renders_the_same_bits() {
    let levels: Vec<Level> = Level::ALL.into_iter().filter(|l| l.supported()).collect();
    for l in Level::ALL.iter().filter(|l| !l.supported()) {
        println!("note: this CPU lacks {l}: its kernels are not exercised here");
    }
    // The path tracer's eight-lane Lambertian bounce (Sobol lanes, triangle BVH), and the
    // scalar path over spheres, glossy materials and the environment light.
    let mut cbox = repository_scene("cbox-mitsuba.toml", 64, 64);
    cbox.render.sampler = SamplerKind::Sobol;
    // Path tracing under an environment beside point and spot lights: light samples of
    // every lane kind, the environment's lookups and the Lambertian mesh's bounce under
    // the environment in lanes.
    let env_path = "[render]\nwidth = 48\nheight = 32\nintegrator = \"path\"\nmax_depth = 6\n\
        [camera]\nposition = [0, 1.2, 4]\ntarget = [0, 0.4, 0]\nfov = 45\n\
        [environment]\nradiance = [0.4, 0.5, 0.7]\n\
        [[material]]\nname = \"floor\"\ntype = \"diffuse\"\nreflectance = [0.6, 0.5, 0.4]\n\
        [[material]]\nname = \"glossy\"\ntype = \"plastic\"\ndiffuse = [0.1, 0.2, 0.4]\nroughness = 0.1\n\
        [[shape]]\ntype = \"mesh\"\nmaterial = \"floor\"\npositions = [[-4, 0, -4], [4, 0, -4], [4, 0, 4], [-4, 0, 4]]\n\
        indices = [[0, 2, 1], [0, 3, 2]]\n\
        [[shape]]\ntype = \"sphere\"\ncenter = [0, 0.5, 0]\nradius = 0.5\nmaterial = \"glossy\"\n\
        [[light]]\ntype = \"point\"\nposition = [-2, 3, 2]\nintensity = [10, 10, 10]\n\
        [[light]]\ntype = \"spot\"\nposition = [2, 4, 3]\ntarget = [0, 0, 0]\nintensity = [60, 60, 60]\ncone_angle = 30\n";
    let env_path =
        penumbra::scene::formats::native::read(&SourceFile::new("env-path.toml", env_path.to_string())).unwrap();
    let scenes = [
        ("cbox-mitsuba.toml", cbox, 8),
        ("glossy-env.toml", repository_scene("glossy-env.toml", 48, 32), 4),
        ("env-path.toml", env_path, 4),
        ("materials.toml", repository_scene("materials.toml", 48, 32), 4),
    ];
    for (name, desc, spp) in &scenes {
        let reference = render_at(Level::Sse2, desc, *spp);
        assert!(reference.samples() > 0, "{name}: rendered nothing");
        for &level in &levels[1..] {
            let film = render_at(level, desc, *spp);
            assert!(film == reference, "{name}: {level} differs from sse2");
            println!("{name}: {level} = sse2, bit for bit");
        }
    }
    simd::set_level(Level::preferred()).unwrap();
}
