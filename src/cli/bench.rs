//! `penumbra bench accel`: race the accelerators on one mesh or scene.

use super::Failure;
use clap::{Args, Subcommand};
use penumbra::bench::{bench_accel, coherent_rays, incoherent_rays, read_hits, read_rays, AccelReport, RaySet};
use penumbra::geometry::{AccelKind, Geometry, GeometryBuilder, TraversalStats};
use penumbra::math::{Ray, Rgb};
use penumbra::scene::image_io::{write_image, Image};
use std::path::{Path, PathBuf};
use std::sync::Arc;

#[derive(Subcommand, Debug)]
pub enum BenchCommand {
    /// Build and race the acceleration structures on a mesh (.ply, .obj) or scene (.toml).
    Accel(AccelArgs),
    /// Time renders of a scene: samples/s, rays/s, rays per sample; `--mitsuba` measures
    /// Mitsuba 3 on its Cornell box in the same command.
    Render(super::bench_render::RenderBenchArgs),
}

#[derive(Args, Debug)]
pub struct AccelArgs {
    /// A mesh (.ply or .obj) or a scene (.toml).
    pub input: PathBuf,
    /// Ray file (N x 6 little-endian float32: origin, direction); repeatable. Expected hits
    /// are read from `hits_NAME.bin` beside `rays_NAME.f32` when present. Without this,
    /// coherent camera rays and incoherent random rays are generated.
    #[arg(long)]
    pub rays: Vec<PathBuf>,
    /// Accelerators to race, comma-separated (default: all).
    #[arg(long, value_delimiter = ',')]
    pub accel: Vec<String>,
    /// Repeats of every build and timing; best and median are reported.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub repeats: u32,
    /// Threads for the all-threads figures (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// `cost`: also write a heat map of traversal cost per pixel for each accelerator.
    #[arg(long)]
    pub aov: Option<String>,
    /// Where the heat maps go.
    #[arg(long, default_value = ".")]
    pub out_dir: PathBuf,
}

pub fn run(command: BenchCommand) -> Result<(), Failure> {
    let args = match command {
        BenchCommand::Accel(args) => args,
        BenchCommand::Render(args) => return super::bench_render::run(args),
    };
    let bad = |m: String| Failure::BadInput(miette::miette!("{m}"));
    let kinds: Vec<AccelKind> = if args.accel.is_empty() {
        AccelKind::NAMES
            .iter()
            .filter_map(|n| AccelKind::from_name(n))
            .collect()
    } else {
        args.accel
            .iter()
            .map(|n| {
                AccelKind::from_name(n).ok_or_else(|| {
                    bad(format!(
                        "--accel: unknown accelerator `{n}`; expected one of: {}",
                        AccelKind::NAMES.join(", ")
                    ))
                })
            })
            .collect::<Result<_, _>>()?
    };
    if args.aov.as_deref().is_some_and(|a| a != "cost") {
        return Err(bad("--aov: the only AOV is `cost`".into()));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.map_or(0, |t| t as usize))
        .build()
        .map_err(|e| Failure::Internal(e.to_string()))?;
    let ext = args
        .input
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    pool.install(|| match ext.as_str() {
        "ply" | "obj" => {
            let mesh = if ext == "ply" {
                penumbra::scene::formats::ply::load(&args.input)
            } else {
                penumbra::scene::formats::obj::load(&args.input)
            }
            .map_err(|e| bad(format!("cannot load {}: {e}", args.input.display())))?;
            let mut mesh = mesh;
            let place = args.input.display().to_string();
            if let Some(warning) = penumbra::scene::formats::drop_degenerate(&mut mesh, &place) {
                eprintln!("warning: {warning}");
            }
            let triangles = mesh.indices.len();
            let mut builder = GeometryBuilder::new();
            builder.add_mesh(mesh);
            let geometry = Arc::new(builder.build());
            let bounds = geometry.finite_bounds();
            let camera = |side: u32| (side, side, coherent_rays(bounds, side));
            race(&args, &kinds, &geometry, triangles, &camera)
        }
        "toml" => {
            let desc = penumbra::scene::read_scene(&args.input).map_err(|e| Failure::BadInput(e.into()))?;
            let scene = penumbra::scene::build_scene(&desc).map_err(|e| Failure::BadInput(e.into()))?;
            let triangles = scene.geometry.triangle_count();
            let (w, h) = (scene.width, scene.height);
            let camera = |_side: u32| {
                let rays = (0..w as u64 * h as u64)
                    .map(|i| {
                        let (x, y) = ((i % w as u64) as f32, (i / w as u64) as f32);
                        scene
                            .camera
                            .generate_ray(glam::Vec2::new(x + 0.5, y + 0.5), glam::Vec2::splat(0.5))
                    })
                    .collect();
                (w, h, rays)
            };
            race(&args, &kinds, &scene.geometry, triangles, &camera)
        }
        _ => Err(bad(format!(
            "cannot benchmark {}: expected a .ply, .obj or .toml file",
            args.input.display()
        ))),
    })
}

