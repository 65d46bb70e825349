//! Ray sets for benchmarks: read from the anchors' files (N x 6 little-endian float32:
//! origin, direction) with their expected hits (N x (int32 primitive or -1, float32 t)),
//! or generated.

use glam::Vec3;
use penumbra_core::{Aabb, Pcg32, Ray};
use std::io;
use std::path::Path;

/// A named set of rays, with the hits another ray tracer found for them if known.
pub struct RaySet {
    pub name: String,
    pub rays: Vec<Ray>,
    pub expected: Option<Vec<ExpectedHit>>,
}

/// A closest hit as another ray tracer reported it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExpectedHit {
    /// Primitive index, or -1 for a miss.
    pub prim: i32,
    pub t: f32,
}

impl ExpectedHit {
    /// Whether `hit` (primitive, distance) is the same answer: the same primitive, or a tie at
    /// the same distance (within 1e-4 relative, e.g. on an edge shared by two triangles).
    pub fn agrees(&self, hit: Option<(u32, f32)>) -> bool {
        match hit {
            None => self.prim < 0,
            Some((prim, t)) => {
                self.prim >= 0 && (prim as i32 == self.prim || (t - self.t).abs() <= 1e-4 * self.t.abs().max(1e-6))
            }
        }
    }
}

fn floats(bytes: &[u8]) -> impl Iterator<Item = f32> + '_ {
    bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Reads a ray file: N x 6 little-endian float32. A ray with a non-finite number or a zero
/// direction is an error naming it.
pub fn read_rays(path: &Path) -> io::Result<Vec<Ray>> {
    let bytes = std::fs::read(path)?;
    if bytes.len() % 24 != 0 {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("{}: size is not a multiple of 24 bytes", path.display()),
        ));
    }
    if bytes.is_empty() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("{}: the file holds no rays", path.display()),
        ));
    }
    let f: Vec<f32> = floats(&bytes).collect();
    f.chunks_exact(6)
        .enumerate()
        .map(|(i, r)| {
            let ray = Ray::new(Vec3::new(r[0], r[1], r[2]), Vec3::new(r[3], r[4], r[5]));
            if !ray.origin.is_finite() || !ray.dir.is_finite() || ray.dir == Vec3::ZERO {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    format!(
                        "{}: ray {i} (origin {}, direction {}) needs finite numbers and a non-zero direction",
                        path.display(),
                        ray.origin,
                        ray.dir
                    ),
                ));
            }
            Ok(ray)
        })
        .collect()
}

/// Reads an expected-hit file: N x (int32 primitive or -1, float32 t), little-endian.
pub fn read_hits(path: &Path) -> io::Result<Vec<ExpectedHit>> {
    let bytes = std::fs::read(path)?;
    if bytes.len() % 8 != 0 {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("{}: size is not a multiple of 8 bytes", path.display()),
        ));
    }
    Ok(bytes
        .chunks_exact(8)
        .map(|b| ExpectedHit {
            prim: i32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            t: f32::from_le_bytes([b[4], b[5], b[6], b[7]]),
        })
        .collect())
}

/// A `side` x `side` pinhole grid of rays looking at `bounds` from the +z side.
pub fn coherent_rays(bounds: Aabb, side: u32) -> Vec<Ray> {
    let (c, r) = (bounds.centroid(), 0.5 * bounds.extent().length());
    let eye = c + Vec3::new(0.0, 0.0, 3.0 * r);
    (0..side * side)
        .map(|i| {
            let x = ((i % side) as f32 + 0.5) / side as f32 - 0.5;
            let y = ((i / side) as f32 + 0.5) / side as f32 - 0.5;
            Ray::new(eye, (c + Vec3::new(x, -y, 0.0) * 2.2 * r - eye).normalize())
        })
        .collect()
}

/// `n` rays from random points on a sphere around `bounds` towards random points inside it.
pub fn incoherent_rays(bounds: Aabb, n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, 0);
    let (c, r) = (bounds.centroid(), 0.5 * bounds.extent().length());
    let mut unit = || loop {
        let v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE;
        if v.length_squared() <= 1.0 && v.length_squared() > 1e-6 {
            return v.normalize();
        }
    };
    (0..n)
        .map(|_| {
            let origin = c + unit() * 2.0 * r;
            let target = c + unit() * 0.8 * r;
            Ray::new(origin, (target - origin).normalize())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_and_hit_files_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let rays_path = dir.path().join("rays.f32");
        let bytes: Vec<u8> = [1.0f32, 2.0, 3.0, 0.0, 0.0, -1.0]
            .iter()
            .flat_map(|f| f.to_le_bytes())
            .collect();
        std::fs::write(&rays_path, &bytes).unwrap();
        let rays = read_rays(&rays_path).unwrap();
        assert_eq!(rays, vec![Ray::new(Vec3::new(1.0, 2.0, 3.0), Vec3::NEG_Z)]);
        std::fs::write(&rays_path, &bytes[..20]).unwrap();
        assert!(read_rays(&rays_path).is_err());
        std::fs::write(&rays_path, []).unwrap();
        assert!(read_rays(&rays_path).unwrap_err().to_string().contains("no rays"));
        for bad in [[0.0f32, 0.0, 0.0, 0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0, 0.0, 0.0, 1.0]] {
            let mut b = bytes.clone();
            b.extend(bad.iter().flat_map(|f| f.to_le_bytes()));
            std::fs::write(&rays_path, &b).unwrap();
            let e = read_rays(&rays_path).unwrap_err().to_string();
            assert!(e.contains("ray 1 "), "{e}");
        }
        let hits_path = dir.path().join("hits.bin");
        let hb: Vec<u8> = (-1i32)
            .to_le_bytes()
            .into_iter()
            .chain(f32::INFINITY.to_le_bytes())
            .collect();
        std::fs::write(&hits_path, hb).unwrap();
        let h = read_hits(&hits_path).unwrap()[0];
        assert!(h.agrees(None) && !h.agrees(Some((0, 1.0))));
        let e = ExpectedHit { prim: 3, t: 2.0 };
        assert!(
            e.agrees(Some((3, 2.1))) && e.agrees(Some((4, 2.0001))) && !e.agrees(Some((4, 2.1))) && !e.agrees(None)
        );
    }
}
