//! The wavefront's BSDF stage: every shading point of a depth asks its BSDF for a sample
//! and, where a light sample waits, for the BSDF's value and density towards the light.
//! Points are bucketed by BSDF kind (as wavefront renderers sort hits by material: Laine,
//! Karras and Aila 2013); each kind with a lane kernel ([`Gather`], [`LaneKernel`]) answers
//! eight points per pass of eight-lane instructions at the CPU's SIMD level, the other
//! kinds one point at a time; blends through their parts' kinds ([`blends`]). A lane gives
//! the bits its kind's scalar BSDF gives (the scalar BSDF is the kernel's one-lane
//! instance), so the image does not depend on the bucketing.

use super::nee::Shading;
use crate::bsdfs::{flip, Bsdf, BsdfKind, BsdfSample, Gather, LaneKernel, TransportMode};
use glam::{Vec2, Vec3};
use penumbra_core::lanes::{Lane8, F8, V3};
#[cfg(target_arch = "x86_64")]
use penumbra_core::lanes_avx::F8Avx;
use penumbra_core::Rgb;

mod blends;

/// What one shading point asks of its BSDF (radiance mode), in the shading frame, beside
/// the point's own view direction.
#[derive(Clone, Copy, Debug)]
pub(super) struct BsdfQuery {
    /// The direction to a light sample, if one waits, and whether its density is needed.
    pub light: Option<(Vec3, bool)>,
    /// Whether a sample (a continuation) is wanted: a blend's part may be asked for its
    /// value and density alone.
    pub sample: bool,
    pub u_lobe: f32,
    pub u: Vec2,
}

/// The BSDF's answers: value and density towards the light (zero without one), a sample.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct BsdfAnswer {
    pub f: Rgb,
    pub pdf: f32,
    pub sample: Option<BsdfSample>,
}

/// The BSDF kinds answered in lanes, one line each (bucket, `BsdfKind` variant): generates
/// [`Buckets`] and its [`Buckets::answer`]. A kind with a lane kernel joins by one line here.
/// The kinds after the `;` run in AVX2 lanes only (see [`avx2_kernel`]; one at a time on
/// CPUs without AVX2). Blends are answered through their parts' kinds ([`blends`]).
macro_rules! lane_kinds {
    ($($bucket:ident: $variant:ident),* ; $($alone:ident: $alone_variant:ident),* $(,)?) => {
        /// The buckets of one depth's shading points, by index, kept between depths.
        #[derive(Default)]
        pub(super) struct Buckets {
            $($bucket: Vec<usize>,)*
            $($alone: Vec<usize>,)*
            /// The blends, answered through their parts.
            blends: Vec<usize>,
            /// The buckets of the blends' parts (made at the first blend).
            parts: Option<Box<Buckets>>,
        }

        impl Buckets {
            /// Answers `queries[i]` of shading point `shs[i]` into `out[i]`.
            pub fn answer<'s, P: BsdfPoint<'s>>(&mut self, shs: &[P], queries: &[BsdfQuery], out: &mut [BsdfAnswer]) {
                $(self.$bucket.clear();)*
                $(self.$alone.clear();)*
                self.blends.clear();
                for (i, (sh, q)) in shs.iter().zip(queries).enumerate() {
                    match sh.bsdf().kind {
                        $(BsdfKind::$variant(_) => self.$bucket.push(i),)*
                        $(BsdfKind::$alone_variant(_) => self.$alone.push(i),)*
                        BsdfKind::Blend(_) => self.blends.push(i),
                        // Kinds not listed go one at a time (none today: every kind
                        // has a lane kernel).
                        #[allow(unreachable_patterns)]
                        _ => out[i] = answer_one(sh, q),
                    }
                }
                let mode = TransportMode::Radiance;
                $( lane_kinds!(@kind self.$bucket, shs, queries, out, mode, $variant, Some(run_kernel)); )*
                $( lane_kinds!(@kind self.$alone, shs, queries, out, mode, $alone_variant, avx2_kernel()); )*
                if !self.blends.is_empty() {
                    let parts = self.parts.get_or_insert_with(Default::default);
                    blends::answer_blends(&self.blends, parts, shs, queries, out);
                }
            }
        }
    };
    // One kind's bucket answered by its kernel, run by `$run`.
    (@kind $bucket:expr, $shs:ident, $q:ident, $out:ident, $mode:ident, $variant:ident, $run:expr) => {
        for group in $bucket.chunks(8) {
            answer_lanes(group, $shs, $q, $out, $run, |p| match $shs[group[p]].bsdf().kind {
                BsdfKind::$variant(k) => k.lanes($mode),
                _ => unreachable!("a bucket holds one kind"),
            });
        }
    };
}

