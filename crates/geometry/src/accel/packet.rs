//! Packets: up to eight coherent rays of a wavefront's batch that walk an accelerator together,
//! one SIMD lane each (Wald, Slusallek, Benthin and Wagner, "Interactive Rendering with
//! Coherent Ray Tracing", 2001). A batch is sorted into packets by a class the primitives'
//! packet tests need shared (for triangles, the dominant axis of the direction, which
//! fixes the watertight test's frame), in batch order within a class, so the packets of a
//! batch are the same whatever the thread or machine.

use super::PrimitiveSet;
use penumbra_core::Ray;

/// Rays per packet: the lanes of an AVX register.
pub const PACKET: usize = 8;
/// The most classes a set sorts rays into ([`PrimitiveSet::packet_class`]).
pub(crate) const CLASSES: usize = 3;
/// Rays sorted at a time: the index lists live on the stack.
pub(crate) const CHUNK: usize = 256;

/// Up to [`PACKET`] rays, their prepared data and where they came from.
pub struct RayPacket<D> {
    pub rays: [Ray; PACKET],
    pub data: [D; PACKET],
    /// The lanes that hold a ray of the batch; the others repeat the last of them.
    pub mask: u32,
    /// Each lane's place in the batch.
    pub index: [usize; PACKET],
}

/// A chunk of a batch sorted by class: the rays' places in the chunk, class by class.
pub(crate) struct Sorted {
    members: [[u16; CHUNK]; CLASSES],
    len: [usize; CLASSES],
}

impl Sorted {
    /// Sorts `chunk` (at most [`CHUNK`] rays).
    #[inline(always)]
    pub(crate) fn new<P: PrimitiveSet>(prims: &P, chunk: &[(Ray, f32)]) -> Self {
        let mut sorted = Sorted {
            members: [[0; CHUNK]; CLASSES],
            len: [0; CLASSES],
        };
        for (i, (ray, _)) in chunk.iter().enumerate() {
            let class = prims.packet_class(ray).min(CLASSES - 1);
            sorted.members[class][sorted.len[class]] = i as u16;
            sorted.len[class] += 1;
        }
        sorted
    }

    /// The packets' members: runs of at most [`PACKET`] rays of one class.
    pub(crate) fn groups(&self) -> impl Iterator<Item = &[u16]> {
        self.members
            .iter()
            .zip(self.len)
            .flat_map(|(m, len)| m[..len].chunks(PACKET))
    }
}

/// The packet of `group` (places in the chunk of `rays` starting at `base`), and its rays'
/// `t_max`; lanes past the group's end repeat its last ray.
#[inline(always)]
pub(crate) fn packet_of<P: PrimitiveSet>(
    prims: &P,
    rays: &[(Ray, f32)],
    base: usize,
    group: &[u16],
) -> (RayPacket<P::RayData>, [f32; PACKET]) {
    let at = |j: usize| base + group[j.min(group.len() - 1)] as usize;
    let rays_of: [Ray; PACKET] = std::array::from_fn(|j| rays[at(j)].0);
    let packet = RayPacket {
        data: std::array::from_fn(|j| prims.prepare(&rays_of[j])),
        rays: rays_of,
        mask: (1u32 << group.len()) - 1,
        index: std::array::from_fn(at),
    };
    (packet, std::array::from_fn(|j| rays[at(j)].1))
}
