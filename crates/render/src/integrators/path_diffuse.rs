//! The path tracer's side of the eight-lane Lambertian bounce ([`super::diffuse_lanes`]):
//! which hits take it, and the gathering of up to eight paths' surfaces, random numbers,
//! lights and throughputs into lanes and the scattering of the results back (shadow rays
//! and continuations), with the scalar light sample where the lanes do not take it.

use super::diffuse_lanes::{self, DiffuseHit, TriangleLight};
use super::nee::{self, LightStrategy, Shading};
use super::path::{PathState, PathTracer, Shadows};
use super::{RayCounts, SHADOW_T_MAX};
use crate::lights::{AreaLight, Environment, Light, LightSelection, TriangleByArea};
use crate::materials::DiffuseMaterial;
use crate::{Interaction, Material, Scene, Texture};
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, F8, V3};
#[cfg(target_arch = "x86_64")]
use penumbra_core::lanes_avx::F8Avx;
use penumbra_core::{PixelSampler, Rgb};
use penumbra_geometry::triangle_lanes::{triangle_surface_lanes, SurfaceLanes, TriangleLanes};
use penumbra_geometry::{Hit, SurfaceHit, TriangleMesh};
use std::sync::{RwLock, RwLockReadGuard};

/// A path at a plain Lambertian, non-emitting triangle of a world-space mesh, waiting for
/// the eight-lane bounce (the surface itself is worked out there, in lanes).
#[derive(Clone, Copy)]
pub(super) struct DiffuseLane<'s> {
    /// Where the path is in this depth's list of live paths.
    pub k: usize,
    /// What the mesh's triangles share: object, colour, sidedness.
    lane: &'s LaneMesh,
    mesh: &'s TriangleMesh,
    triangle: u32,
    /// The hit's barycentric coordinates.
    b: Vec2,
    /// The reflectance at the hit: the mesh's constant, or its texture's value there.
    reflectance: Rgb,
}

/// A world-space mesh whose triangles take the eight-lane bounce: its object, and its
/// material's colour (`None`: a texture, looked up per hit) and sidedness.
#[derive(Clone, Copy, Debug)]
pub struct LaneMesh {
    object: u32,
    reflectance: Option<Rgb>,
    two_sided: bool,
}

/// For each world-space mesh of the scene being rendered, what the eight-lane bounce
/// needs if the mesh takes it (one lookup per hit instead of a chain of them): the path
/// tracer's own table, made by its `prepare` for each render.
#[derive(Debug, Default)]
pub struct LaneTable(RwLock<Vec<Option<LaneMesh>>>);

impl LaneTable {
    /// Makes the table for `scene`.
    pub(super) fn fill(&self, scene: &Scene) {
        *self.0.write().unwrap_or_else(|e| e.into_inner()) = lane_meshes(scene);
    }

    /// The table, for one batch of paths (empty before any `fill`: every hit then takes
    /// the one-path bounce, which gives the same image).
    pub(super) fn read(&self) -> RwLockReadGuard<'_, Vec<Option<LaneMesh>>> {
        self.0.read().unwrap_or_else(|e| e.into_inner())
    }
}

/// The meshes with a plain Lambertian material (see [`plain_diffuse`]) that do not emit.
fn lane_meshes(scene: &Scene) -> Vec<Option<LaneMesh>> {
    scene
        .geometry
        .meshes()
        .iter()
        .map(|&(_, object)| {
            let (texture, two_sided) = plain_diffuse(scene.material_of(object))?;
            let reflectance = match texture {
                Texture::Constant(c) => Some(*c),
                _ => None,
            };
            (!scene.lights.emits(object)).then_some(LaneMesh {
                object,
                reflectance,
                two_sided,
            })
        })
        .collect()
}

/// The scalar [`Interaction`] of lane `j`'s surface (for the light samples the lanes do
/// not take): the same floats `Scene::interaction` gives.
fn lane_interaction<'s>(d: &DiffuseLane, material: &'s Material, j: usize, r: &LaneResults) -> Interaction<'s> {
    Interaction {
        surface: SurfaceHit {
            p: r.p.at(j),
            ng: r.ng.at(j),
            ns: r.ns.at(j),
            uv: Vec2::new(r.uv[0][j], r.uv[1][j]),
            dpdu: r.dpdu.at(j),
            object: d.lane.object,
            triangle: d.triangle,
        },
        material,
        wo: r.wo.at(j),
    }
}

