//! Triangle meshes, stored in world space with shared vertices.

use glam::{Vec2, Vec3};
use penumbra_core::{Aabb, Transform};

/// An indexed triangle mesh. Optional per-vertex normals and texture coordinates are
/// interpolated across each triangle.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<Vec2>>,
    pub indices: Vec<[u32; 3]>,
}

/// Why a mesh is unusable.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshError {
    IndexOutOfRange {
        triangle: usize,
        index: u32,
        vertices: usize,
    },
    AttributeCount {
        attribute: &'static str,
        found: usize,
        vertices: usize,
    },
    NonFinitePosition {
        vertex: usize,
    },
    HugePosition {
        vertex: usize,
        value: f32,
    },
}

/// Largest coordinate magnitude a mesh may have: beyond it, box extents and the products
/// in the intersection tests overflow single precision.
pub const MAX_COORDINATE: f32 = 1e30;

impl std::fmt::Display for MeshError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MeshError::IndexOutOfRange {
                triangle,
                index,
                vertices,
            } => {
                write!(
                    f,
                    "triangle {triangle} uses vertex {index}, but the mesh has {vertices} vertices"
                )
            }
            MeshError::AttributeCount {
                attribute,
                found,
                vertices,
            } => {
                write!(f, "the mesh has {vertices} vertices but {found} {attribute}")
            }
            MeshError::NonFinitePosition { vertex } => write!(f, "vertex {vertex} is not a finite number"),
            MeshError::HugePosition { vertex, value } => write!(
                f,
                "vertex {vertex} has the coordinate {value:e}, beyond the supported ±{MAX_COORDINATE:e}; scale the scene down"
            ),
        }
    }
}

impl std::error::Error for MeshError {}

impl TriangleMesh {
    /// Checks indices and attribute counts.
    pub fn validate(&self) -> Result<(), MeshError> {
        let vertices = self.positions.len();
        if let Some(vertex) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFinitePosition { vertex });
        }
        if let Some(vertex) = self
            .positions
            .iter()
            .position(|p| p.abs().max_element() > MAX_COORDINATE)
        {
            let value = self.positions[vertex].abs().max_element();
            return Err(MeshError::HugePosition { vertex, value });
        }
        for (attribute, found) in [
            ("normals", self.normals.as_ref().map(Vec::len)),
            ("texture coordinates", self.uvs.as_ref().map(Vec::len)),
        ] {
            if let Some(found) = found.filter(|&n| n != vertices) {
                return Err(MeshError::AttributeCount {
                    attribute,
                    found,
                    vertices,
                });
            }
        }
        for (triangle, tri) in self.indices.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= vertices) {
                return Err(MeshError::IndexOutOfRange {
                    triangle,
                    index,
                    vertices,
                });
            }
        }
        Ok(())
    }

    /// The mesh under `t`: positions and normals transformed, winding kept consistent.
    pub fn transformed(&self, t: &Transform) -> TriangleMesh {
        let flip = t.swaps_handedness();
        TriangleMesh {
            positions: self.positions.iter().map(|&p| t.point(p)).collect(),
            normals: self
                .normals
                .as_ref()
                .map(|ns| ns.iter().map(|&n| t.normal(n).normalize_or_zero()).collect()),
            uvs: self.uvs.clone(),
            indices: if flip {
                self.indices.iter().map(|&[a, b, c]| [a, c, b]).collect()
            } else {
                self.indices.clone()
            },
        }
    }

    /// Gives a mesh without normals smooth per-vertex normals: the area-weighted mean of the
    /// normals of the triangles around each vertex.
    pub fn compute_smooth_normals(&mut self) {
        if self.normals.is_some() {
            return;
        }
        let mut normals = vec![Vec3::ZERO; self.positions.len()];
        for (tri, idx) in self.indices.iter().enumerate() {
            let [p0, p1, p2] = self.vertices(tri);
            // The cross product's length is twice the area: area weighting for free.
            let n = (p1 - p0).cross(p2 - p0);
            idx.iter().for_each(|&i| normals[i as usize] += n);
        }
        self.normals = Some(normals.into_iter().map(Vec3::normalize_or_zero).collect());
    }

    /// Drops the triangles with zero area (repeated or collinear vertices), which no ray can
    /// hit and which have no normal; returns how many were dropped. The area is computed in
    /// double precision, so tiny but proper triangles are kept.
    pub fn remove_degenerate(&mut self) -> usize {
        let before = self.indices.len();
        let positions = &self.positions;
        self.indices.retain(|idx| {
            let [a, b, c] = idx.map(|i| positions[i as usize].as_dvec3());
            (b - a).cross(c - a) != glam::DVec3::ZERO
        });
        before - self.indices.len()
    }

    pub fn vertices(&self, tri: usize) -> [Vec3; 3] {
        self.indices[tri].map(|i| self.positions[i as usize])
    }

    /// The texture coordinates at barycentrics `b` of triangle `tri` (`b` itself for a
    /// mesh without any): the floats the hit's surface gets.
    pub fn uv_at(&self, tri: usize, b: Vec2) -> Vec2 {
        match &self.uvs {
            Some(uvs) => {
                let [t0, t1, t2] = self.indices[tri].map(|i| uvs[i as usize]);
                (1.0 - b.x - b.y) * t0 + b.x * t1 + b.y * t2
            }
            None => b,
        }
    }

    pub fn triangle_bounds(&self, tri: usize) -> Aabb {
        Aabb::from_points(self.vertices(tri))
    }

    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.positions.iter().copied())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_normals_of_a_tent() {
        // Two triangles meeting at a ridge along x: the ridge normal is straight up.
        let mut m = TriangleMesh {
            positions: vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::new(0.0, -1.0, 1.0),
                Vec3::new(0.0, -1.0, -1.0),
            ],
            indices: vec![[0, 2, 1], [0, 1, 3]],
            ..Default::default()
        };
        m.compute_smooth_normals();
        let n = m.normals.as_ref().unwrap();
        assert!((n[0] - Vec3::Y).length() < 1e-6, "{}", n[0]);
        assert!(m.validate().is_ok());
    }

    #[test]
    fn validation_finds_bad_indices_and_counts() {
        let mut m = TriangleMesh {
            positions: vec![Vec3::ZERO; 3],
            indices: vec![[0, 1, 3]],
            ..Default::default()
        };
        assert!(matches!(m.validate(), Err(MeshError::IndexOutOfRange { index: 3, .. })));
        m.indices = vec![[0, 1, 2]];
        m.uvs = Some(vec![glam::Vec2::ZERO; 2]);
        assert!(matches!(m.validate(), Err(MeshError::AttributeCount { found: 2, .. })));
    }

    #[test]
    fn degenerate_triangles_are_removed_and_counted() {
        let mut m = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::X * 2.0, Vec3::splat(1e-20)],
            // A proper one, a collinear one, a repeated index, a tiny proper one.
            indices: vec![[0, 1, 2], [0, 1, 3], [2, 2, 1], [0, 4, 2]],
            ..Default::default()
        };
        assert_eq!(m.remove_degenerate(), 2);
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 4, 2]]);
    }

    #[test]
    fn huge_coordinates_are_an_error() {
        let m = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X * 3e38, Vec3::Y],
            indices: vec![[0, 1, 2]],
            ..Default::default()
        };
        let e = m.validate().unwrap_err();
        assert!(matches!(e, MeshError::HugePosition { vertex: 1, .. }), "{e}");
        assert!(e.to_string().contains("vertex 1"), "{e}");
    }
}
