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
#[derive(Clone, Debug, PartialEq, Eq)]
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
}

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

    pub fn vertices(&self, tri: usize) -> [Vec3; 3] {
        self.indices[tri].map(|i| self.positions[i as usize])
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
}
