//! The surface at triangle hits for lanes of any [`Real`] type: the interpolated point,
//! the geometric normal, the shading normal from vertex normals, texture coordinates and
//! ∂p/∂u, as `instance::triangle_surface` computes them for one hit, with the
//! same IEEE operations in the same order (its branches on the mesh's optional normals and
//! UVs become per-lane masks), so each lane is bit for bit the scalar result.

use penumbra_core::lanes::{Real, V3};

/// What a triangle hit needs of its mesh, one lane each.
#[derive(Clone, Copy)]
pub struct TriangleLanes<R: Real> {
    pub p: [V3<R>; 3],
    /// Vertex normals where `has_normals`.
    pub n: [V3<R>; 3],
    pub has_normals: R::Mask,
    /// Vertex texture coordinates (u, v) where `has_uvs`.
    pub t: [(R, R); 3],
    pub has_uvs: R::Mask,
    /// The hit's barycentric coordinates (b1, b2).
    pub b: (R, R),
}

/// [`crate::SurfaceHit`]'s geometry, one lane each.
#[derive(Clone, Copy)]
pub struct SurfaceLanes<R: Real> {
    pub p: V3<R>,
    pub ng: V3<R>,
    pub ns: V3<R>,
    pub uv: (R, R),
    pub dpdu: V3<R>,
}

