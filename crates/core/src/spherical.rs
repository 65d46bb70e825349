//! Sampling the solid angle a triangle or a rectangle subtends: directions uniform over
//! the spherical polygon, density 1 / (solid angle). Triangles after Arvo, "Stratified
//! Sampling of Spherical Triangles" (SIGGRAPH 1995), rectangles after Ureña, Fajardo and
//! King, "An Area-Preserving Parametrization for Spherical Rectangles" (EGSR 2013), both
//! in the form pbrt-v4 gives them (section 6.5). The arithmetic is in double precision:
//! both methods subtract nearly equal angles when the polygon is small.

use glam::{DVec3, Vec2, Vec3};
use std::f64::consts::PI;

/// Below this solid angle (steradians) the methods lose their accuracy; callers sample
/// such polygons by area instead.
pub const MIN_SOLID_ANGLE: f32 = 1e-4;

/// The solid angle of triangle `v` seen from `p` (Van Oosterom and Strackee 1983).
pub fn triangle_solid_angle(p: Vec3, v: [Vec3; 3]) -> f32 {
    let [a, b, c] = v.map(|q| (q - p).as_dvec3().normalize_or_zero());
    let num = a.dot(b.cross(c)).abs();
    let den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
    (2.0 * num.atan2(den)) as f32
}

/// A direction from `p` uniform over the solid angle of triangle `v`, with its density
/// (1 / solid angle); `None` when the triangle is degenerate as seen from `p` or subtends
/// less than [`MIN_SOLID_ANGLE`].
pub fn sample_triangle(p: Vec3, v: [Vec3; 3], u: Vec2) -> Option<(Vec3, f32)> {
    let [a, b, c] = v.map(|q| (q - p).as_dvec3().normalize_or_zero());
    let (n_ab, n_bc, n_ca) = (
        a.cross(b).normalize_or_zero(),
        b.cross(c).normalize_or_zero(),
        c.cross(a).normalize_or_zero(),
    );
    if n_ab == DVec3::ZERO || n_bc == DVec3::ZERO || n_ca == DVec3::ZERO {
        return None;
    }
    // The spherical triangle's angles at a, b and c, and its area.
    let alpha = angle_between(n_ab, -n_ca);
    let beta = angle_between(n_bc, -n_ab);
    let gamma = angle_between(n_ca, -n_bc);
    let area = alpha + beta + gamma - PI;
    if area.is_nan() || area < MIN_SOLID_ANGLE as f64 {
        return None;
    }
    // The sub-triangle (a, b, c') with area u0 * area: find c' on the arc a-c.
    let area_pi = PI + u.x as f64 * area;
    let (sin_alpha, cos_alpha) = alpha.sin_cos();
    let (sin_ap, cos_ap) = area_pi.sin_cos();
    let sin_phi = sin_ap * cos_alpha - cos_ap * sin_alpha;
    let cos_phi = cos_ap * cos_alpha + sin_ap * sin_alpha;
    let k1 = cos_phi + cos_alpha;
    let k2 = sin_phi - sin_alpha * a.dot(b);
    let cos_bp = ((k2 + (k2 * cos_phi - k1 * sin_phi) * cos_alpha) / ((k2 * sin_phi + k1 * cos_phi) * sin_alpha))
        .clamp(-1.0, 1.0);
    let sin_bp = (1.0 - cos_bp * cos_bp).max(0.0).sqrt();
    let cp = cos_bp * a + sin_bp * gram_schmidt(c, a);
    // Then a point on the arc b-c' by u1, uniform in area.
    let cos_theta = 1.0 - u.y as f64 * (1.0 - cp.dot(b));
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let w = cos_theta * b + sin_theta * gram_schmidt(cp, b);
    Some((w.normalize().as_vec3(), (1.0 / area) as f32))
}

/// A rectangle as seen from a point, in the frame of Ureña et al.: x and y along the edges,
/// z away from the point; the rectangle spans [x0, x1] x [y0, y1] at depth z0 < 0.
struct RectangleView {
    frame: [DVec3; 3],
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    z0: f64,
    /// z components of the normals of the first and third edge planes.
    b0: f64,
    b1: f64,
    /// The spherical rectangle's interior angles, and its area.
    g: [f64; 4],
    solid_angle: f64,
}

impl RectangleView {
    /// `None` when `p` lies in the rectangle's plane.
    fn new(p: Vec3, corner: Vec3, ex: Vec3, ey: Vec3) -> Option<Self> {
        let (exl, eyl) = (ex.length() as f64, ey.length() as f64);
        let x = ex.as_dvec3() / exl;
        let y = ey.as_dvec3() / eyl;
        let mut z = x.cross(y);
        let d = (corner - p).as_dvec3();
        let (x0, y0, mut z0) = (d.dot(x), d.dot(y), d.dot(z));
        // Work with the rectangle below the reference point's local frame.
        if z0 > 0.0 {
            z = -z;
            z0 = -z0;
        }
        if z0 == 0.0 {
            return None;
        }
        let (x1, y1) = (x0 + exl, y0 + eyl);
        let v00 = DVec3::new(x0, y0, z0);
        let v01 = DVec3::new(x0, y1, z0);
        let v10 = DVec3::new(x1, y0, z0);
        let v11 = DVec3::new(x1, y1, z0);
        let n0 = v00.cross(v10).normalize();
        let n1 = v10.cross(v11).normalize();
        let n2 = v11.cross(v01).normalize();
        let n3 = v01.cross(v00).normalize();
        let g = [
            angle_between(-n0, n1),
            angle_between(-n1, n2),
            angle_between(-n2, n3),
            angle_between(-n3, n0),
        ];
        Some(RectangleView {
            frame: [x, y, z],
            x0,
            x1,
            y0,
            y1,
            z0,
            b0: n0.z,
            b1: n2.z,
            g,
            solid_angle: g.iter().sum::<f64>() - 2.0 * PI,
        })
    }
}

