//! Connections through parallel layers in closed form: the common case of a camera connection
//! through a flat pane (the table or the background seen through the glass, or a point on the
//! glass seen through itself).
//!
//! When every interface of a chain is a plane with one normal m, the chain is a stack of
//! layers of heights H_k (measured along m) and indices n_k, and Snell's law keeps
//! s = n_k·sin θ_k the same in every layer (the ray's direction across m is conserved). The
//! chain from x reaches, at the height of the lens point L, the distance across m
//!
//!   D(s) = Σ_k H_k·s/√(n_k² − s²),
//!
//! which grows monotonically from 0 (s = 0, along m) to infinity (s → 1 in the air layers), so
//! D(s) = |L − x|⊥ has exactly one solution: found by Newton's method in s, safeguarded by
//! bisection (a one-dimensional solve instead of a two-dimensional Newton iteration whose
//! Jacobian costs four more chain traces per step).
//!
//! The generalised geometry term follows from the same map. With the launch direction at angle
//! θ₀ to m (sin θ₀ = s/n₀) and azimuth φ, a landing point at distance D and azimuth φ on the plane
//! through L normal to m has dA_m = D·dD·dφ and dω = sin θ₀·dθ₀·dφ, so
//!
//!   dω/dA_m = (s/n₀²) / (cos θ₀·D(s)·D′(s)),   D′(s) = Σ_k H_k·n_k²/(n_k² − s²)^{3/2},
//!
//! (→ 1/(n₀²·Q²), Q = Σ H_k/n_k, as s → 0), and on the aperture plane (normal a) dω/dA_L =
//! dω/dA_m·|w·a|/|w·m| for the arriving direction w. Without glass this is cos θ_L/r², the
//! straight connection's term (tested). The chain's Fresnel transmission and absorption still
//! come from tracing the solved direction (`connect::follow_chain`), which also confirms that it
//! crosses the same planes and lands on L; a chain that does not is solved by the general
//! Newton method instead.

use nalgebra::{Point3, Vector3};

/// One interface of a traced chain: where it was crossed and the media on either side.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Interface {
    /// The crossing point (m).
    pub point: Point3<f64>,
    /// The shading normal there (unit, either orientation).
    pub normal: Vector3<f64>,
    /// Refractive index of the medium the ray came from (1 for air).
    pub index_before: f64,
}

/// Interfaces with normals within this angle (rad) of the first one count as parallel: the
/// closed form is then exact to f64 rounding.
const PARALLEL_RAD: f64 = 1e-12;

/// The launch direction and geometry term of a chain through parallel layers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayeredSolution {
    /// Launch direction at x (unit).
    pub dir: Vector3<f64>,
    /// dω/dA on the aperture plane at L (1/m²), for aperture normal `axis`.
    pub dw_da: f64,
}

