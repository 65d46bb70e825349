//! pbrt-v4's environment maps: square images in Clarberg's equal-area octahedral mapping
//! ("Fast Equal-Area Mapping of the (Hemi)Sphere using SIMD", 2008; pbrt-v4's
//! `EqualAreaSphereToSquare`, section 3.8.3 of the 4th edition), resampled into the
//! equirectangular maps our [`penumbra_render::lights::Environment`] samples.

use glam::{Vec2, Vec3};
use penumbra_core::Rgb;
use penumbra_render::texture::{TextureImage, Wrap};
use std::f32::consts::PI;

/// The point of the unit square (x right, y down the image) that direction `d` (unit)
/// maps to: +z at the centre, -z at the four corners, the z = 0 circle on the diamond
/// between the edges' midpoints; equal solid angles map to equal areas.
pub fn sphere_to_square(d: Vec3) -> Vec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = (1.0 - z).max(0.0).sqrt();
    let (a, b) = (x.max(y), x.min(y));
    let b = if a == 0.0 { 0.0 } else { b / a };
    let mut phi = b.atan() * 2.0 / PI;
    if x < y {
        phi = 1.0 - phi;
    }
    let mut v = phi * r;
    let mut u = r - v;
    if d.z < 0.0 {
        (u, v) = (1.0 - v, 1.0 - u);
    }
    Vec2::new(0.5 * (u.copysign(d.x) + 1.0), 0.5 * (v.copysign(d.y) + 1.0))
}

/// The equirectangular map (2n x n for an n x n octahedral `map`) of the same
/// environment: each pixel the octahedral map, bilinearly filtered, in the direction of the
/// pixel's centre under our mapping (Mitsuba's: (sin φ sin θ, cos θ, −cos φ sin θ) at
/// (φ / 2π, θ / π)), with pbrt's light-space axes taken as ours.
pub fn to_equirect(map: &TextureImage) -> TextureImage {
    let n = map.width.max(2);
    let (w, h) = (2 * n, n);
    let clamped = TextureImage {
        wrap: [Wrap::Clamp; 2],
        ..map.clone()
    };
    let pixels = (0..w * h)
        .map(|i| {
            let (phi, theta) = (
                2.0 * PI * ((i % w) as f32 + 0.5) / w as f32,
                PI * ((i / w) as f32 + 0.5) / h as f32,
            );
            let d = Vec3::new(phi.sin() * theta.sin(), theta.cos(), -phi.cos() * theta.sin());
            let st = sphere_to_square(d);
            // Our images' v runs up from the bottom row; pbrt's y runs down from the top.
            clamped.bilinear(Vec2::new(st.x, 1.0 - st.y))
        })
        .collect::<Vec<Rgb>>();
    TextureImage {
        width: w,
        height: h,
        pixels,
        wrap: Default::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_testkit::{chi2_test, Grid2, Uniforms};

    #[test]
    fn axes_land_where_pbrt_puts_them() {
        let at = |d: Vec3| sphere_to_square(d);
        assert!((at(Vec3::Z) - Vec2::new(0.5, 0.5)).length() < 1e-6);
        assert!((at(Vec3::X) - Vec2::new(1.0, 0.5)).length() < 1e-6);
        assert!((at(Vec3::NEG_X) - Vec2::new(0.0, 0.5)).length() < 1e-6);
        assert!((at(Vec3::Y) - Vec2::new(0.5, 1.0)).length() < 1e-6);
        assert!((at(Vec3::NEG_Y) - Vec2::new(0.5, 0.0)).length() < 1e-6);
        let corner = at(Vec3::new(1e-7, 1e-7, -1.0));
        assert!((corner - Vec2::new(1.0, 1.0)).length() < 1e-3, "{corner}");
    }

    /// Equal area: uniform directions fill the square uniformly (chi-square over 8 x 8
    /// cells, 64,000 directions).
    #[test]
    fn the_mapping_keeps_areas() {
        let mut rng = Uniforms::new(5);
        let grid = Grid2 {
            min: [0.0, 0.0],
            max: [1.0, 1.0],
            bins: [8, 8],
        };
        let sample = || {
            let u = rng.next_vec2();
            let z = 1.0 - 2.0 * u.x;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let d = Vec3::new(r * (2.0 * PI * u.y).cos(), r * (2.0 * PI * u.y).sin(), z);
            let st = sphere_to_square(d);
            Some([st.x as f64, st.y as f64])
        };
        chi2_test(grid, 64_000, sample, |_| 1.0).assert_fits("equal-area mapping", 1);
    }

    /// The equirectangular map shows, in each direction, what the octahedral map holds
    /// there: a map bright only around +x and +y is bright at φ = 90°, θ = 90° (our +x)
    /// and at θ = 0 (our +y), and dark opposite them.
    #[test]
    fn resampling_keeps_directions() {
        let n = 32;
        let pixels = (0..n * n)
            .map(|i| {
                let st = Vec2::new(((i % n) as f32 + 0.5) / n as f32, ((i / n) as f32 + 0.5) / n as f32);
                // Bright around pbrt's +x, (1, 0.5) in (x right, y down), and its +y,
                // (0.5, 1): the bottom edge's middle (this one checks the rows' direction).
                if (st - Vec2::new(0.97, 0.5)).length() < 0.06 || (st - Vec2::new(0.5, 0.97)).length() < 0.06 {
                    Rgb::WHITE
                } else {
                    Rgb::BLACK
                }
            })
            .collect();
        let map = TextureImage {
            width: n,
            height: n,
            pixels,
            wrap: Default::default(),
        };
        let e = to_equirect(&map);
        let at = |phi: f32, theta: f32| {
            let (x, y) = (
                (phi / 360.0 * e.width as f32) as usize,
                (theta / 180.0 * e.height as f32) as usize,
            );
            e.pixels[y * e.width + x].r
        };
        assert!(at(90.0, 90.0) > 0.9, "{}", at(90.0, 90.0));
        assert_eq!(at(270.0, 90.0), 0.0);
        assert_eq!(at(0.0, 30.0), 0.0);
        // pbrt's +y is ours: straight up (θ = 0), not down.
        assert!(at(45.0, 3.0) > 0.9, "{}", at(45.0, 3.0));
        assert_eq!(at(45.0, 177.0), 0.0);
    }
}
