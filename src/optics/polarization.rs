//! Stokes vectors and Mueller matrices of a beam and of smooth dielectric interfaces.
//!
//! Conventions (the same as Mitsuba 3's `mueller.h` and Chandrasekhar, *Radiative Transfer*,
//! 1950, ch. I):
//! - A Stokes vector S = (I, Q, U, V) is expressed in a reference frame (x, y, d) that is
//!   right-handed around the propagation direction d: x = `frame`, y = d × x.
//! - I is the intensity (any radiometric unit: the matrices are linear), Q = I_x − I_y,
//!   U = I_{+45°} − I_{−45°} with +45° along (x + y)/√2, and V > 0 when the field turns from x
//!   towards y, i.e. counter-clockwise for an observer facing the source (positive helicity;
//!   "right-handed" in the IEEE convention). With Jones components (E_x, E_y) and fields
//!   ∝ exp(i(k·r − ωt)): U = 2 Re(E_x E_y*), V = −2 Im(E_x E_y*).
//! - Rotating the frame by θ about d (counter-clockwise seen facing the source, i.e. the right
//!   hand rule about d) multiplies S by the rotator L(θ) with Q′ = Q cos 2θ + U sin 2θ,
//!   U′ = −Q sin 2θ + U cos 2θ (Chandrasekhar's L(φ); Mitsuba `rotator(theta)`).
//! - Interfaces act in the (s, p) basis: frame x = s = d × n / |d × n| for the incident,
//!   reflected and transmitted beams alike (the three share it), so Q = I_s − I_p. See
//!   `fresnel` for the amplitude signs; a mirror at normal incidence is R·diag(1, 1, −1, −1).

use nalgebra::Vector3;

use super::fresnel::FresnelDielectric;
use super::lambert::orthonormal_basis;

/// A 4×4 Mueller matrix acting on Stokes vectors (row-major: `m[row][col]`).
pub type Mueller = [[f64; 4]; 4];

/// A Stokes vector with its reference frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stokes {
    /// (I, Q, U, V); I ≥ √(Q² + U² + V²) for a physical beam.
    pub s: [f64; 4],
    /// Unit reference x axis, ⊥ to the propagation direction; Q > 0 is linear polarisation
    /// along it.
    pub frame: Vector3<f64>,
}

impl Stokes {
    /// Unit-intensity unpolarised light travelling along the unit vector `dir`, with an
    /// arbitrary reference frame.
    pub fn unpolarized(dir: &Vector3<f64>) -> Self {
        Stokes {
            s: [1.0, 0.0, 0.0, 0.0],
            frame: orthonormal_basis(dir).0,
        }
    }

    /// Unit-intensity light travelling along `dir`, linearly polarised along `axis` (projected
    /// onto the plane ⊥ `dir`; it must not be parallel to `dir`). The frame is that axis.
    pub fn linear(dir: &Vector3<f64>, axis: &Vector3<f64>) -> Self {
        Stokes {
            s: [1.0, 1.0, 0.0, 0.0],
            frame: perpendicular_unit(dir, axis),
        }
    }

    /// Intensity I = S₀.
    pub fn intensity(&self) -> f64 {
        self.s[0]
    }

    /// Degree of polarisation √(Q² + U² + V²)/I in [0, 1] (0 for a dark beam).
    pub fn degree_of_polarization(&self) -> f64 {
        let [i, q, u, v] = self.s;
        if i > 0.0 {
            (q * q + u * u + v * v).sqrt() / i
        } else {
            0.0
        }
    }

    /// Re-expresses the vector in the reference frame `new_frame` (projected onto the plane ⊥
    /// `dir`, the unit propagation direction). The physical beam is unchanged: only Q and U
    /// mix, by the rotator of the signed angle from the old frame to the new one about `dir`.
    pub fn rotate_frame(&mut self, dir: &Vector3<f64>, new_frame: &Vector3<f64>) {
        self.rotate_to_unit_frame(dir, &perpendicular_unit(dir, new_frame));
    }