/// Solves the chain from `x` to `lens` through `interfaces` (in the order crossed) if they
/// are parallel planes; `axis` is the aperture plane's normal. `None` if they are not parallel
/// or the chain is not a stack crossed in one direction.
pub fn solve_layered(
    x: &Point3<f64>,
    interfaces: &[Interface],
    lens: &Point3<f64>,
    axis: &Vector3<f64>,
) -> Option<LayeredSolution> {
    let first = interfaces.first()?;
    let chord = lens - x;
    let mut m = first.normal;
    if m.dot(&chord) < 0.0 {
        m = -m;
    }
    if m.dot(&chord) <= 0.0 {
        return None;
    }
    // Heights of the layers along m, each with its index: x → interface 1 → … → L.
    let mut layers = [(0.0, 1.0); 16];
    let mut count = 0;
    let mut previous = m.dot(&x.coords);
    for f in interfaces {
        if f.normal.cross(&m).norm() > PARALLEL_RAD || count + 1 >= layers.len() {
            return None;
        }
        let h = m.dot(&f.point.coords);
        if h < previous {
            return None;
        }
        layers[count] = (h - previous, f.index_before);
        count += 1;
        previous = h;
    }
    let top = m.dot(&lens.coords);
    if top < previous {
        return None;
    }
    layers[count] = (top - previous, 1.0);
    count += 1;
    let layers = &layers[..count];
    let across = chord - m * m.dot(&chord);
    let target = across.norm();
    let n0 = layers[0].1;
    let axis_cos = |w: &Vector3<f64>| w.dot(axis).abs();
    if target < 1e-15 {
        // Along m: the limit s → 0 of the geometry term.
        let q: f64 = layers.iter().map(|&(h, n)| h / n).sum();
        let dw_dam = 1.0 / (n0 * n0 * q * q);
        return Some(LayeredSolution {
            dir: m,
            dw_da: dw_dam * axis_cos(&m),
        });
    }
    let u = across / target;
    let s_max = layers.iter().map(|&(_, n)| n).fold(f64::INFINITY, f64::min);
    let d_of = |s: f64| -> (f64, f64) {
        layers.iter().fold((0.0, 0.0), |(d, dd), &(h, n)| {
            let c2 = n * n - s * s;
            (d + h * s / c2.sqrt(), dd + h * n * n / (c2 * c2.sqrt()))
        })
    };
    // Newton on s in (0, s_max), kept inside a shrinking bracket. It starts where the chain
    // would land if every layer were air (D_air(s) = H·s/√(1 − s²) = target): glass layers only
    // shorten D, so this start lies left of the root, and on the convex, increasing D(s) the
    // first step lands right of it and the rest converge from the right, 4–5 evaluations in
    // all (from s_max/2 it took 8–70 on edge_study_bare, the bisection safeguard often firing).
    // It stops once D(s) is within 1e-15 of the target, far inside the 1e-12 the solution must
    // meet below and the 1e-10 m the traced chain must land within.
    let (mut lo, mut hi) = (0.0, s_max);
    let height: f64 = layers.iter().map(|&(h, _)| h).sum();
    let mut s = target / (target * target + height * height).sqrt();
    if !(s > 0.0 && s < s_max) {
        s = 0.5 * s_max;
    }
    for _ in 0..100 {
        let (d, dd) = d_of(s);
        let r = d - target;
        if r.abs() <= 1e-15 * target {
            break;
        }
        if r > 0.0 {
            hi = s;
        } else {
            lo = s;
        }
        let mut next = s - r / dd;
        if next.is_nan() || next <= lo || next >= hi {
            next = 0.5 * (lo + hi);
        }
        if (next - s).abs() <= 1e-16 * s_max {
            s = next;
            break;
        }
        s = next;
    }
    let (d, dd) = d_of(s);
    let residual = (d - target).abs();
    if residual.is_nan() || residual > 1e-12 * target.max(1e-3) {
        return None;
    }
    let sin0 = s / n0;
    let cos0 = (1.0 - sin0 * sin0).sqrt();
    let dir = u * sin0 + m * cos0;
    let arrive = u * s + m * (1.0 - s * s).sqrt();
    let dw_dam = (s / (n0 * n0)) / (cos0 * d * dd);
    Some(LayeredSolution {
        dir,
        dw_da: dw_dam * axis_cos(&arrive) / arrive.dot(&m),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_glass_the_geometry_term_is_the_straight_one() {
        // A single "interface" of air on both sides: the chain is straight and
        // dω/dA_L = cos θ_L / r² (inverse-square law with the aperture's obliquity).
        let x = Point3::new(0.01, -0.02, 0.0);
        let lens = Point3::new(0.05, 0.1, 0.3);
        let axis = Vector3::new(0.1, -0.2, -1.0).normalize();
        let f = Interface {
            point: Point3::new(0.0, 0.0, 0.1),
            normal: Vector3::z(),
            index_before: 1.0,
        };
        let sol = solve_layered(&x, &[f], &lens, &axis).unwrap();
        let r = lens - x;
        assert!((sol.dir - r.normalize()).norm() < 1e-12);
        let expected = sol.dir.dot(&axis).abs() / r.norm_squared();
        assert!(
            (sol.dw_da / expected - 1.0).abs() < 1e-9,
            "{} vs {expected}",
            sol.dw_da
        );
    }

    #[test]
    fn a_slab_solution_obeys_snell_and_lands_on_the_lens() {
        // x on the table, a 4 mm pane from z = 1 mm to 5 mm, the lens 300 mm up and 100 mm
        // across: follow the solved direction through both faces by Snell and land on L.
        let n = 1.5208;
        let x = Point3::new(0.0, 0.0, 0.0);
        let lens = Point3::new(0.1, 0.02, 0.3);
        let faces = [
            Interface {
                point: Point3::new(0.0, 0.0, 1e-3),
                normal: Vector3::z(),
                index_before: 1.0,
            },
            Interface {
                point: Point3::new(0.0, 0.0, 5e-3),
                normal: -Vector3::z(),
                index_before: n,
            },
        ];
        let sol = solve_layered(&x, &faces, &lens, &-Vector3::z()).unwrap();
        let refract = |w: Vector3<f64>, ratio: f64| {
            let s = Vector3::new(w.x, w.y, 0.0) * ratio;
            Vector3::new(s.x, s.y, (1.0 - s.norm_squared()).sqrt())
        };
        let mut p = x + sol.dir * (1e-3 / sol.dir.z);
        let w1 = refract(sol.dir, 1.0 / n);
        p += w1 * (4e-3 / w1.z);
        let w2 = refract(w1, n);
        p += w2 * ((lens.z - p.z) / w2.z);
        assert!((p - lens).norm() < 1e-12, "{:?}", p - lens);
        assert!(
            (w2 - sol.dir).norm() < 1e-12,
            "a slab does not turn the ray"
        );
        // The geometry term against central differences of the landing map.
        let land = |w: Vector3<f64>| {
            let mut p = x + w * (1e-3 / w.z);
            let w1 = refract(w, 1.0 / n);
            p += w1 * (4e-3 / w1.z);
            let w2 = refract(w1, n);
            p + w2 * ((lens.z - p.z) / w2.z)
        };
        let (t1, t2) = crate::optics::lambert::orthonormal_basis(&sol.dir);
        let h = 1e-7;
        let dx = (land((sol.dir + t1 * h).normalize()) - land((sol.dir - t1 * h).normalize()))
            / (2.0 * h);
        let dy = (land((sol.dir + t2 * h).normalize()) - land((sol.dir - t2 * h).normalize()))
            / (2.0 * h);
        // Landing on the plane z = lens.z (normal −z = the axis here): area per solid angle.
        let area = (dx.x * dy.y - dx.y * dy.x).abs();
        assert!(
            (sol.dw_da * area - 1.0).abs() < 1e-6,
            "{}",
            sol.dw_da * area
        );
    }

    #[test]
    fn tilted_or_folded_interfaces_are_refused() {
        let x = Point3::origin();
        let lens = Point3::new(0.0, 0.0, 0.3);
        let a = Interface {
            point: Point3::new(0.0, 0.0, 0.1),
            normal: Vector3::z(),
            index_before: 1.0,
        };
        let tilted = Interface {
            point: Point3::new(0.0, 0.0, 0.104),
            normal: Vector3::new(0.0, 0.01, 1.0).normalize(),
            index_before: 1.5,
        };
        assert_eq!(solve_layered(&x, &[a, tilted], &lens, &-Vector3::z()), None);
        let back = Interface {
            point: Point3::new(0.0, 0.0, 0.05),
            ..tilted
        };
        let back = Interface {
            normal: Vector3::z(),
            ..back
        };
        assert_eq!(solve_layered(&x, &[a, back], &lens, &-Vector3::z()), None);
    }
}