/// The reflectance and sidedness of a material the eight-lane bounce takes: Lambertian,
/// one- or two-sided, no normal map, its reflectance a texture or a non-black, finite
/// constant. (A black reflectance makes the scalar BSDF skip its light sample, and it
/// rejects a non-finite sample weight: a texture's value is checked per hit.)
fn plain_diffuse(material: &Material) -> Option<(&Texture, bool)> {
    fn diffuse(m: &Material) -> Option<&Texture> {
        match m {
            Material::Diffuse(DiffuseMaterial { reflectance }) => match reflectance {
                Texture::Constant(c) if c.is_black() || !c.is_finite() => None,
                texture => Some(texture),
            },
            _ => None,
        }
    }
    match material {
        Material::TwoSided(inner) => diffuse(inner).map(|t| (t, true)),
        m => diffuse(m).map(|t| (t, false)),
    }
}

/// The inputs of eight lanes, gathered into columns of eight floats. One set serves a
/// batch's groups in turn: a group writes every column its lanes use (a lane's columns
/// for normals, UVs or a light it lacks keep an earlier group's values, which only that
/// lane's discarded results read).
pub(super) struct Columns([[f32; 8]; Columns::COUNT]);

impl Columns {
    pub(super) fn new() -> Self {
        Columns([[0.0; 8]; Columns::COUNT])
    }

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
    fn f8<L: Lane8>(&self, column: usize) -> L {
        L::from_array(self.0[column])
    }

    #[inline(always)]
    fn v3<L: Lane8>(&self, column: usize) -> V3<L> {
        V3::new(self.f8(column), self.f8(column + 1), self.f8(column + 2))
    }
}

/// The per-lane flags beside [`Columns`]: sidedness of surface and light, whether the
/// mesh has normals and UVs, whether the picked light is the environment.
#[derive(Default)]
struct Flags {
    two_sided: [bool; 8],
    light_two_sided: [bool; 8],
    has_normals: [bool; 8],
    has_uvs: [bool; 8],
    environment: [bool; 8],
}

/// What the lanes computed, read back per lane: the surface, the light sample's shadow
/// ray and value, the continuation.
struct LaneResults {
    p: Lanes3,
    ng: Lanes3,
    ns: Lanes3,
    dpdu: Lanes3,
    uv: [[f32; 8]; 2],
    wo: Lanes3,
    by_area: u32,
    lit: u32,
    l_origin: Lanes3,
    l_dir: Lanes3,
    l_value: Lanes3,
    c_ok: u32,
    c_pdf: [f32; 8],
    c_origin: Lanes3,
    c_dir: Lanes3,
    c_beta: Lanes3,
}

