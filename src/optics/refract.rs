//! Specular reflection and refraction of directions (law of reflection, Snell's law).
//!
//! Directions point away from the surface (see the module docs of `optics`): `wo`/`wi` is the
//! direction back towards where the light came from, the result the direction it leaves in.

use nalgebra::Vector3;

/// Mirror image of `wo` about the unit normal `n`: 2(wo·n)n − wo. Works on either side of the
/// surface (the result is on the same side as `wo`); `wo` unit gives a unit result.
pub fn reflect(wo: &Vector3<f64>, n: &Vector3<f64>) -> Vector3<f64> {
    2.0 * wo.dot(n) * n - wo
}

/// Refracts the unit direction `wi` through the surface with unit normal `n`, where `eta` is
/// the relative index n_t/n_i for light arriving from the side `n` points into (pbrt-v4
/// `Refract`, *PBR* 4th ed., §9.3: with n pointing out of glass, η = n_glass/n_air).
///
/// If `wi` lies on the other side of the surface, the normal is flipped and η inverted. Returns
/// the unit transmitted direction (on the opposite side of `wi`) and the relative index η′
/// actually used, or `None` under total internal reflection. The tangential part obeys
/// n_i sin θ_i = n_t sin θ_t: wt = −wi/η′ + (cos θ_i/η′ − cos θ_t)·n.
pub fn refract(wi: &Vector3<f64>, n: &Vector3<f64>, eta: f64) -> Option<(Vector3<f64>, f64)> {
    debug_assert!((wi.norm() - 1.0).abs() < 1e-9 && (n.norm() - 1.0).abs() < 1e-9);
    let mut cos_i = n.dot(wi);
    let (n, eta) = if cos_i < 0.0 {
        cos_i = -cos_i;
        (-n, 1.0 / eta)
    } else {
        (*n, eta)
    };
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    // The formula is exactly unit for unit inputs; renormalise only to remove rounding, so that
    // long chains of refractions cannot drift.
    let wt = (-wi / eta + (cos_i / eta - cos_t) * n).normalize();
    Some((wt, eta))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_passes_straight_through() {
        let z = Vector3::z();
        let (wt, etap) = refract(&z, &z, 1.5).unwrap();
        assert!((wt + z).norm() < 1e-15 && etap == 1.5);
        let (wt, etap) = refract(&-z, &z, 1.5).unwrap();
        assert!((wt - z).norm() < 1e-15 && etap == 1.0 / 1.5);
    }

    #[test]
    fn refraction_is_reversible() {
        // Light reversed along wt comes back along wi (Helmholtz reciprocity of Snell's law).
        let n = Vector3::new(0.1, -0.2, 0.9).normalize();
        let (t, b) = crate::optics::lambert::orthonormal_basis(&n);
        for k in 0..50 {
            let phi = k as f64 * 0.7;
            let theta = 1.5 * k as f64 / 50.0;
            let wi =
                (t * (theta.sin() * phi.cos()) + b * (theta.sin() * phi.sin()) + n * theta.cos())
                    .normalize();
            let (wt, etap) = refract(&wi, &n, 1.5208).unwrap();
            let (back, etap2) = refract(&wt, &n, 1.5208).unwrap();
            assert!((back - wi).norm() < 1e-12 && (etap * etap2 - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn total_internal_reflection_has_no_refracted_ray() {
        let n = Vector3::z();
        let theta: f64 = 0.75; // > asin(1/1.5) = 0.7297 rad, from inside.
        let wi = Vector3::new(theta.sin(), 0.0, -theta.cos());
        assert!(refract(&wi, &n, 1.5).is_none());
    }
}
