//! The photon map: photons in a balanced k-d tree (Jensen, "Realistic Image Synthesis
//! Using Photon Mapping", 2001, section 6.3), kept implicitly: the photons of a subtree
//! occupy a range of the array with the splitting photon at its middle, so the tree needs
//! no nodes, only each photon's splitting axis. Queries visit the photons in an order fixed
//! by the array, so sums over them do not depend on threads.

use super::Photon;
use glam::Vec3;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

pub struct PhotonMap {
    photons: Vec<Photon>,
    /// The splitting axis of the subtree whose middle is each photon.
    axes: Vec<u8>,
}

/// Subtrees smaller than this are built on the calling thread.
const PARALLEL_BUILD: usize = 8192;

/// Deeper than any balanced tree of addressable photons (2 log2 n pushes at most).
const STACK: usize = 128;

impl PhotonMap {
    /// The tree over `photons` (median splits along the widest axis of each subtree).
    pub fn build(mut photons: Vec<Photon>) -> Self {
        let mut axes = vec![0u8; photons.len()];
        build(&mut photons, &mut axes);
        PhotonMap { photons, axes }
    }

    pub fn len(&self) -> usize {
        self.photons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    /// Calls `visit` with every photon within squared distance `r2` of `p`.
    pub fn within(&self, p: Vec3, r2: f32, mut visit: impl FnMut(&Photon)) {
        self.search(
            p,
            || r2,
            |_, ph, d2| {
                if d2 <= r2 {
                    visit(ph);
                }
            },
        );
    }

    /// The `k` photons nearest to `p` among those `keep` accepts and within squared
    /// distance `r2_max`, into `out` (nearest first), and the squared radius of the disc that
    /// holds them: the k-th distance, or `r2_max` when fewer were found.
    pub fn nearest(&self, p: Vec3, k: usize, r2_max: f32, keep: impl Fn(&Photon) -> bool, out: &mut Vec<u32>) -> f32 {
        let mut heap: BinaryHeap<Near> = BinaryHeap::with_capacity(k + 1);
        let bound = std::cell::Cell::new(r2_max);
        self.search(
            p,
            || bound.get(),
            |index, ph, d2| {
                if k == 0 || d2 > bound.get() || !keep(ph) {
                    return;
                }
                heap.push(Near { d2, index });
                if heap.len() > k {
                    heap.pop();
                }
                if heap.len() == k {
                    bound.set(heap.peek().map_or(r2_max, |n| n.d2));
                }
            },
        );
        out.clear();
        let full = heap.len() == k;
        out.extend(heap.into_sorted_vec().iter().map(|n| n.index));
        if full {
            bound.get()
        } else {
            r2_max
        }
    }

    pub fn photon(&self, index: u32) -> &Photon {
        &self.photons[index as usize]
    }

    /// Walks the tree towards `p`, entering a far subtree only when its splitting plane
    /// is within the current squared bound (checked again when it is taken from the stack:
    /// the bound of a k-nearest query shrinks meanwhile); `visit` gets each photon met, its
    /// index and its squared distance.
    fn search(&self, p: Vec3, bound: impl Fn() -> f32, mut visit: impl FnMut(u32, &Photon, f32)) {
        // (range, squared distance of `p` to the plane that separates it from `p`'s side).
        let mut stack = [(0u32, 0u32, 0f32); STACK];
        stack[0] = (0, self.photons.len() as u32, 0.0);
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (lo, hi, plane) = stack[top];
            if lo >= hi || plane > bound() {
                continue;
            }
            let mid = lo + (hi - lo) / 2;
            let ph = &self.photons[mid as usize];
            let axis = self.axes[mid as usize] as usize;
            let d = p[axis] - ph.p[axis];
            visit(mid, ph, ph.p.distance_squared(p));
            let (near, far) = if d <= 0.0 {
                ((lo, mid), (mid + 1, hi))
            } else {
                ((mid + 1, hi), (lo, mid))
            };
            if d * d <= bound() && top < STACK {
                stack[top] = (far.0, far.1, d * d);
                top += 1;
            }
            if top < STACK {
                stack[top] = (near.0, near.1, plane);
                top += 1;
            }
        }
    }
}