/// The solid angle of the rectangle with corner `corner` and perpendicular edges `ex`,
/// `ey`, seen from `p` (zero from a point in its plane).
pub fn rectangle_solid_angle(p: Vec3, corner: Vec3, ex: Vec3, ey: Vec3) -> f32 {
    RectangleView::new(p, corner, ex, ey).map_or(0.0, |v| v.solid_angle as f32)
}

/// A point on the rectangle with corner `corner` and perpendicular edges `ex`, `ey`,
/// uniform over the solid angle it subtends from `p`, with its density (1 / solid angle).
/// `None` for a degenerate view or a solid angle below [`MIN_SOLID_ANGLE`].
pub fn sample_rectangle(p: Vec3, corner: Vec3, ex: Vec3, ey: Vec3, u: Vec2) -> Option<(Vec3, f32)> {
    let RectangleView {
        frame: [x, y, z],
        x0,
        x1,
        y0,
        y1,
        z0,
        b0,
        b1,
        g: [g0, g1, g2, g3],
        solid_angle,
    } = RectangleView::new(p, corner, ex, ey)?;
    if solid_angle.is_nan() || solid_angle < MIN_SOLID_ANGLE as f64 {
        return None;
    }
    // x by inverting the area of the part of the rectangle left of x (u0).
    let au = u.x as f64 * (g0 + g1 - 2.0 * PI) + (u.x as f64 - 1.0) * (g2 + g3);
    let fu = (au.cos() * b0 - b1) / au.sin();
    let cu = (1.0 / (fu * fu + b0 * b0).sqrt())
        .copysign(fu)
        .clamp(-1.0 + 1e-12, 1.0 - 1e-12);
    let xu = (-(cu * z0) / (1.0 - cu * cu).max(0.0).sqrt()).clamp(x0, x1);
    // y uniform in the projected height along that column (u1).
    let dd = (xu * xu + z0 * z0).sqrt();
    let h0 = y0 / (dd * dd + y0 * y0).sqrt();
    let h1 = y1 / (dd * dd + y1 * y1).sqrt();
    let hv = h0 + u.y as f64 * (h1 - h0);
    let yv = if hv * hv < 1.0 - 1e-12 {
        (hv * dd / (1.0 - hv * hv).sqrt()).clamp(y0, y1)
    } else {
        y1
    };
    let point = p.as_dvec3() + xu * x + yv * y + z0 * z;
    Some((point.as_vec3(), (1.0 / solid_angle) as f32))
}

/// The angle between unit vectors, accurate near 0 and π.
fn angle_between(a: DVec3, b: DVec3) -> f64 {
    if a.dot(b) < 0.0 {
        PI - 2.0 * ((a + b).length() / 2.0).clamp(-1.0, 1.0).asin()
    } else {
        2.0 * ((b - a).length() / 2.0).clamp(-1.0, 1.0).asin()
    }
}

