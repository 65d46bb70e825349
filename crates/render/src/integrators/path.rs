//! Unidirectional path tracing of the rendering equation (Kajiya 1986), as pbrt-v4's
//! `PathIntegrator` and Mitsuba 3's `path` do it: one random continuation per bounce drawn
//! from the BSDF, next-event estimation at every vertex with a non-delta part (one shadow
//! ray to a light picked by power, solid-angle sampled unless it is a small flat light),
//! emitters and the environment reached by the continuation rays weighted against it by the
//! power heuristic (Veach and Guibas 1995), and Russian roulette from `rr_depth` on with
//! survival probability min(max throughput channel × η², 0.95).
//!
//! `max_depth` has Mitsuba's meaning: the largest number of path segments, so 1 shows the
//! emitters only, 2 gives direct lighting, and each further unit one more bounce.
//!
//! The paths of a batch of camera rays advance in lockstep, one stage at a time over all
//! of them (a wavefront, as in Laine, Karras and Aila, "Megakernels Considered Harmful",
//! 2013): closest hits for every live path; then at each surface the emission met, a light
//! sample (its shadow ray kept) and the continuation; then every shadow ray. Each stage is
//! a loop over the batch (a whole tile of camera rays, [`BATCH`]), so the rays of a stage
//! go to the accelerator together ([`Scene::occluded_batch`]); paths at plain Lambertian
//! triangles are set aside at the hit and take their bounce eight at a time in SIMD lanes
//! (`diffuse_lanes.rs`). Every path draws its random numbers and adds its terms in the
//! order a path traced alone would, so a batch gives exactly the radiance of its paths
//! traced one by one ([`PathTracer::li`] is a batch of one).

use super::diffuse_lanes::{self, DiffuseHit, TriangleLight};
use super::nee::{self, LightStrategy, Shading};
use super::{Integrator, IntegratorOptions, MisHeuristic, RayCounts};
use crate::bsdfs::TransportMode;
use crate::lights::{AreaSampling, Light, LightSelection};
use crate::{Interaction, Material, Scene, Texture};
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{F8, V3};
use penumbra_core::{PixelSampler, Ray, Rgb};
use penumbra_geometry::triangle_lanes::{triangle_surface_lanes, SurfaceLanes, TriangleLanes};
use penumbra_geometry::{Hit, SurfaceHit, TriangleMesh};

/// The default depth (path segments) from which Russian roulette may end paths, Mitsuba's.
pub const RR_DEPTH: u32 = 5;

/// The most paths traced in lockstep: a whole tile of the driver (16 x 16 pixels), so
/// that the eight-lane groups stay full as paths end.
pub const BATCH: usize = 256;

pub struct PathTracer {
    pub options: IntegratorOptions,
    /// Bounces at plain Lambertian surfaces taken eight paths at a time
    /// (`integrators/diffuse_lanes.rs`); the same image either way, `false` only to show that.
    pub eight_wide: bool,
}

impl PathTracer {
    pub fn new(options: IntegratorOptions) -> Self {
        PathTracer {
            options,
            eight_wide: true,
        }
    }
}

/// A path at a plain Lambertian, non-emitting triangle of a world-space mesh, waiting for
/// the eight-lane bounce (the surface itself is worked out there, in lanes).
#[derive(Clone, Copy)]
struct DiffuseLane<'s> {
    /// Where the path is in this depth's rays.
    k: usize,
    reflectance: Rgb,
    two_sided: bool,
    mesh: &'s TriangleMesh,
    triangle: u32,
    object: u32,
    material: &'s Material,
    /// The hit's barycentric coordinates.
    b: Vec2,
}

/// The scalar [`Interaction`] of lane `j`'s surface (for the light samples the lanes do
/// not take): the same floats `Scene::interaction` gives.
fn lane_interaction<'s>(d: &DiffuseLane<'s>, j: usize, s: &SurfaceLanes<F8>, wo: V3<F8>) -> Interaction<'s> {
    let at = |v: V3<F8>| v.to_lanes()[j];
    Interaction {
        surface: SurfaceHit {
            p: at(s.p),
            ng: at(s.ng),
            ns: at(s.ns),
            uv: Vec2::new(s.uv.0.to_array()[j], s.uv.1.to_array()[j]),
            dpdu: at(s.dpdu),
            object: d.object,
            triangle: d.triangle,
        },
        material: d.material,
        wo: at(wo),
    }
}