lane_kinds! {
    diffuse: Diffuse,
    conductor: Conductor,
    dielectric: Dielectric,
    plastic: Plastic,
    phong: Phong;
    layered: Layered,
}

/// What the BSDF stage needs of a point: its BSDF and the direction towards the viewer in
/// its shading frame (a shading point, or a blend's part, [`blends::Part`]).
pub(super) trait BsdfPoint<'s> {
    fn bsdf(&self) -> &Bsdf<'s>;
    fn wo(&self) -> Vec3;
}

impl<'s> BsdfPoint<'s> for Shading<'s> {
    #[inline(always)]
    fn bsdf(&self) -> &Bsdf<'s> {
        &self.bsdf
    }
    #[inline(always)]
    fn wo(&self) -> Vec3 {
        self.wo
    }
}

/// One point's answers from its scalar BSDF.
fn answer_one<'s>(sh: &impl BsdfPoint<'s>, q: &BsdfQuery) -> BsdfAnswer {
    let (bsdf, wo, mode) = (sh.bsdf(), sh.wo(), TransportMode::Radiance);
    let (f, pdf) = match q.light {
        Some((l, need_pdf)) => (
            bsdf.eval(wo, l, mode),
            if need_pdf { bsdf.pdf(wo, l, mode) } else { 0.0 },
        ),
        None => (Rgb::BLACK, 0.0),
    };
    BsdfAnswer {
        f,
        pdf,
        sample: if q.sample {
            bsdf.sample(wo, q.u_lobe, q.u, mode)
        } else {
            None
        },
    }
}

/// The inputs of eight lanes, in columns.
struct Columns {
    wo: [[f32; 8]; 3],
    l: [[f32; 8]; 3],
    u_lobe: [f32; 8],
    u: [[f32; 8]; 2],
    /// Whether any lane wants a sample.
    sample: bool,
}

/// What eight lanes answered, in columns.
struct Results {
    f: [[f32; 8]; 3],
    pdf: [f32; 8],
    wi: [[f32; 8]; 3],
    weight: [[f32; 8]; 3],
    sample_pdf: [f32; 8],
    eta: [f32; 8],
    delta: u32,
    ok: u32,
}

/// The points `group` (up to eight) of one kind, whose one-lane kernels `kernel` gives
/// (by place in the group), answered in lanes by `run` ([`run_kernel`], or
/// [`avx2_kernel`]'s; without one, one at a time by their scalar BSDFs, the same floats);
/// lanes past the group's end repeat its last point and are dropped.
fn answer_lanes<'s, G: Gather>(
    group: &[usize],
    shs: &[impl BsdfPoint<'s>],
    queries: &[BsdfQuery],
    out: &mut [BsdfAnswer],
    run: Option<fn(&[G; 8], &Columns) -> Results>,
    kernel: impl Fn(usize) -> G,
) {
    let Some(run) = run else {
        for &i in group {
            out[i] = answer_one(&shs[i], &queries[i]);
        }
        return;
    };
    let n = group.len();
    let at = |j: usize| group[j.min(n - 1)];
    // Two-sided BSDFs seen from behind work on mirrored directions (`Bsdf`'s rule).
    let mirrored: [bool; 8] = std::array::from_fn(|j| {
        let sh = &shs[at(j)];
        sh.bsdf().mirrored(sh.wo())
    });
    let side = |j: usize, w: Vec3| if mirrored[j] { flip(w) } else { w };
    let one: [G; 8] = std::array::from_fn(|j| kernel(j.min(n - 1)));
    let mut c = Columns {
        wo: [[0.0; 8]; 3],
        l: [[0.0; 8]; 3],
        u_lobe: [0.0; 8],
        u: [[0.0; 8]; 2],
        sample: group.iter().any(|&i| queries[i].sample),
    };
    for j in 0..8 {
        let q = &queries[at(j)];
        let (wo, l) = (side(j, shs[at(j)].wo()), side(j, q.light.map_or(Vec3::Z, |(l, _)| l)));
        for (axis, (a, b)) in [(wo.x, l.x), (wo.y, l.y), (wo.z, l.z)].into_iter().enumerate() {
            (c.wo[axis][j], c.l[axis][j]) = (a, b);
        }
        c.u_lobe[j] = q.u_lobe;
        (c.u[0][j], c.u[1][j]) = (q.u.x, q.u.y);
    }
    let r = run(&one, &c);
    let v3 = |a: &[[f32; 8]; 3], j: usize| Vec3::new(a[0][j], a[1][j], a[2][j]);
    for (j, &i) in group.iter().enumerate() {
        let (lit, need_pdf) = queries[i].light.map_or((false, false), |(_, need)| (true, need));
        let f = v3(&r.f, j);
        let sample = (queries[i].sample && r.ok >> j & 1 != 0)
            .then(|| BsdfSample {
                wi: side(j, v3(&r.wi, j)),
                weight: Rgb::new(r.weight[0][j], r.weight[1][j], r.weight[2][j]),
                pdf: r.sample_pdf[j],
                delta: r.delta >> j & 1 != 0,
                eta: r.eta[j],
            })
            // `BsdfKind::sample`'s rule.
            .filter(BsdfSample::usable);
        out[i] = BsdfAnswer {
            f: if lit { Rgb::new(f.x, f.y, f.z) } else { Rgb::BLACK },
            pdf: if need_pdf { r.pdf[j] } else { 0.0 },
            sample,
        };
    }
}