/// The unit part of `v` perpendicular to unit `w`.
fn gram_schmidt(v: DVec3, w: DVec3) -> DVec3 {
    (v - v.dot(w) * w).normalize_or_zero()
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_testkit::chi2_directions;
    use std::f32::consts::PI as PI32;

    /// Chi-square tests in this module, for the significance correction.
    const TESTS: usize = 8;
    const N: usize = 300_000;

    /// Whether the ray from `p` along `w` crosses the parallelogram corner + s ex + t ey
    /// (s, t in [0, 1]), or the triangle corner, corner + ex, corner + ey if `triangle`.
    fn crosses(p: Vec3, w: Vec3, corner: Vec3, ex: Vec3, ey: Vec3, triangle: bool) -> bool {
        let (p, w, c, e1, e2) = (
            p.as_dvec3(),
            w.as_dvec3(),
            corner.as_dvec3(),
            ex.as_dvec3(),
            ey.as_dvec3(),
        );
        let h = w.cross(e2);
        let det = e1.dot(h);
        if det.abs() < 1e-14 {
            return false;
        }
        let s = (p - c).dot(h) / det;
        let q = (p - c).cross(e1);
        let t = w.dot(q) / det;
        let dist = e2.dot(q) / det;
        dist > 0.0 && s >= 0.0 && t >= 0.0 && if triangle { s + t <= 1.0 } else { s <= 1.0 && t <= 1.0 }
    }

    #[test]
    fn solid_angles_match_closed_forms() {
        // An octant's triangle seen from the origin: pi/2. A 2 x 2 square at distance 1 seen
        // from above its centre: 4 asin(1/2) = 2 pi / 3 (a cube's face from its centre).
        let octant = [Vec3::X, Vec3::Y, Vec3::Z];
        assert!((triangle_solid_angle(Vec3::ZERO, octant) - PI32 / 2.0).abs() < 1e-5);
        let (_, pdf) = sample_triangle(Vec3::ZERO, octant, Vec2::splat(0.5)).unwrap();
        assert!((1.0 / pdf - PI32 / 2.0).abs() < 1e-5);
        let (_, pdf) = sample_rectangle(
            Vec3::ZERO,
            Vec3::new(-1.0, -1.0, -1.0),
            2.0 * Vec3::X,
            2.0 * Vec3::Y,
            Vec2::ZERO,
        )
        .unwrap();
        assert!((1.0 / pdf - 2.0 * PI32 / 3.0).abs() < 1e-5, "{}", 1.0 / pdf);
        let omega = rectangle_solid_angle(Vec3::ZERO, Vec3::new(-1.0, -1.0, -1.0), 2.0 * Vec3::X, 2.0 * Vec3::Y);
        assert!((omega - 2.0 * PI32 / 3.0).abs() < 1e-5, "{omega}");
    }

    #[test]
    fn triangle_directions_are_uniform_over_the_solid_angle() {
        // (Edges are kept off the test's phi = 0 seam, where rounding would put a direction
        // on the wrong side of the sphere's parametrisation.)
        let cases = [
            (Vec3::new(-0.1, -0.05, -0.02), [Vec3::X, Vec3::Y, Vec3::Z]),
            (
                Vec3::new(0.2, -0.3, 0.1),
                [
                    Vec3::new(-1.0, -1.0, 2.0),
                    Vec3::new(2.0, -0.5, 1.5),
                    Vec3::new(0.0, 2.0, 1.0),
                ],
            ),
            // Far and oblique: a thin spherical triangle.
            (
                Vec3::new(5.0, 0.0, 0.5),
                [
                    Vec3::new(0.0, 0.0, 0.0),
                    Vec3::new(0.0, 2.0, 0.0),
                    Vec3::new(1.0, 1.0, 1.0),
                ],
            ),
        ];
        for (k, (p, v)) in cases.into_iter().enumerate() {
            let omega = triangle_solid_angle(p, v);
            let r = chi2_directions(
                20 + k as u64,
                N,
                |u| sample_triangle(p, v, u).map(|(w, _)| w),
                |w| {
                    if crosses(p, w, v[0], v[1] - v[0], v[2] - v[0], true) {
                        1.0 / omega
                    } else {
                        0.0
                    }
                },
            );
            r.assert_fits(&format!("spherical triangle {k}"), TESTS);
            assert!((r.integral - 1.0).abs() < 2e-3, "triangle {k}: {}", r.describe());
        }
    }

    #[test]
    fn rectangle_points_are_uniform_over_the_solid_angle() {
        let cases = [
            // Above the centre, off to one side, oblique and rotated, and seen from behind.
            // (A view much closer to edge-on makes corners so sharp that the test's
            // quadrature of the density per bin, not the sampler, becomes the weak point.)
            (
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(-1.0, -1.0, 0.0),
                2.0 * Vec3::X,
                2.0 * Vec3::Y,
            ),
            (
                Vec3::new(2.0, 0.5, 0.7),
                Vec3::new(-1.0, -1.0, 0.0),
                2.0 * Vec3::X,
                1.0 * Vec3::Y,
            ),
            (
                Vec3::new(2.5, 0.2, 0.5),
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(-1.5, 1.5, 0.0),
            ),
            (
                Vec3::new(0.3, -0.2, -0.8),
                Vec3::new(-1.0, -1.0, 0.0),
                2.0 * Vec3::X,
                2.0 * Vec3::Y,
            ),
        ];
        for (k, (p, corner, ex, ey)) in cases.into_iter().enumerate() {
            let (_, pdf) = sample_rectangle(p, corner, ex, ey, Vec2::splat(0.5)).unwrap();
            let r = chi2_directions(
                30 + k as u64,
                N,
                |u| {
                    let (q, _) = sample_rectangle(p, corner, ex, ey, u)?;
                    // The point lies on the rectangle.
                    let (s, t) = (
                        (q - corner).dot(ex) / ex.length_squared(),
                        (q - corner).dot(ey) / ey.length_squared(),
                    );
                    assert!(
                        (-1e-4..=1.0001).contains(&s) && (-1e-4..=1.0001).contains(&t),
                        "{s} {t}"
                    );
                    Some((q - p).normalize())
                },
                |w| if crosses(p, w, corner, ex, ey, false) { pdf } else { 0.0 },
            );
            r.assert_fits(&format!("spherical rectangle {k}"), TESTS);
            assert!((r.integral - 1.0).abs() < 2e-3, "rectangle {k}: {}", r.describe());
        }
    }
}