/// The lanes' arithmetic: the surfaces ([`triangle_surface_lanes`]) and the bounce
/// ([`diffuse_lanes::bounce`]), in lane type `L`.
#[inline(always)]
fn lane_kernel<L: Lane8>(input: &LaneInput) -> LaneResults {
    let LaneInput {
        columns: c,
        flags: f,
        env,
        u_light,
        u_dir,
    } = input;
    // No closure makes lane values here: `array::map` and the like are not inlined, and
    // a closure compiled apart from this kernel lacks its SIMD level (its intrinsics
    // become calls).
    let uv = |v: usize| (c.f8::<L>(Columns::UV + 2 * v), c.f8::<L>(Columns::UV + 2 * v + 1));
    let surface = triangle_surface_lanes(&TriangleLanes {
        p: [c.v3(Columns::P), c.v3(Columns::P + 3), c.v3(Columns::P + 6)],
        n: [c.v3(Columns::N), c.v3(Columns::N + 3), c.v3(Columns::N + 6)],
        has_normals: L::mask_of(f.has_normals),
        t: [uv(0), uv(1), uv(2)],
        has_uvs: L::mask_of(f.has_uvs),
        b: (c.f8(Columns::B), c.f8(Columns::B + 1)),
    });
    // `Scene::interaction`'s -dir.normalize().
    let dir: V3<L> = c.v3(Columns::DIR);
    let wo = -dir.try_normalize().0;
    let hit = DiffuseHit {
        p: surface.p,
        ng: surface.ng,
        ns: surface.ns,
        dpdu: surface.dpdu,
        wo,
        reflectance: c.v3(Columns::REFLECTANCE),
        two_sided: L::mask_of(f.two_sided),
        beta: c.v3(Columns::BETA),
    };
    let light = TriangleLight {
        triangle: TriangleByArea {
            v: [c.v3(Columns::V), c.v3(Columns::V + 3), c.v3(Columns::V + 6)],
            normal: c.v3(Columns::LIGHT_NORMAL),
            area: c.f8(Columns::AREA),
            radiance: c.v3(Columns::RADIANCE),
            two_sided: L::mask_of(f.light_two_sided),
        },
        centroid: c.v3(Columns::CENTROID),
        p_pick: c.f8(Columns::P_PICK),
    };
    let env = env.map(Environment::lanes);
    // A match, not `Option::map`: no closure makes lane values here.
    #[allow(clippy::manual_map)]
    let env = match &env {
        Some(env) => Some((env, L::mask_of(f.environment))),
        None => None,
    };
    let (lo, co) = diffuse_lanes::bounce(
        &hit,
        &light,
        env,
        (L::from_array(u_light.0), L::from_array(u_light.1)),
        (L::from_array(u_dir.0), L::from_array(u_dir.1)),
    );
    let s: &SurfaceLanes<L> = &surface;
    // Read back one float at a time from whole-register stores (a vector assembled in
    // a temporary and reloaded across two of its stores would stall the loads).
    LaneResults {
        p: Lanes3::of(s.p),
        ng: Lanes3::of(s.ng),
        ns: Lanes3::of(s.ns),
        dpdu: Lanes3::of(s.dpdu),
        uv: [s.uv.0.to_array(), s.uv.1.to_array()],
        wo: Lanes3::of(wo),
        by_area: L::bits(lo.by_area),
        lit: L::bits(lo.ok),
        l_origin: Lanes3::of(lo.origin),
        l_dir: Lanes3::of(lo.dir),
        l_value: Lanes3::of(lo.value),
        c_ok: L::bits(co.ok),
        c_pdf: co.pdf.to_array(),
        c_origin: Lanes3::of(co.origin),
        c_dir: Lanes3::of(co.dir),
        c_beta: Lanes3::of(co.beta),
    }
}

/// [`lane_kernel`] at the SIMD level the CPU runs ([`penumbra_core::simd::level`]); the same floats at
/// every level.
fn run_lane_kernel(input: &LaneInput) -> LaneResults {
    #[cfg(target_arch = "x86_64")]
    penumbra_core::level_fns! {
        /// The kernel compiled for AVX2 and for AVX-512, in `F8Avx` lanes.
        unsafe fn [avx2, avx512](input: &LaneInput) -> LaneResults {
            lane_kernel::<F8Avx>(input)
        }
    }
    penumbra_core::at_level!(
        avx512: avx512(input),
        avx2: avx2(input),
        portable: lane_kernel::<F8>(input),
    )
}

/// What the lane kernel takes: the gathered columns and flags, the environment where a
/// lane picked it, and the light sample's and the continuation's numbers.
struct LaneInput<'a> {
    columns: &'a Columns,
    flags: &'a Flags,
    env: Option<&'a Environment>,
    u_light: ([f32; 8], [f32; 8]),
    u_dir: ([f32; 8], [f32; 8]),
}

/// The three components of eight lanes' vectors, each as stored from its register.
struct Lanes3([[f32; 8]; 3]);

impl Lanes3 {
    #[inline(always)]
    fn of<L: Lane8>(v: V3<L>) -> Self {
        Lanes3([v.x.to_array(), v.y.to_array(), v.z.to_array()])
    }

    #[inline(always)]
    fn at(&self, j: usize) -> Vec3 {
        Vec3::new(self.0[0][j], self.0[1][j], self.0[2][j])
    }
}