    /// [`Stokes::rotate_frame`] into the (s, p) basis of a surface with unit normal `n`
    /// (either orientation) met along `dir`: the frame becomes [`s_axis`]`(dir, n)`, which is
    /// unit and ⊥ `dir` to rounding, so it is not projected again (issue 11: the projection's
    /// two square roots were a third of the frame rotations' time).
    pub fn rotate_to_s_axis(&mut self, dir: &Vector3<f64>, n: &Vector3<f64>) {
        self.rotate_to_unit_frame(dir, &s_axis(dir, n));
    }

    /// The rotation to `new_frame`, a unit vector ⊥ `dir`.
    fn rotate_to_unit_frame(&mut self, dir: &Vector3<f64>, new_frame: &Vector3<f64>) {
        debug_assert!(
            self.frame.dot(dir).abs() < 1e-6,
            "the current frame must be ⊥ to the direction of propagation"
        );
        debug_assert!(
            (new_frame.norm() - 1.0).abs() < 1e-9 && new_frame.dot(dir).abs() < 1e-9,
            "the new frame must be a unit vector ⊥ to the direction of propagation"
        );
        // The rotator of `rotator(θ)` needs only cos 2θ and sin 2θ, and cos θ, sin θ are the
        // two dot products: the double-angle identities replace atan2 and sin_cos (13 % of a
        // glass profile's time, issue 11), equal to the matrix form to rounding (tested).
        let (c, s) = (
            self.frame.dot(new_frame),
            dir.dot(&self.frame.cross(new_frame)),
        );
        let r2 = c * c + s * s;
        let (c2, s2) = ((c * c - s * s) / r2, 2.0 * c * s / r2);
        let [i, q, u, v] = self.s;
        self.s = [i, c2 * q + s2 * u, -s2 * q + c2 * u, v];
        self.frame = *new_frame;
    }

    /// Applies the Mueller matrix `m`, whose input and output frames are both `self.frame`.
    pub fn transform(&mut self, m: &Mueller) {
        self.s = apply(m, &self.s);
    }

    /// Removes all polarisation, keeping the intensity: what an ideal diffuse (Lambertian)
    /// scatterer does to the beam it re-emits (see [`depolarizer`]).
    pub fn depolarize(&mut self) {
        self.s = [self.s[0], 0.0, 0.0, 0.0];
    }
}

/// Unit vector along the part of `axis` ⊥ to the unit vector `dir`.
fn perpendicular_unit(dir: &Vector3<f64>, axis: &Vector3<f64>) -> Vector3<f64> {
    let p = axis - axis.dot(dir) * dir;
    let len = p.norm();
    // Squared, so that the check takes no second square root.
    assert!(
        len * len > 1e-18 * axis.norm_squared(),
        "a reference axis must not be parallel to the direction"
    );
    p / len
}

/// The s axis of the plane of incidence for a beam travelling along the unit vector `dir` onto
/// a surface with unit normal `n` (either orientation): the unit vector d × n, ⊥ `dir` to
/// rounding. The incident, reflected and transmitted beams share it. Within 10⁻⁶ rad of normal
/// incidence, where d × n loses its relative precision, it is projected onto the plane ⊥ `dir`
/// again; at normal incidence, where the plane of incidence is undefined, any unit axis ⊥ `dir`
/// is returned (the interface then acts the same in every frame).
pub fn s_axis(dir: &Vector3<f64>, n: &Vector3<f64>) -> Vector3<f64> {
    debug_assert!((n.norm() - 1.0).abs() < 1e-9, "n must be a unit normal");
    let s = dir.cross(n);
    let len = s.norm();
    if len > 1e-6 {
        return s / len;
    }
    let axis = if len > 1e-12 {
        s / len
    } else {
        orthonormal_basis(dir).0
    };
    perpendicular_unit(dir, &axis)
}