/// The colour and sidedness of a material the eight-lane bounce takes: Lambertian with a
/// constant, non-black reflectance, one- or two-sided, no normal map.
fn plain_diffuse(material: &Material) -> Option<(Rgb, bool)> {
    let constant = |m: &Material| match m {
        Material::Diffuse {
            reflectance: Texture::Constant(c),
        } if !c.is_black() => Some(*c),
        _ => None,
    };
    match material {
        Material::TwoSided(inner) => constant(inner).map(|c| (c, true)),
        m => constant(m).map(|c| (c, false)),
    }
}

/// Up to [`BATCH`] camera rays, their samplers and where their radiance goes.
struct Batch<'a> {
    rays: &'a [Ray],
    samplers: &'a mut [PixelSampler],
    out: &'a mut [Rgb],
}

/// What one path carries from bounce to bounce.
#[derive(Clone, Copy)]
struct PathState {
    radiance: Rgb,
    beta: Rgb,
    ray: Ray,
    /// The vertex the ray left and the BSDF density of its direction; `None` after the
    /// camera or a perfectly specular bounce (nothing else could have sampled it).
    previous: Option<(Vec3, f32)>,
    /// The product of η² over the refractions so far.
    eta_scale: f32,
    alive: bool,
}

/// The inputs of eight lanes, gathered into columns of eight floats.
struct Columns([[f32; 8]; Columns::COUNT]);

impl Columns {
    /// The hit triangle's corners (nine columns), vertex normals (nine) and UVs (six).
    const P: usize = 0;
    const N: usize = 9;
    const UV: usize = 18;
    /// The hit's barycentrics, and the ray direction.
    const B: usize = 24;
    const DIR: usize = 26;
    const REFLECTANCE: usize = 29;
    const BETA: usize = 32;
    /// The light triangle's corners, nine columns.
    const V: usize = 35;
    const LIGHT_NORMAL: usize = 44;
    const CENTROID: usize = 47;
    const RADIANCE: usize = 50;
    const AREA: usize = 53;
    const P_PICK: usize = 54;
    const COUNT: usize = 55;

    #[inline(always)]
    fn put(&mut self, column: usize, lane: usize, v: Vec3) {
        self.0[column][lane] = v.x;
        self.0[column + 1][lane] = v.y;
        self.0[column + 2][lane] = v.z;
    }

    #[inline(always)]
    fn f8(&self, column: usize) -> F8 {
        F8::from(self.0[column])
    }

    #[inline(always)]
    fn v3(&self, column: usize) -> V3<F8> {
        V3::new(self.f8(column), self.f8(column + 1), self.f8(column + 2))
    }
}

/// The shadow rays of a depth, the path and light each brings if unblocked.
struct Shadows<'a, const N: usize> {
    rays: &'a mut [(Ray, f32); N],
    light: &'a mut [(usize, Rgb); N],
    len: usize,
}

impl<const N: usize> Shadows<'_, N> {
    fn push(&mut self, ray: (Ray, f32), light: (usize, Rgb)) {
        self.rays[self.len] = ray;
        self.light[self.len] = light;
        self.len += 1;
    }
}

impl Integrator for PathTracer {
    fn li(&self, scene: &Scene, camera_ray: &Ray, sampler: &mut PixelSampler, counts: &mut RayCounts) -> Rgb {
        let mut out = [Rgb::BLACK];
        let batch = Batch {
            rays: std::slice::from_ref(camera_ray),
            samplers: std::slice::from_mut(sampler),
            out: &mut out,
        };
        self.trace_batch::<1>(scene, batch, counts);
        out[0]
    }

    fn li_batch(
        &self,
        scene: &Scene,
        camera_rays: &[Ray],
        samplers: &mut [PixelSampler],
        out: &mut [Rgb],
        counts: &mut RayCounts,
    ) {
        for ((rays, samplers), out) in camera_rays
            .chunks(BATCH)
            .zip(samplers.chunks_mut(BATCH))
            .zip(out.chunks_mut(BATCH))
        {
            self.trace_batch::<BATCH>(scene, Batch { rays, samplers, out }, counts);
        }
    }
}

