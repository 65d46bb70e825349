//! Images are bit-identical whichever SIMD kernels run (`penumbra::math::simd`): each
//! level this CPU runs renders the same scenes, through the BVH's slab test and the Sobol
//! sampler's lanes (the two kernels compiled per level), and the films must agree bit for
//! bit. A level the CPU lacks is skipped with a note.

use penumbra::math::simd::{self, Level};
use penumbra::math::SamplerKind;
use penumbra::renderer::integrators::IntegratorOptions;
use penumbra::renderer::{render, Film, RenderOptions};
use penumbra::scene::{build_scene, SceneDesc, SourceFile};

fn repository_scene(name: &str, width: u32, height: u32) -> SceneDesc {
    let path = format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR"));
    let file = SourceFile::new(&path, std::fs::read_to_string(&path).unwrap());
    let mut desc = penumbra::scene::formats::native::read(&file).unwrap();
    desc.render.width = width;
    desc.render.height = height;
    desc
}

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

/// One test, so that no other test in this binary changes the level meanwhile.
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
    let scenes = [
        ("cbox-mitsuba.toml", cbox, 8),
        ("glossy-env.toml", repository_scene("glossy-env.toml", 48, 32), 4),
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
    simd::set_level(Level::best()).unwrap();
}
