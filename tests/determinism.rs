//! The same scene, seed and sample count give the same image for any thread count and
//! tile order.

use penumbra::renderer::integrators::IntegratorOptions;
use penumbra::renderer::{render, Film, RenderOptions};
use penumbra::scene::build_scene;

fn render_with(threads: usize, tile_size: u32, seed: u64) -> Film {
    let mut desc = penumbra::default_scene();
    desc.render.width = 96;
    desc.render.height = 64;
    let scene = build_scene(&desc).unwrap();
    let integrator = desc.render.integrator.create(IntegratorOptions::default());
    let options = RenderOptions {
        spp: 4,
        seed,
        tile_size,
        ..RenderOptions::default()
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let cancel = std::sync::atomic::AtomicBool::new(false);
    pool.install(|| render(&scene, integrator.as_ref(), &options, &(), &cancel))
        .film
}

#[test]
fn identical_for_any_thread_count_and_tiling() {
    let reference = render_with(1, 16, 3);
    assert_eq!(reference, render_with(2, 16, 3), "1 vs 2 threads");
    assert_eq!(reference, render_with(2, 7, 3), "16 vs 7 pixel tiles");
    assert_ne!(
        reference,
        render_with(2, 16, 4),
        "a different seed gives a different image"
    );
}
