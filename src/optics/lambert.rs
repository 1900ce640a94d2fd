//! The Lambertian (ideal diffuse) reflector: f = ρ/π.

use nalgebra::Vector3;

use super::warp::{cosine_hemisphere, cosine_hemisphere_pdf};

/// An ideal diffuse reflector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lambertian {
    /// Hemispherical reflectance ρ in [0, 1].
    pub albedo: f64,
}

impl Lambertian {
    /// BRDF value ρ/π for directions on the same side as `n` (1/sr), zero otherwise.
    pub fn f(&self, n: &Vector3<f64>, wo: &Vector3<f64>, wi: &Vector3<f64>) -> f64 {
        if n.dot(wo) > 0.0 && n.dot(wi) > 0.0 {
            self.albedo / std::f64::consts::PI
        } else {
            0.0
        }
    }

    /// Samples `wi` with density cos θ/π around `n` and returns it with its pdf (1/sr).
    pub fn sample_wi(&self, n: &Vector3<f64>, u: [f64; 2]) -> (Vector3<f64>, f64) {
        let [x, y, z] = cosine_hemisphere(u);
        let (t, b) = orthonormal_basis(n);
        let wi = (t * x + b * y + n * z).normalize();
        (wi, cosine_hemisphere_pdf(z))
    }
}

/// Two unit vectors that complete `n` to a right-handed orthonormal frame (Duff et al. 2017,
/// "Building an Orthonormal Basis, Revisited", JCGT 6(1)).
pub fn orthonormal_basis(n: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vector3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vector3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal() {
        for n in [
            Vector3::z(),
            -Vector3::z(),
            Vector3::new(0.3, -0.4, 0.866).normalize(),
        ] {
            let (t, b) = orthonormal_basis(&n);
            assert!(t.dot(&b).abs() < 1e-12 && t.dot(&n).abs() < 1e-12 && b.dot(&n).abs() < 1e-12);
            assert!((t.cross(&b) - n).norm() < 1e-12);
        }
    }

    #[test]
    fn white_furnace_estimate_is_the_albedo() {
        // ∫ f cos θ dω = ρ, estimated with the sampling routine's own pdf.
        let m = Lambertian { albedo: 0.7 };
        let n = Vector3::new(0.1, 0.2, 0.97).normalize();
        let k = 10_000;
        let est: f64 = (0..k)
            .map(|i| {
                let u = [(i as f64 + 0.5) / k as f64, (i as f64 * 0.618_034).fract()];
                let (wi, pdf) = m.sample_wi(&n, u);
                m.f(&n, &n, &wi) * n.dot(&wi) / pdf
            })
            .sum::<f64>()
            / k as f64;
        assert!((est - 0.7).abs() < 1e-9, "{est}");
    }
}
