//! Penumbra geometry: shapes, triangle meshes, instances and the acceleration structures
//! that find the closest hit along a ray.
//!
//! A query goes in two steps, as in pbrt and Embree: an [`Accel`] finds the closest [`Hit`]
//! (distance, primitive, barycentrics) cheaply, then [`Geometry::surface`] computes the full
//! [`SurfaceHit`] (position, normals, texture coordinates) once, for the hit that won.

pub mod accel;
mod geometry;
mod hit;
pub mod instance;
mod mesh;
mod object_set;
mod placement;
pub mod shapes;
pub mod triangle_lanes;

pub use accel::{build_accel, Accel, AccelKind, PrimitiveSet, TraversalStats};
pub use geometry::{Geometry, GeometryBuilder};
pub use hit::{Hit, SurfaceHit};
pub use instance::{Instance, MeshAccel};
pub use mesh::{MeshError, TriangleMesh};
pub use placement::{AffineLanes, Placement, PlacementLanes};
pub use shapes::Shape;