impl PathTracer {
    /// Traces up to `N` paths in lockstep (a batch of one for [`Integrator::li`]: no
    /// room set up for the lanes it does not use).
    fn trace_batch<const N: usize>(&self, scene: &Scene, batch: Batch, counts: &mut RayCounts) {
        let Batch {
            rays: camera_rays,
            samplers,
            out,
        } = batch;
        let n = camera_rays.len();
        // One shadow ray per vertex: "every light in turn" makes no sense here, and picking
        // by power with `All`'s within-object probabilities would break the MIS weights.
        let selection = match self.options.direct.selection {
            LightSelection::All => LightSelection::Power,
            s => s,
        };
        let heuristic = MisHeuristic::Power;
        let nee = LightStrategy {
            sampling: AreaSampling::Adaptive,
            samples: 1.0,
            mis: Some((heuristic, 1.0)),
        };
        let no_ray = Ray::new(Vec3::ZERO, Vec3::Z);
        let mut paths: [PathState; N] = std::array::from_fn(|i| PathState {
            radiance: Rgb::BLACK,
            beta: Rgb::WHITE,
            ray: camera_rays.get(i).copied().unwrap_or(no_ray),
            previous: None,
            eta_scale: 1.0,
            alive: i < n,
        });
        let mut rays = [no_ray; N];
        let mut live = [0usize; N];
        let mut hits: [Option<Interaction>; N] = [const { None }; N];
        // Shadow rays (ray, t_max), the path and light each brings if unblocked, and the
        // answers.
        let mut shadow_rays = [(no_ray, 0.0f32); N];
        let mut shadow_light = [(0usize, Rgb::BLACK); N];
        let mut blocked = [false; N];
        let mut diffuse: [Option<DiffuseLane>; N] = [None; N];
        let mut group = Vec::with_capacity(N);
        // The paths still alive, compacted as paths end.
        for (i, l) in live.iter_mut().enumerate() {
            *l = i;
        }
        let mut count = n;
        for depth in 0.. {
            // Closest hits of every live path.
            let mut still = 0;
            for j in 0..count {
                let i = live[j];
                if paths[i].alive {
                    live[still] = i;
                    rays[still] = paths[i].ray;
                    still += 1;
                }
            }
            count = still;
            if count == 0 {
                break;
            }
            // The surfaces met; plain Lambertian triangles are set aside for the lanes.
            for k in 0..count {
                (hits[k], diffuse[k]) = (None, None);
                let Some(hit) = scene.accel.intersect(&rays[k], f32::INFINITY) else {
                    continue;
                };
                diffuse[k] = self.diffuse_lane(scene, k, &hit);
                if diffuse[k].is_none() {
                    hits[k] = Some(scene.interaction(&rays[k], &hit));
                }
            }

            // Emission met, a light sample (its shadow ray kept for later) and the
            // continuation at each surface; plain Lambertian surfaces after the others,
            // eight at a time.
            let mut m = 0;
            group.clear();
            for k in 0..count {
                let path = &mut paths[live[k]];
                if let Some(d) = diffuse[k] {
                    // Not an emitter: nothing to add before the bounce.
                    if depth + 1 >= self.options.max_depth {
                        path.alive = false;
                    } else {
                        group.push(d);
                    }
                    continue;
                }
                let Some(it) = &hits[k] else {
                    // The environment, weighted against its light sampling as an emitter is.
                    path.radiance += path.beta
                        * match scene.environment() {
                            Some(env) => {
                                let weight = path.previous.map_or(1.0, |(_, p_bsdf)| {
                                    let mis = (selection, heuristic);
                                    nee::environment_weight(scene, mis, env, path.ray.dir, (1.0, p_bsdf), 1.0)
                                });
                                env.1.le(path.ray.dir) * weight
                            }
                            None => scene.background,
                        };
                    path.alive = false;
                    continue;
                };
                if let Some((index, light)) = scene.emitter_at(it) {
                    let normal = light.emitter.normal_at(it.surface.p);
                    let le = light.le(normal, it.wo);
                    if !le.is_black() {
                        let weight = path.previous.map_or(1.0, |(p, p_bsdf)| {
                            let hit = (index, light);
                            nee::emitter_weight(
                                scene,
                                (selection, nee.sampling),
                                heuristic,
                                p,
                                hit,
                                it.surface.p,
                                normal,
                                (1.0, p_bsdf),
                                1.0,
                            )
                        });
                        path.radiance += path.beta * le * weight;
                    }
                }
                // One more segment would exceed the maximum path length.
                if depth + 1 >= self.options.max_depth {
                    path.alive = false;
                    continue;
                }
                let sampler = &mut samplers[live[k]];
                let sh = Shading::new(it);
                if sh.bsdf.has_smooth() {
                    let u_pick = sampler.next_1d();
                    let u = sampler.next_2d();
                    let test = scene
                        .lights
                        .pick(selection, u_pick)
                        .and_then(|(index, p_pick)| nee::light_sample(scene, &sh, index, p_pick, u, &nee));
                    if let Some(test) = test {
                        // What the light brings if visible, with the throughput up to here.
                        shadow_rays[m] = (test.ray, test.t_max);
                        shadow_light[m] = (live[k], path.beta * test.value);
                        m += 1;
                    }
                }
                path.alive = self.continue_path(&sh, path, sampler, depth, counts);
            }

            let mut shadows = Shadows {
                rays: &mut shadow_rays,
                light: &mut shadow_light,
                len: m,
            };
            for group in group.chunks(8) {
                self.diffuse_bounces(
                    scene,
                    group,
                    (&rays, &live),
                    (&mut paths, samplers),
                    &mut shadows,
                    (depth, &nee, selection),
                    counts,
                );
            }
            let m = shadows.len;

            // Every shadow ray of the batch, then the light of those that reached it.
            counts.shadow += m as u64;
            scene.occluded_batch(&shadow_rays[..m], &mut blocked[..m]);
            for (&(lane, value), &blocked) in shadow_light[..m].iter().zip(&blocked) {
                if !blocked {
                    paths[lane].radiance += value;
                }
            }
        }
        for (o, path) in out.iter_mut().zip(&paths) {
            *o = path.radiance;
        }
    }