/// A photon found by [`PhotonMap::nearest`], ordered by distance (the heap's top is the
/// farthest; ties by index, so the set found does not depend on the visiting order).
struct Near {
    d2: f32,
    index: u32,
}

impl PartialEq for Near {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}

impl Eq for Near {}

impl PartialOrd for Near {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

impl Ord for Near {
    fn cmp(&self, o: &Self) -> Ordering {
        self.d2.total_cmp(&o.d2).then(self.index.cmp(&o.index))
    }
}

fn build(photons: &mut [Photon], axes: &mut [u8]) {
    if photons.is_empty() {
        return;
    }
    let (lo, hi) = photons
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), ph| {
            (lo.min(ph.p), hi.max(ph.p))
        });
    let extent = hi - lo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mid = photons.len() / 2;
    photons.select_nth_unstable_by(mid, |a, b| a.p[axis].total_cmp(&b.p[axis]));
    axes[mid] = axis as u8;
    let (left, rest) = photons.split_at_mut(mid);
    let (left_axes, rest_axes) = axes.split_at_mut(mid);
    let (right, right_axes) = (&mut rest[1..], &mut rest_axes[1..]);
    if left.len() > PARALLEL_BUILD {
        rayon::join(|| build(left, left_axes), || build(right, right_axes));
    } else {
        build(left, left_axes);
        build(right, right_axes);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_core::{Pcg32, Rgb};

    fn random_photons(n: usize, seed: u64) -> Vec<Photon> {
        let mut rng = Pcg32::new(seed, 0);
        (0..n)
            .map(|i| Photon {
                p: Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32() * 0.1),
                wi: Vec3::Z,
                n: Vec3::Z,
                power: Rgb::new(i as f32, 0.0, 0.0),
                segments: 1,
                caustic: false,
            })
            .collect()
    }

    /// Both queries find exactly what a brute-force scan finds, at many random points
    /// (including ties and empty answers).
    #[test]
    fn queries_match_brute_force() {
        let photons = random_photons(5000, 1);
        let map = PhotonMap::build(photons.clone());
        let mut rng = Pcg32::new(2, 0);
        let mut out = Vec::new();
        for _ in 0..300 {
            let p = Vec3::new(rng.next_f32() * 1.2 - 0.1, rng.next_f32() * 1.2 - 0.1, 0.05);
            let r2 = rng.next_f32() * 0.01;
            let mut found: Vec<u32> = Vec::new();
            map.within(p, r2, |ph| found.push(ph.power.r as u32));
            found.sort();
            let expected: Vec<u32> = photons
                .iter()
                .filter(|ph| ph.p.distance_squared(p) <= r2)
                .map(|ph| ph.power.r as u32)
                .collect();
            assert_eq!(found, expected);

            let k = 1 + (rng.next_f32() * 40.0) as usize;
            let r2_max = 0.02;
            let keep = |ph: &Photon| !(ph.power.r as u32).is_multiple_of(3);
            let got_r2 = map.nearest(p, k, r2_max, keep, &mut out);
            let mut got: Vec<u32> = out.iter().map(|&i| map.photon(i).power.r as u32).collect();
            got.sort();
            let mut by_distance: Vec<(f32, u32)> = photons
                .iter()
                .filter(|ph| keep(ph) && ph.p.distance_squared(p) <= r2_max)
                .map(|ph| (ph.p.distance_squared(p), ph.power.r as u32))
                .collect();
            by_distance.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            by_distance.truncate(k);
            let expected_r2 = if by_distance.len() == k {
                by_distance[k - 1].0
            } else {
                r2_max
            };
            let mut expected: Vec<u32> = by_distance.iter().map(|x| x.1).collect();
            expected.sort();
            assert_eq!(got, expected);
            assert_eq!(got_r2, expected_r2);
        }
    }
}
