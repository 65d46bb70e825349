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