/// Mueller matrix that re-expresses a Stokes vector in a frame rotated by `theta` (rad) about
/// the propagation direction (right-hand rule); see the module docs.
pub fn rotator(theta: f64) -> Mueller {
    let (s, c) = (2.0 * theta).sin_cos();
    [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, c, s, 0.0],
        [0.0, -s, c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// Mueller matrix of reflection at a smooth interface, in the (s, p) frames of the incident and
/// reflected beams (Q = I_s − I_p). With c + i·d = r_s r_p* = √(R_s R_p)·e^{iδ}, δ = δ_s − δ_p
/// (Mitsuba `mueller::specular_reflection`; Collett, *Field Guide to Polarization*, 2005,
/// "Mueller matrices for reflection and transmission"):
///
/// ```text
/// ½(R_s+R_p)  ½(R_s−R_p)   0   0
/// ½(R_s−R_p)  ½(R_s+R_p)   0   0
///     0           0        c   d
///     0           0       −d   c
/// ```
///
/// It maps incident power to reflected power (R is the same for radiance and flux).
pub fn mueller_reflection(f: &FresnelDielectric) -> Mueller {
    let a = 0.5 * (f.r_s + f.r_p);
    let b = 0.5 * (f.r_s - f.r_p);
    let amp = (f.r_s * f.r_p).sqrt();
    let (c, d) = (amp * f.cos_retardance_r, amp * f.sin_retardance_r);
    [
        [a, b, 0.0, 0.0],
        [b, a, 0.0, 0.0],
        [0.0, 0.0, c, d],
        [0.0, 0.0, -d, c],
    ]
}

/// Mueller matrix of transmission through a smooth interface, in the (s, p) frames of the
/// incident and transmitted beams. t_s and t_p are real and positive, so there is no
/// retardance: diagonal blocks ½(T_s ± T_p) and √(T_s T_p) (same sources as
/// [`mueller_reflection`]). Zero under total internal reflection.
///
/// It maps incident power (flux) to transmitted power. Radiance additionally changes by
/// (n_t/n_i)² through the compression of solid angle; the BSDFs carry that factor, not this.
pub fn mueller_transmission(f: &FresnelDielectric) -> Mueller {
    let a = 0.5 * (f.t_s + f.t_p);
    let b = 0.5 * (f.t_s - f.t_p);
    let c = (f.t_s * f.t_p).sqrt();
    [
        [a, b, 0.0, 0.0],
        [b, a, 0.0, 0.0],
        [0.0, 0.0, c, 0.0],
        [0.0, 0.0, 0.0, c],
    ]
}

/// Ideal depolariser with intensity factor `albedo`: diag(ρ, 0, 0, 0), for diffuse
/// (Lambertian) scattering. Multiple sub-surface scattering randomises the polarisation; this
/// ignores the weak partial polarisation that the light's exit through a smooth surface adds
/// (modelled by Wolff, "Diffuse-reflectance model for smooth dielectric surfaces", JOSA A
/// 11(11), 1994).
pub fn depolarizer(albedo: f64) -> Mueller {
    let mut m = [[0.0; 4]; 4];
    m[0][0] = albedo;
    m
}

/// The product M·S.
pub fn apply(m: &Mueller, s: &[f64; 4]) -> [f64; 4] {
    std::array::from_fn(|r| (0..4).map(|c| m[r][c] * s[c]).sum())
}

/// The product A·B (apply B first).
pub fn compose(a: &Mueller, b: &Mueller) -> Mueller {
    std::array::from_fn(|r| std::array::from_fn(|c| (0..4).map(|k| a[r][k] * b[k][c]).sum()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotate_frame_equals_the_rotator_of_the_frame_angle() {
        // The double-angle form against atan2 + `rotator`, at angles in every quadrant.
        let dir = Vector3::new(0.3, -0.2, 0.9).normalize();
        let e1 = perpendicular_unit(&dir, &Vector3::x());
        let e2 = dir.cross(&e1);
        for k in 0..24 {
            let theta = -3.1 + k as f64 * 0.27;
            let target = e1 * theta.cos() + e2 * theta.sin();
            let mut a = Stokes {
                s: [1.0, 0.3, -0.5, 0.2],
                frame: e1,
            };
            a.rotate_frame(&dir, &(target * 2.5 + dir * 0.7));
            let expected = apply(&rotator(theta), &[1.0, 0.3, -0.5, 0.2]);
            for (x, y) in a.s.iter().zip(expected) {
                assert!(
                    (x - y).abs() < 1e-14,
                    "θ = {theta}: {:?} vs {expected:?}",
                    a.s
                );
            }
            assert!((a.frame - target).norm() < 1e-14);
        }
    }
    use crate::optics::fresnel::fresnel_dielectric;

    #[test]
    fn rotating_to_the_s_axis_is_rotating_the_frame_to_it() {
        // The unprojected rotation to s = d × n / |d × n| against the general one, which
        // projects its axis first, over normals on both sides; near normal incidence (where s
        // is ill-conditioned and either frame serves) it still leaves a unit frame ⊥ d and
        // the degree of linear polarisation unchanged.
        let dir = Vector3::new(0.3, -0.2, 0.9).normalize();
        let start = Stokes {
            s: [1.0, 0.3, -0.5, 0.2],
            frame: perpendicular_unit(&dir, &Vector3::x()),
        };
        for k in 0..24 {
            let a = k as f64 * 0.27;
            let n = Vector3::new(a.cos(), a.sin(), (a * 1.7).cos() * 2.0).normalize();
            for n in [n, -n] {
                let (mut x, mut y) = (start, start);
                x.rotate_to_s_axis(&dir, &n);
                y.rotate_frame(&dir, &s_axis(&dir, &n));
                assert!((x.frame - y.frame).norm() < 1e-15, "{x:?} vs {y:?}");
                for (p, q) in x.s.iter().zip(y.s) {
                    assert!((p - q).abs() < 1e-14, "{x:?} vs {y:?}");
                }
            }
            let mut x = start;
            x.rotate_to_s_axis(&dir, &(dir + n * 1e-7).normalize());
            assert!((x.frame.norm() - 1.0).abs() < 1e-15 && x.frame.dot(&dir).abs() < 1e-15);
            let linear = |s: &Stokes| s.s[1].hypot(s.s[2]);
            assert!((linear(&x) - linear(&start)).abs() < 1e-15);
        }
    }

    #[test]
    fn rotating_the_frame_by_45_degrees_turns_q_into_u() {
        let d = Vector3::z();
        let mut s = Stokes::linear(&d, &Vector3::x());
        // New x′ = (x + y)/√2: the field along x is at −45° from x′, so U′ = −1.
        s.rotate_frame(&d, &Vector3::new(1.0, 1.0, 0.0));
        assert!(
            s.s[1].abs() < 1e-15 && (s.s[2] + 1.0).abs() < 1e-15,
            "{:?}",
            s.s
        );
        // A 90° rotation swaps the axes: Q changes sign.
        let mut s = Stokes::linear(&d, &Vector3::x());
        s.rotate_frame(&d, &Vector3::y());
        assert!((s.s[1] + 1.0).abs() < 1e-15);
        // Rotations about one axis compose additively.
        let (a, b) = (compose(&rotator(0.3), &rotator(-1.1)), rotator(-0.8));
        for r in 0..4 {
            for c in 0..4 {
                assert!((a[r][c] - b[r][c]).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn reflection_at_normal_incidence_mirrors_u_and_v() {
        let m = mueller_reflection(&fresnel_dielectric(1.0, 1.5));
        let out = apply(&m, &[1.0, 0.2, 0.3, 0.4]);
        let expect = [0.04, 0.04 * 0.2, -0.04 * 0.3, -0.04 * 0.4];
        for k in 0..4 {
            assert!((out[k] - expect[k]).abs() < 1e-15, "{out:?}");
        }
    }

    #[test]
    fn total_internal_reflection_is_a_pure_retarder() {
        let f = fresnel_dielectric(0.5, 1.0 / 1.5);
        assert!(f.tir);
        let m = mueller_reflection(&f);
        let out = apply(&m, &[1.0, 0.0, 1.0, 0.0]);
        assert!((out[0] - 1.0).abs() < 1e-15);
        assert!((out[2].powi(2) + out[3].powi(2) - 1.0).abs() < 1e-14 && out[3].abs() > 0.1);
        assert_eq!(mueller_transmission(&f), [[0.0; 4]; 4]);
    }
}