fn ray_sets(
    args: &AccelArgs,
    geometry: &Geometry,
    camera: &dyn Fn(u32) -> (u32, u32, Vec<Ray>),
) -> Result<Vec<RaySet>, Failure> {
    if args.rays.is_empty() {
        return Ok(vec![
            RaySet {
                name: "coherent".into(),
                rays: camera(512).2,
                expected: None,
            },
            RaySet {
                name: "incoherent".into(),
                rays: incoherent_rays(geometry.finite_bounds(), 1 << 18, 1),
                expected: None,
            },
        ]);
    }
    args.rays
        .iter()
        .map(|path| {
            let rays = read_rays(path)
                .map_err(|e| Failure::BadInput(miette::miette!("cannot read rays {}: {e}", path.display())))?;
            let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("rays").to_string();
            let name = stem.strip_prefix("rays_").unwrap_or(&stem).to_string();
            let hits_path = path.with_file_name(format!("hits_{name}.bin"));
            let expected = if hits_path.exists() {
                let hits = read_hits(&hits_path).map_err(|e| Failure::BadInput(miette::miette!("{e}")))?;
                if hits.len() != rays.len() {
                    return Err(Failure::BadInput(miette::miette!(
                        "{} has {} hits for {} rays",
                        hits_path.display(),
                        hits.len(),
                        rays.len()
                    )));
                }
                Some(hits)
            } else {
                None
            };
            Ok(RaySet { name, rays, expected })
        })
        .collect()
}