/// The surface at each lane's hit.
#[inline(always)]
pub fn triangle_surface_lanes<R: Real>(h: &TriangleLanes<R>) -> SurfaceLanes<R> {
    let (one, zero) = (R::splat(1.0), R::splat(0.0));
    let [p0, p1, p2] = h.p;
    let (bx, by) = h.b;
    let b0 = one - bx - by;
    let p = p0.scale(b0) + p1.scale(bx) + p2.scale(by);
    let (e1, e2) = (p1 - p0, p2 - p0);
    let (ng, _) = e1.cross(e2).try_normalize();

    let [n0, n1, n2] = h.n;
    let (n, n_ok) = (n0.scale(b0) + n1.scale(bx) + n2.scale(by)).try_normalize();
    let smooth = R::and(h.has_normals, n_ok);
    let flip = R::and(smooth, n.dot(ng).cmp_lt(zero));
    let ns = V3::select(smooth, n, ng);
    let ng = V3::select(flip, -ng, ng);

    let [t0, t1, t2] = h.t;
    let (d1, d2) = ((t1.0 - t0.0, t1.1 - t0.1), (t2.0 - t0.0, t2.1 - t0.1));
    let det = d1.0 * d2.1 - d1.1 * d2.0;
    let regular = R::and(h.has_uvs, det.abs().cmp_gt(R::splat(1e-12)));
    let dpdu = V3::select(regular, (e1.scale(d2.1) - e2.scale(d1.1)).div_by(det), e1);
    let uv = (
        R::select(h.has_uvs, t0.0 * b0 + t1.0 * bx + t2.0 * by, bx),
        R::select(h.has_uvs, t0.1 * b0 + t1.1 * bx + t2.1 * by, by),
    );
    SurfaceLanes { p, ng, ns, uv, dpdu }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::instance::triangle_surface;
    use crate::TriangleMesh;
    use glam::{Vec2, Vec3};
    use penumbra_core::lanes::F8;
    use penumbra_core::Pcg32;

    /// One lane's share of [`TriangleLanes`]: triangle `tri` of `mesh` hit at barycentrics `b`.
    struct TriangleInput {
        p: [Vec3; 3],
        n: Option<[Vec3; 3]>,
        t: Option<[Vec2; 3]>,
        b: Vec2,
    }

    impl TriangleInput {
        fn new(mesh: &TriangleMesh, tri: u32, b: Vec2) -> Self {
            let idx = mesh.indices[tri as usize];
            TriangleInput {
                p: mesh.vertices(tri as usize),
                n: mesh.normals.as_ref().map(|n| idx.map(|i| n[i as usize])),
                t: mesh.uvs.as_ref().map(|t| idx.map(|i| t[i as usize])),
                b,
            }
        }
    }

    /// Eight lanes give `triangle_surface`'s floats bit for bit, for meshes with and
    /// without normals and UVs (mixed in one group), normals facing against the winding,
    /// zero normals and UV triangles of zero area.
    #[test]
    fn lanes_equal_the_scalar_surface() {
        let mut rng = Pcg32::new(3, 5);
        let v =
            |rng: &mut Pcg32, s: f32| Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5) * s;
        for round in 0..4000 {
            let meshes: Vec<TriangleMesh> = (0..8)
                .map(|k| {
                    let positions = vec![v(&mut rng, 4.0), v(&mut rng, 4.0), v(&mut rng, 4.0)];
                    let normals = match (round + k) % 4 {
                        0 => None,
                        1 => Some(vec![Vec3::ZERO; 3]),
                        _ => Some(vec![v(&mut rng, 1.0), v(&mut rng, 1.0), v(&mut rng, 1.0)]),
                    };
                    let uvs = match (round + k) % 3 {
                        0 => None,
                        1 => Some(vec![Vec2::new(0.25, 0.5); 3]),
                        _ => Some((0..3).map(|_| v(&mut rng, 1.0).truncate()).collect()),
                    };
                    TriangleMesh {
                        positions,
                        normals,
                        uvs,
                        indices: vec![[0, 1, 2]],
                    }
                })
                .collect();
            let b: Vec<Vec2> = (0..8)
                .map(|_| {
                    let (x, y) = (rng.next_f32(), rng.next_f32());
                    if x + y > 1.0 {
                        Vec2::new(1.0 - x, 1.0 - y)
                    } else {
                        Vec2::new(x, y)
                    }
                })
                .collect();
            let inputs: Vec<TriangleInput> = (0..8).map(|k| TriangleInput::new(&meshes[k], 0, b[k])).collect();
            let got = triangle_surface_lanes(&gather(&inputs));
            let (p, ng, ns, dpdu) = (
                got.p.to_lanes(),
                got.ng.to_lanes(),
                got.ns.to_lanes(),
                got.dpdu.to_lanes(),
            );
            let (u, w) = (got.uv.0.to_array(), got.uv.1.to_array());
            for k in 0..8 {
                let (sp, sng, sns, suv, sdpdu) = triangle_surface(&meshes[k], 0, b[k]);
                let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                let what = format!("round {round}, lane {k}");
                assert_eq!(bits(p[k]), bits(sp), "{what}: p");
                assert_eq!(bits(ng[k]), bits(sng), "{what}: ng");
                assert_eq!(bits(ns[k]), bits(sns), "{what}: ns");
                assert_eq!(bits(dpdu[k]), bits(sdpdu), "{what}: dpdu");
                assert_eq!(
                    [u[k].to_bits(), w[k].to_bits()],
                    [suv.x.to_bits(), suv.y.to_bits()],
                    "{what}: uv"
                );
            }
        }
    }

    fn gather(inputs: &[TriangleInput]) -> TriangleLanes<F8> {
        let v3 = |f: &dyn Fn(&TriangleInput) -> Vec3| V3::<F8>::from_lanes(&std::array::from_fn(|k| f(&inputs[k])));
        let f8 = |f: &dyn Fn(&TriangleInput) -> f32| F8::from(std::array::from_fn::<f32, 8, _>(|k| f(&inputs[k])));
        TriangleLanes {
            p: [0, 1, 2].map(|c| v3(&|i| i.p[c])),
            n: [0, 1, 2].map(|c| v3(&|i| i.n.map_or(Vec3::ZERO, |n| n[c]))),
            has_normals: F8::mask(std::array::from_fn(|k| inputs[k].n.is_some())),
            t: [0, 1, 2].map(|c| {
                (
                    f8(&|i| i.t.map_or(0.0, |t| t[c].x)),
                    f8(&|i| i.t.map_or(0.0, |t| t[c].y)),
                )
            }),
            has_uvs: F8::mask(std::array::from_fn(|k| inputs[k].t.is_some())),
            b: (f8(&|i| i.b.x), f8(&|i| i.b.y)),
        }
    }
}