impl PathTracer {
    /// `hit` as a lane of the eight-wide bounce, if it is one: a plain Lambertian,
    /// non-emitting triangle of a world-space mesh. (Inlined: a call returned the lane
    /// through the stack in pieces that the caller's wider reloads then waited on, a
    /// failed store-to-load forwarding costing about 2% of a box's time.)
    #[inline(always)]
    pub(super) fn diffuse_lane<'s>(
        &self,
        scene: &'s Scene,
        lanes: &'s [Option<LaneMesh>],
        k: usize,
        hit: &Hit,
    ) -> Option<DiffuseLane<'s>> {
        if !self.eight_wide {
            return None;
        }
        let (mesh, triangle) = scene.geometry.pooled_index(hit)?;
        let lane = lanes.get(mesh)?.as_ref()?;
        let mesh = &scene.geometry.meshes()[mesh].0;
        let reflectance = match lane.reflectance {
            Some(c) => c,
            None => {
                // The texture at the hit's coordinates, as the scalar BSDF looks it up; a
                // black or non-finite value takes the one-path bounce (see `plain_diffuse`).
                let (texture, _) = plain_diffuse(scene.material_of(lane.object))?;
                let c = texture.eval(mesh.uv_at(triangle as usize, hit.uv));
                if c.is_black() || !c.is_finite() {
                    return None;
                }
                c
            }
        };
        Some(DiffuseLane {
            k,
            lane,
            mesh,
            triangle,
            b: hit.uv,
            reflectance,
        })
    }

    /// The light samples and continuations of up to eight paths at plain Lambertian
    /// surfaces, in eight lanes ([`diffuse_lanes::bounce`]); light samples the lanes do
    /// not take (other kinds of light, triangles near enough to be sampled by solid angle)
    /// by [`nee::light_sample`].
    #[allow(clippy::too_many_arguments)]
    pub(super) fn diffuse_bounces<const N: usize>(
        &self,
        scene: &Scene,
        group: &[DiffuseLane],
        live: &[usize; N],
        (paths, samplers): (&mut [PathState; N], &mut [PixelSampler]),
        shadows: &mut Shadows<N>,
        (depth, nee, selection): (u32, &LightStrategy, LightSelection),
        counts: &mut RayCounts,
        columns: &mut Columns,
    ) {
        let n = group.len();
        // Lanes past the group's end repeat its last path; their results are dropped.
        let lane = |j: usize| &group[j.min(n - 1)];
        // The random numbers, in the scalar bounce's order: the light's pick and point,
        // the lobe choice (a Lambertian BSDF has one lobe: passed over), the direction;
        // the one for Russian roulette below, for the paths that go on.
        let path_of: [usize; 8] = std::array::from_fn(|j| live[lane(j).k]);
        let idx = &path_of[..n];
        let [(u_pick, _), u_light, u_dir] =
            PixelSampler::draws_lanes(samplers, idx, [(0, false), (1, true), (3, true)], 4);
        // The lights picked, in lanes (`LightSet::pick`'s floats).
        let (pick_i, pick_p) = scene.lights.pick_lanes(selection, F8::from_array(u_pick));
        let (pick_i, pick_p) = (pick_i.to_array(), pick_p.to_array());
        let picks: [_; 8] = std::array::from_fn(|j| (pick_i[j] >= 0.0).then_some((pick_i[j] as u32, pick_p[j])));
        let triangle = |j: usize| {
            let (index, p_pick) = picks[j]?;
            // Textured lights take the scalar light sample, which looks the texture up.
            let Light::Area(light @ AreaLight { texture: None, .. }) = &scene.lights.lights()[index as usize] else {
                return None;
            };
            let (v, normal, centroid) = light.emitter.triangle_parts()?;
            Some((v, normal, centroid, light, p_pick))
        };
        // The environment's light samples are taken in the lanes too.
        let mut environment = None;
        let rgb = |c: Rgb| Vec3::new(c.r, c.g, c.b);
        let c = columns;
        let mut f = Flags::default();
        let mut tris = [false; 8];
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
                f.has_normals[j] = true;
            }
            if let Some(uvs) = &d.mesh.uvs {
                for (v, &i) in idx.iter().enumerate() {
                    c.0[Columns::UV + 2 * v][j] = uvs[i].x;
                    c.0[Columns::UV + 2 * v + 1][j] = uvs[i].y;
                }
                f.has_uvs[j] = true;
            }
            c.0[Columns::B][j] = d.b.x;
            c.0[Columns::B + 1][j] = d.b.y;
            let path = &paths[path_of[j]];
            c.put(Columns::DIR, j, path.ray.dir);
            c.put(Columns::REFLECTANCE, j, rgb(d.reflectance));
            c.put(Columns::BETA, j, rgb(path.beta));
            f.two_sided[j] = d.lane.two_sided;
            if let Some((v, normal, centroid, light, p_pick)) = triangle(j) {
                c.put(Columns::V, j, v[0]);
                c.put(Columns::V + 3, j, v[1]);
                c.put(Columns::V + 6, j, v[2]);
                c.put(Columns::LIGHT_NORMAL, j, normal);
                c.put(Columns::CENTROID, j, centroid);
                c.put(Columns::RADIANCE, j, rgb(light.radiance));
                c.0[Columns::AREA][j] = light.emitter.area();
                c.0[Columns::P_PICK][j] = p_pick;
                f.light_two_sided[j] = light.two_sided;
                tris[j] = true;
            } else if let Some((index, p_pick)) = picks[j] {
                if let Some((_, env)) = scene.environment().filter(|e| e.0 == index) {
                    c.0[Columns::P_PICK][j] = p_pick;
                    f.environment[j] = true;
                    environment = Some(env);
                }
            }
        }
        let r = run_lane_kernel(&LaneInput {
            columns: c,
            flags: &f,
            env: environment,
            u_light,
            u_dir,
        });
        let (by_area, lit, c_ok, c_pdf) = (r.by_area, r.lit, r.c_ok, r.c_pdf);
        // Russian roulette's number for each path that goes on, where it is played.
        let (mut going, mut rank) = ([0usize; 8], [0usize; 8]);
        let mut going_n = 0;
        for j in (0..n).filter(|j| c_ok >> j & 1 != 0) {
            (going[going_n], rank[j]) = (idx[j], going_n);
            going_n += 1;
        }
        let u_rr = if depth + 1 >= self.options.rr_depth && going_n > 0 {
            PixelSampler::next_1d_lanes(samplers, &going[..going_n])
        } else {
            [0.0; 8]
        };
        let (l_origin, l_dir, l_value) = (&r.l_origin, &r.l_dir, &r.l_value);
        let (c_origin, c_dir, c_beta) = (&r.c_origin, &r.c_dir, &r.c_beta);
        for (j, d) in group.iter().enumerate() {
            let i = path_of[j];
            if let Some((index, p_pick)) = picks[j] {
                let at_infinity = f.environment[j];
                if (tris[j] || at_infinity) && by_area >> j & 1 != 0 {
                    if lit >> j & 1 != 0 {
                        let v = l_value.at(j);
                        let t_max = if at_infinity { f32::INFINITY } else { SHADOW_T_MAX };
                        shadows.push(l_origin.at(j), l_dir.at(j), t_max, (i, Rgb::new(v.x, v.y, v.z)));
                    }
                } else {
                    let it = lane_interaction(d, scene.material_of(d.lane.object), j, &r);
                    let sh = Shading::new(&it);
                    if let Some(test) =
                        nee::light_sample(scene, &sh, index, p_pick, Vec2::new(u_light.0[j], u_light.1[j]), nee)
                    {
                        shadows.push(
                            test.ray.origin,
                            test.ray.dir,
                            test.t_max,
                            (i, paths[i].beta * test.value),
                        );
                    }
                }
            }
            let path = &mut paths[i];
            path.alive = c_ok >> j & 1 != 0 && {
                let b = c_beta.at(j);
                path.beta = Rgb::new(b.x, b.y, b.z);
                counts.secondary += 1;
                (path.ray.origin, path.ray.dir) = (c_origin.at(j), c_dir.at(j));
                path.previous_pdf = Some(c_pdf[j]);
                self.roulette(path, depth, || u_rr[rank[j]])
            };
        }
    }
}