fn race(
    args: &AccelArgs,
    kinds: &[AccelKind],
    geometry: &Arc<Geometry>,
    triangles: usize,
    camera: &dyn Fn(u32) -> (u32, u32, Vec<Ray>),
) -> Result<(), Failure> {
    let sets = ray_sets(args, geometry.as_ref(), camera)?;
    println!(
        "{}: {} primitives ({} triangles); {}; {} repeats",
        args.input.display(),
        geometry.primitive_count(),
        triangles,
        sets.iter()
            .map(|s| format!(
                "{} {} rays{}",
                s.rays.len(),
                s.name,
                if s.expected.is_some() {
                    " with expected hits"
                } else {
                    ""
                }
            ))
            .collect::<Vec<_>>()
            .join(", "),
        args.repeats
    );
    println!(
        "{:<12} {:>15} {:>10} {:>8} {:>11}  {:<11} {:>17} {:>17} {:>9} {:>9} {:>10}",
        "accel",
        "build s (best/med)",
        "memory MB",
        "B/tri",
        "+tris B/tri",
        "rays",
        "Mrays/s 1T b/med",
        "Mrays/s all b/med",
        "nodes/ray",
        "tests/ray",
        "mismatches"
    );
    let mut reports: Vec<AccelReport> = Vec::new();
    for &kind in kinds {
        let r = bench_accel(kind, geometry, &sets, args.repeats as usize);
        for (i, t) in r.throughput.iter().enumerate() {
            let build = if i == 0 {
                format!("{:.3}/{:.3}", r.build.0, r.build.1)
            } else {
                String::new()
            };
            let mem = if i == 0 {
                format!("{:.2}", r.memory_bytes as f64 / 1e6)
            } else {
                String::new()
            };
            let (per_tri, with_tris) = if i == 0 && triangles > 0 {
                let per = |bytes: usize| format!("{:.1}", bytes as f64 / triangles as f64);
                (per(r.memory_bytes), per(r.memory_bytes + r.primitive_bytes))
            } else {
                (String::new(), String::new())
            };
            let sampled = if t.traced < sets[i].rays.len() {
                format!(" ({} traced)", t.traced)
            } else {
                String::new()
            };
            println!(
                "{:<12} {:>15} {:>10} {:>8} {:>11}  {:<11} {:>8.2}/{:<8.2} {:>8.2}/{:<8.2} {:>9.1} {:>9.1} {:>10}{}",
                if i == 0 { kind.name() } else { "" },
                build,
                mem,
                per_tri,
                with_tris,
                t.rays,
                t.single.0,
                t.single.1,
                t.all.0,
                t.all.1,
                t.nodes_per_ray,
                t.prims_per_ray,
                t.mismatches.map_or("-".to_string(), |m| m.to_string()),
                sampled
            );
        }
        reports.push(r);
    }
    if args.aov.is_some() {
        write_cost_images(args, kinds, geometry, camera)?;
    }
    Ok(())
}

/// Heat maps of nodes visited plus primitives tested per camera ray, one per accelerator,
/// on a common logarithmic scale so the images compare.
fn write_cost_images(
    args: &AccelArgs,
    kinds: &[AccelKind],
    geometry: &Arc<Geometry>,
    camera: &dyn Fn(u32) -> (u32, u32, Vec<Ray>),
) -> Result<(), Failure> {
    std::fs::create_dir_all(&args.out_dir)
        .map_err(|e| Failure::BadInput(miette::miette!("cannot create {}: {e}", args.out_dir.display())))?;
    let (w, h, rays) = camera(256);
    let costs: Vec<(AccelKind, Vec<f32>)> = kinds
        .iter()
        .map(|&kind| {
            let accel = geometry.accel(kind);
            let c = rays
                .iter()
                .map(|r| {
                    let mut s = TraversalStats::default();
                    accel.intersect_counted(r, f32::INFINITY, &mut s);
                    (s.nodes + s.prims) as f32
                })
                .collect();
            (kind, c)
        })
        .collect();
    let max = costs.iter().flat_map(|(_, c)| c.iter().copied()).fold(1.0f32, f32::max);
    for (kind, c) in &costs {
        let pixels: Vec<Rgb> = c.iter().map(|&v| heat((1.0 + v).ln() / (1.0 + max).ln())).collect();
        let path = args.out_dir.join(format!("cost-{}.png", kind.name()));
        write(&path, w, h, &pixels)?;
        println!("wrote {} (cost from 0 to {max} per ray, log scale)", path.display());
    }
    Ok(())
}

fn write(path: &Path, w: u32, h: u32, pixels: &[Rgb]) -> Result<(), Failure> {
    // Heat-map colours are display values already: undo the sRGB encoding PNG output applies.
    let linear: Vec<Rgb> = pixels.iter().map(|c| c.map(|v| v.powf(2.2))).collect();
    write_image(
        path,
        &Image {
            width: w,
            height: h,
            pixels: &linear,
        },
        0.0,
    )
    .map_err(|e| Failure::Internal(format!("cannot write {}: {e}", path.display())))
}

/// A black-red-yellow-white ramp for x in [0, 1].
fn heat(x: f32) -> Rgb {
    let x = x.clamp(0.0, 1.0) * 3.0;
    Rgb::new(x.min(1.0), (x - 1.0).clamp(0.0, 1.0), (x - 2.0).clamp(0.0, 1.0))
}