/// The lanes' arithmetic in lane type `L`.
#[inline(always)]
fn kernel<G: Gather, L: Lane8>(one: &[G; 8], c: &Columns) -> Results {
    let k = G::gather::<L>(one);
    let v3 = |a: &[[f32; 8]; 3]| V3::new(L::from_array(a[0]), L::from_array(a[1]), L::from_array(a[2]));
    let (wo, l) = (v3(&c.wo), v3(&c.l));
    let f = k.eval(wo, l);
    let pdf = k.pdf(wo, l);
    let columns = |v: V3<L>| [v.x.to_array(), v.y.to_array(), v.z.to_array()];
    let mut r = Results {
        f: columns(f),
        pdf: pdf.to_array(),
        wi: [[0.0; 8]; 3],
        weight: [[0.0; 8]; 3],
        sample_pdf: [0.0; 8],
        eta: [1.0; 8],
        delta: 0,
        ok: 0,
    };
    if c.sample {
        let s = k.sample(
            wo,
            L::from_array(c.u_lobe),
            (L::from_array(c.u[0]), L::from_array(c.u[1])),
        );
        (r.wi, r.weight, r.sample_pdf) = (columns(s.wi), columns(s.weight), s.pdf.to_array());
        (r.eta, r.delta, r.ok) = (s.eta.to_array(), L::bits(s.delta), L::bits(s.ok));
    }
    r
}

/// [`kernel`] at the SIMD level the CPU runs ([`penumbra_core::simd::level`]); the same floats at every
/// level.
fn run_kernel<G: Gather>(one: &[G; 8], c: &Columns) -> Results {
    #[cfg(target_arch = "x86_64")]
    penumbra_core::level_fns! {
        /// The kernel compiled for AVX2 and for AVX-512, in `F8Avx` lanes.
        unsafe fn [avx2, avx512]<G: Gather>(one: &[G; 8], c: &Columns) -> Results {
            kernel::<G, F8Avx>(one, c)
        }
    }
    penumbra_core::at_level!(avx512: avx512(one, c), avx2: avx2(one, c), portable: kernel::<G, F8>(one, c))
}

