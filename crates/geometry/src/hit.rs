//! The results of ray queries.

use glam::{Vec2, Vec3};

/// The closest intersection found by an accelerator: cheap to produce and compare.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit point.
    pub t: f32,
    /// Index of the primitive within the set the accelerator was built over.
    pub prim: u32,
    /// Index within the primitive: the triangle of a mesh instance, else 0.
    pub sub: u32,
    /// Shape-specific coordinates of the hit (barycentrics b1, b2 for triangles).
    pub uv: Vec2,
}

/// The surface at a hit point, computed once for the closest hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    pub p: Vec3,
    /// Unit geometric normal, pointing to the shape's outside (or its front for flat shapes).
    pub ng: Vec3,
    /// Unit shading normal, in the same hemisphere as `ng`.
    pub ns: Vec3,
    /// Texture coordinates.
    pub uv: Vec2,
    /// ∂p/∂u: the direction in which u grows (not normalised; zero where undefined). The
    /// shading frame's tangent, for anisotropic materials and normal maps.
    pub dpdu: Vec3,
    /// The scene object (shape, mesh or instance) that was hit, as numbered by the builder.
    pub object: u32,
    /// The triangle within the object for meshes and instances; 0 for analytic shapes.
    pub triangle: u32,
}