    /// Draws the continuation of `path` at `sh` from the whole BSDF (delta lobes included)
    /// and plays Russian roulette; whether the path goes on.
    fn continue_path(
        &self,
        sh: &Shading,
        path: &mut PathState,
        sampler: &mut PixelSampler,
        depth: u32,
        counts: &mut RayCounts,
    ) -> bool {
        let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
        let Some(bs) = sh.bsdf.sample(sh.wo, u_lobe, u, TransportMode::Radiance) else {
            return false;
        };
        let wi = sh.frame.to_world(bs.wi);
        if !sh.agrees(wi, bs.wi) {
            return false;
        }
        path.beta *= bs.weight;
        path.eta_scale *= bs.eta * bs.eta;
        counts.secondary += 1;
        path.ray = Ray::new(sh.origin_towards(wi), wi);
        path.previous = (!bs.delta).then_some((path.ray.origin, bs.pdf));

        self.roulette(path, depth, || sampler.next_1d())
    }

    /// `hit` as a lane of the eight-wide bounce, if it is one: a plain Lambertian,
    /// non-emitting triangle of a world-space mesh.
    fn diffuse_lane<'s>(&self, scene: &'s Scene, k: usize, hit: &Hit) -> Option<DiffuseLane<'s>> {
        if !self.eight_wide {
            return None;
        }
        let (mesh, triangle, object) = scene.geometry.pooled_hit(hit)?;
        let material = scene.material_of(object);
        let (reflectance, two_sided) = plain_diffuse(material)?;
        if scene.lights.emitter_of(object, triangle).is_some() {
            return None;
        }
        Some(DiffuseLane {
            k,
            reflectance,
            two_sided,
            mesh,
            triangle,
            object,
            material,
            b: hit.uv,
        })
    }

    /// Russian roulette from `rr_depth` on, with `u()` the path's next random number;
    /// whether the path survives. Survival by the throughput with refraction's 1/η²
    /// undone (as Mitsuba and pbrt-v4), so that paths inside glass are not cut for their
    /// scaling alone.
    fn roulette(&self, path: &mut PathState, depth: u32, u: impl FnOnce() -> f32) -> bool {
        if depth + 1 >= self.options.rr_depth {
            let q = (path.beta.max_component() * path.eta_scale).min(0.95);
            if u() >= q {
                return false;
            }
            path.beta = path.beta / q;
        }
        true
    }

    /// The light samples and continuations of up to eight paths at plain Lambertian
    /// surfaces, in eight lanes ([`diffuse_lanes::bounce`]); light samples the lanes do
    /// not take (other kinds of light, triangles near enough to be sampled by solid angle)
    /// by [`nee::light_sample`].
    #[allow(clippy::too_many_arguments)]
    fn diffuse_bounces<const N: usize>(
        &self,
        scene: &Scene,
        group: &[DiffuseLane],
        (rays, live): (&[Ray; N], &[usize; N]),
        (paths, samplers): (&mut [PathState; N], &mut [PixelSampler]),
        shadows: &mut Shadows<N>,
        (depth, nee, selection): (u32, &LightStrategy, LightSelection),
        counts: &mut RayCounts,
    ) {
        let n = group.len();
        // Lanes past the group's end repeat its last path; their results are dropped.
        let lane = |j: usize| &group[j.min(n - 1)];
        // The random numbers, in the scalar bounce's order: the light's pick and point,
        // the lobe choice (a Lambertian BSDF has one lobe: passed over), the direction,
        // and for Russian roulette one drawn whether or not it is played (a path that
        // does not play it ends here, so its later dimensions are never used).
        let idx: [usize; 8] = std::array::from_fn(|j| live[lane(j).k]);
        let idx = &idx[..n];
        let u_pick = PixelSampler::next_1d_lanes(samplers, idx);
        let u_light = PixelSampler::next_2d_lanes(samplers, idx);
        idx.iter().for_each(|&i| samplers[i].skip(1));
        let u_dir = PixelSampler::next_2d_lanes(samplers, idx);
        let u_rr = if depth + 1 >= self.options.rr_depth {
            PixelSampler::next_1d_lanes(samplers, idx)
        } else {
            [0.0; 8]
        };
        let picks: [_; 8] = std::array::from_fn(|j| scene.lights.pick(selection, u_pick[j]));
        let triangle = |j: usize| {
            let (index, p_pick) = picks[j]?;
            let Light::Area(light) = &scene.lights.lights()[index as usize] else {
                return None;
            };
            let (v, normal, centroid) = light.emitter.triangle_parts()?;
            Some((v, normal, centroid, light, p_pick))
        };
        let rgb = |c: Rgb| Vec3::new(c.r, c.g, c.b);
        let mut c = Columns([[0.0; 8]; Columns::COUNT]);
        let (mut two_sided, mut light_two_sided, mut tris) = ([false; 8], [false; 8], [false; 8]);
        let (mut has_normals, mut has_uvs) = ([false; 8], [false; 8]);
        for j in 0..8 {
            let d = lane(j);
            let idx = d.mesh.indices[d.triangle as usize].map(|i| i as usize);
            for (v, &i) in idx.iter().enumerate() {
                c.put(Columns::P + 3 * v, j, d.mesh.positions[i]);
            }
            if let Some(normals) = &d.mesh.normals {
                for (v, &i) in idx.iter().enumerate() {
                    c.put(Columns::N + 3 * v, j, normals[i]);
                }
                has_normals[j] = true;
            }
            if let Some(uvs) = &d.mesh.uvs {
                for (v, &i) in idx.iter().enumerate() {
                    c.0[Columns::UV + 2 * v][j] = uvs[i].x;
                    c.0[Columns::UV + 2 * v + 1][j] = uvs[i].y;
                }
                has_uvs[j] = true;
            }
            c.0[Columns::B][j] = d.b.x;
            c.0[Columns::B + 1][j] = d.b.y;
            c.put(Columns::DIR, j, rays[d.k].dir);
            c.put(Columns::REFLECTANCE, j, rgb(d.reflectance));
            c.put(Columns::BETA, j, rgb(paths[live[d.k]].beta));
            two_sided[j] = d.two_sided;
            if let Some((v, normal, centroid, light, p_pick)) = triangle(j) {
                c.put(Columns::V, j, v[0]);
                c.put(Columns::V + 3, j, v[1]);
                c.put(Columns::V + 6, j, v[2]);
                c.put(Columns::LIGHT_NORMAL, j, normal);
                c.put(Columns::CENTROID, j, centroid);
                c.put(Columns::RADIANCE, j, rgb(light.radiance));
                c.0[Columns::AREA][j] = light.emitter.area();
                c.0[Columns::P_PICK][j] = p_pick;
                light_two_sided[j] = light.two_sided;
                tris[j] = true;
            }
        }
        let uv = |v: usize| (c.f8(Columns::UV + 2 * v), c.f8(Columns::UV + 2 * v + 1));
        let surface = triangle_surface_lanes(&TriangleLanes {
            p: [0, 1, 2].map(|v| c.v3(Columns::P + 3 * v)),
            n: [0, 1, 2].map(|v| c.v3(Columns::N + 3 * v)),
            has_normals: F8::mask(has_normals),
            t: [uv(0), uv(1), uv(2)],
            has_uvs: F8::mask(has_uvs),
            b: (c.f8(Columns::B), c.f8(Columns::B + 1)),
        });
        // `Scene::interaction`'s -dir.normalize().
        let dir = c.v3(Columns::DIR);
        let wo = -dir.try_normalize().0;
        let hit = DiffuseHit {
            p: surface.p,
            ng: surface.ng,
            ns: surface.ns,
            dpdu: surface.dpdu,
            wo,
            reflectance: c.v3(Columns::REFLECTANCE),
            two_sided: F8::mask(two_sided),
            beta: c.v3(Columns::BETA),
        };
        let light = TriangleLight {
            v: [c.v3(Columns::V), c.v3(Columns::V + 3), c.v3(Columns::V + 6)],
            normal: c.v3(Columns::LIGHT_NORMAL),
            centroid: c.v3(Columns::CENTROID),
            area: c.f8(Columns::AREA),
            radiance: c.v3(Columns::RADIANCE),
            two_sided: F8::mask(light_two_sided),
            p_pick: c.f8(Columns::P_PICK),
        };
        let (lo, co) = diffuse_lanes::bounce(
            &hit,
            &light,
            (F8::from(u_light.0), F8::from(u_light.1)),
            (F8::from(u_dir.0), F8::from(u_dir.1)),
        );

        let (by_area, lit) = (F8::mask_bits(lo.by_area), F8::mask_bits(lo.ok));
        let (l_origin, l_dir, l_value) = (lo.origin.to_lanes(), lo.dir.to_lanes(), lo.value.to_lanes());
        let (c_ok, c_pdf) = (F8::mask_bits(co.ok), co.pdf.to_array());
        let (c_origin, c_dir, c_beta) = (co.origin.to_lanes(), co.dir.to_lanes(), co.beta.to_lanes());
        for (j, d) in group.iter().enumerate() {
            let i = live[d.k];
            if let Some((index, p_pick)) = picks[j] {
                if tris[j] && by_area >> j & 1 != 0 {
                    if lit >> j & 1 != 0 {
                        let v = l_value[j];
                        let ray = (
                            Ray::new(l_origin[j], l_dir[j]),
                            1.0 - penumbra_core::ray::SHADOW_EPSILON,
                        );
                        shadows.push(ray, (i, Rgb::new(v.x, v.y, v.z)));
                    }
                } else {
                    let it = lane_interaction(d, j, &surface, wo);
                    let sh = Shading::new(&it);
                    if let Some(test) =
                        nee::light_sample(scene, &sh, index, p_pick, Vec2::new(u_light.0[j], u_light.1[j]), nee)
                    {
                        shadows.push((test.ray, test.t_max), (i, paths[i].beta * test.value));
                    }
                }
            }
            let path = &mut paths[i];
            path.alive = c_ok >> j & 1 != 0 && {
                let b = c_beta[j];
                path.beta = Rgb::new(b.x, b.y, b.z);
                counts.secondary += 1;
                path.ray = Ray::new(c_origin[j], c_dir[j]);
                path.previous = Some((c_origin[j], c_pdf[j]));
                self.roulette(path, depth, || u_rr[j])
            };
        }
    }
}