/// [`kernel`] in AVX2 lanes ([`F8Avx`]) where the CPU has them (AVX-512 CPUs too), `None`
/// elsewhere, for kernels too large to compile at every level: the layered BSDF's walk
/// (77 s of LLVM's time on this crate at three levels, `-Z llvm-time-trace`; two SSE
/// halves per operation make about four times the IR of one AVX2 operation,
/// docs/performance.md).
fn avx2_kernel<G: Gather>() -> Option<fn(&[G; 8], &Columns) -> Results> {
    /// The kernel compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn avx2<G: Gather>(one: &[G; 8], c: &Columns) -> Results {
        kernel::<G, F8Avx>(one, c)
    }
    /// [`avx2`], handed out only where the CPU runs AVX2.
    #[cfg(target_arch = "x86_64")]
    fn checked<G: Gather>(one: &[G; 8], c: &Columns) -> Results {
        // SAFETY: `avx2_kernel` returns this function only at the AVX2 and AVX-512
        // levels, which are chosen only where the CPU runs AVX2.
        unsafe { avx2(one, c) }
    }
    #[cfg(target_arch = "x86_64")]
    type Run<G> = fn(&[G; 8], &Columns) -> Results;
    penumbra_core::at_level!(avx512: Some(checked::<G> as Run<G>), avx2: Some(checked::<G> as Run<G>), portable: None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::MetalFresnel;
    use crate::materials::{
        Coated, CoatedBase, ConductorMaterial, DielectricMaterial, DiffuseMaterial, Phong, Roughness,
    };
    use crate::{Interaction, Material, Texture};
    use penumbra_core::simd::{self, Level};
    use penumbra_core::Pcg32;
    use penumbra_geometry::SurfaceHit;

    /// A material of lane kind `k % 5`, rough (Phong: a low exponent, with a mirror and an
    /// interface) where `k / 5` is odd.
    fn parts(rng: &mut Pcg32, k: usize) -> Material {
        let c = |rng: &mut Pcg32| Texture::Constant(Rgb::new(rng.next_f32(), rng.next_f32(), rng.next_f32()));
        let rough = (k / 5 % 2 == 1).then(|| Roughness::isotropic(0.1 + 0.3 * rng.next_f32()));
        match k % 5 {
            0 => Material::Diffuse(DiffuseMaterial { reflectance: c(rng) }),
            1 => Material::Conductor(ConductorMaterial {
                specular: c(rng),
                roughness: rough,
                ..ConductorMaterial::default()
            }),
            2 => Material::Dielectric(DielectricMaterial {
                eta: 1.3 + rng.next_f32(),
                roughness: rough,
                ..DielectricMaterial::default()
            }),
            3 => Material::plastic(c(rng), Texture::Constant(Rgb::WHITE), 1.5, rough),
            _ => {
                let glossy = rough.is_some();
                Material::Phong(Phong {
                    diffuse: c(rng),
                    specular: Rgb::splat(0.3 * rng.next_f32()),
                    exponent: if glossy { 5.0 + 20.0 * rng.next_f32() } else { 200.0 },
                    mirror: Rgb::splat(if glossy { 0.2 } else { 0.0 }),
                    transmission: Rgb::splat(if glossy { 0.3 } else { 0.0 }),
                    ..Phong::default()
                })
            }
        }
    }

    /// Shading points of blends of every pair of lane kinds (smooth and rough parts,
    /// weights 0 and 1 among them, some blends two-sided, some with a two-sided part),
    /// coated materials alone and in blends, blends of blends (three deep, and one of eight
    /// dielectrics), seen from both sides and mixed with plain kinds in one depth: at every
    /// SIMD level the CPU runs, the buckets' answers in lanes are, point by point, the bits
    /// of each point's scalar BSDF.
    #[test]
    fn blends_answered_in_lanes_give_the_scalar_answers() {
        let mut rng = Pcg32::new(21, 7);
        let mut materials = Vec::new();
        for i in 0..250 {
            // Every pair of kinds, each part smooth and rough.
            let (a, b) = (
                parts(&mut rng, i % 5 + 5 * (i / 25)),
                parts(&mut rng, i / 5 % 5 + 5 * (i / 50)),
            );
            let a = if i % 11 == 0 {
                Material::TwoSided(Box::new(a))
            } else {
                a
            };
            let weight = Texture::Constant(Rgb::splat([0.0, 1.0, rng.next_f32()][i % 3]));
            let blend = Material::Blend {
                a: Box::new(a),
                b: Box::new(b),
                weight,
            };
            materials.push(match i % 5 {
                0 => Material::TwoSided(Box::new(blend)),
                4 => parts(&mut rng, i),
                _ => blend,
            });
        }
        // Coated (layered) materials over diffuse and metal bases, clear or with a medium,
        // alone (their own bucket) and in blends (one at a time) among the others.
        for i in 0..60 {
            let c = |rng: &mut Pcg32| Texture::Constant(Rgb::new(rng.next_f32(), rng.next_f32(), rng.next_f32()));
            let rough = (i % 3 != 0).then(|| Roughness::isotropic(0.05 + 0.3 * rng.next_f32()));
            let base = if i % 2 == 0 {
                CoatedBase::Diffuse {
                    reflectance: c(&mut rng),
                }
            } else {
                CoatedBase::Conductor {
                    fresnel: MetalFresnel::Schlick,
                    specular: c(&mut rng),
                    roughness: (i % 4 == 1).then(|| Roughness::isotropic(0.2)),
                }
            };
            let medium = i % 5 < 2;
            let coated = Material::Coated(Coated {
                base,
                roughness: rough,
                thickness: if medium { 0.3 } else { 0.01 },
                albedo: if medium {
                    c(&mut rng)
                } else {
                    Texture::Constant(Rgb::BLACK)
                },
                g: 0.4,
                max_depth: 1 + i as u32 % 10,
                ..Coated::default()
            });
            materials.push(if i % 6 == 5 {
                Material::Blend {
                    a: Box::new(coated),
                    b: Box::new(parts(&mut rng, i)),
                    weight: Texture::Constant(Rgb::splat(0.5)),
                }
            } else {
                coated
            });
        }
        // Blends of blends: a blend of a blend of a blend, and one of eight dielectrics of
        // different indices, as a Mitsuba scene nests them.
        for i in 0..30 {
            let w = |rng: &mut Pcg32| Texture::Constant(Rgb::splat(rng.next_f32()));
            let deep = Material::Blend {
                a: Box::new(Material::Blend {
                    a: Box::new(parts(&mut rng, i)),
                    b: Box::new(Material::Blend {
                        a: Box::new(parts(&mut rng, i + 3)),
                        b: Box::new(parts(&mut rng, i + 7)),
                        weight: w(&mut rng),
                    }),
                    weight: w(&mut rng),
                }),
                b: Box::new(parts(&mut rng, i + 1)),
                weight: w(&mut rng),
            };
            let mut glasses: Vec<Material> = (0..8)
                .map(|k| {
                    Material::Dielectric(DielectricMaterial {
                        eta: 1.1 + 0.1 * k as f32,
                        roughness: (i % 2 == 1).then(|| Roughness::isotropic(0.2)),
                        ..DielectricMaterial::default()
                    })
                })
                .collect();
            while glasses.len() > 1 {
                let b = glasses.pop().unwrap();
                let a = glasses.pop().unwrap();
                glasses.insert(
                    0,
                    Material::Blend {
                        a: Box::new(a),
                        b: Box::new(b),
                        weight: w(&mut rng),
                    },
                );
            }
            materials.push(if i % 2 == 0 { deep } else { glasses.pop().unwrap() });
        }
        let its: Vec<Interaction> = materials
            .iter()
            .map(|material| {
                let n = penumbra_core::warp::uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                let wo = penumbra_core::warp::uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                Interaction {
                    surface: SurfaceHit {
                        p: Vec3::ZERO,
                        ng: n,
                        ns: n,
                        uv: Vec2::ZERO,
                        dpdu: Vec3::ZERO,
                        object: 0,
                        triangle: 0,
                    },
                    material,
                    wo,
                }
            })
            .collect();
        let shs: Vec<Shading> = its.iter().map(Shading::new).collect();
        let queries: Vec<BsdfQuery> = shs
            .iter()
            .map(|_| {
                let l = penumbra_core::warp::uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                BsdfQuery {
                    light: (rng.next_below(4) != 0).then_some((l, rng.next_below(2) == 0)),
                    sample: rng.next_below(8) != 0,
                    u_lobe: rng.next_f32(),
                    u: Vec2::new(rng.next_f32(), rng.next_f32()),
                }
            })
            .collect();
        let levels: Vec<Level> = Level::ALL.into_iter().filter(|l| l.supported()).collect();
        for &level in &levels {
            simd::set_level(level).unwrap();
            let mut out = vec![BsdfAnswer::default(); shs.len()];
            Buckets::default().answer(&shs, &queries, &mut out);
            let samples = compare(&shs, &queries, &out, level);
            assert!(samples > 40, "only {samples} samples");
        }
        simd::set_level(Level::preferred()).unwrap();
        println!("compared at {levels:?}");
    }

    /// Asserts that `out` holds each point's scalar answers, bit for bit; how many samples.
    fn compare(shs: &[Shading], queries: &[BsdfQuery], out: &[BsdfAnswer], level: Level) -> usize {
        let bits = |c: Rgb| [c.r, c.g, c.b].map(f32::to_bits);
        let mut samples = 0;
        for (i, (sh, q)) in shs.iter().zip(queries).enumerate() {
            let one = answer_one(sh, q);
            assert_eq!(bits(out[i].f), bits(one.f), "value, point {i} at {level}");
            assert_eq!(out[i].pdf.to_bits(), one.pdf.to_bits(), "density, point {i} at {level}");
            assert_eq!(
                out[i].sample.is_some(),
                one.sample.is_some(),
                "sample exists, point {i}"
            );
            if let (Some(a), Some(b)) = (out[i].sample, one.sample) {
                samples += 1;
                assert_eq!(
                    a.wi.to_array().map(f32::to_bits),
                    b.wi.to_array().map(f32::to_bits),
                    "wi, point {i}"
                );
                assert_eq!(bits(a.weight), bits(b.weight), "weight, point {i}");
                assert_eq!(
                    (a.pdf.to_bits(), a.delta, a.eta.to_bits()),
                    (b.pdf.to_bits(), b.delta, b.eta.to_bits()),
                    "point {i}"
                );
            }
        }
        samples
    }
}
