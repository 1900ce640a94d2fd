//! The receiving camera: a thin lens with a circular aperture and a Scheimpflug-tilted image
//! plane, and the exact triangulation map between pixels and the laser plane.
//!
//! Geometry in the sensor frame S: the lens centre sits at `lens_center_m` = (0, baseline, lens_z)
//! and its optical axis points at (0, 0, aim_distance). A thin lens maps planes to planes, so the
//! image of the laser plane y = 0 is a plane: the Scheimpflug plane (Scheimpflug's rule: object
//! plane, lens plane and image plane meet in one line). The pixel grid lies on that plane with
//! columns along the image of the x axis and rows across it, so every point of the laser plane
//! is in focus, and a sub-pixel position maps back to exactly one (x, z).

use nalgebra::Vector3;

/// Parameters of the camera.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CameraSpec {
    /// Offset of the lens centre from the laser plane along +y (m), > 0: the triangulation base.
    pub baseline_m: f64,
    /// z of the lens centre in S (m).
    pub lens_z_m: f64,
    /// Distance along z of the point of the laser axis that the optical axis aims at (m).
    pub aim_distance_m: f64,
    /// Focal length (m), > 0.
    pub focal_length_m: f64,
    /// f-number N = f / D, > 0 (sets the aperture diameter D).
    pub f_number: f64,
    /// Pixel pitch (m), square pixels.
    pub pixel_pitch_m: f64,
    /// Number of pixel columns (along the laser line).
    pub columns: usize,
    /// Number of pixel rows (across the line: the range direction).
    pub rows: usize,
}

impl CameraSpec {
    /// Lens centre in S (m).
    pub fn lens_center(&self) -> Vector3<f64> {
        Vector3::new(0.0, self.baseline_m, self.lens_z_m)
    }

    /// Aperture diameter D = f / N (m).
    pub fn aperture_diameter_m(&self) -> f64 {
        self.focal_length_m / self.f_number
    }
}

/// Why a camera specification cannot be built.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CameraError {
    /// The lens is too close to the measuring range to form a real image of it.
    #[error("the laser plane at z = {z_m} m is within one focal length of the lens")]
    NoRealImage {
        /// The offending range (m).
        z_m: f64,
    },
    /// Part of the measuring range falls outside the pixel grid.
    #[error(
        "the measuring range does not fit on the sensor: (x, z) = ({x_mm:.1}, {z_mm:.1}) mm \
         images to pixel ({col:.1}, {row:.1}) outside {columns} × {rows}"
    )]
    RangeOffSensor {
        /// x of the corner (mm).
        x_mm: f64,
        /// z of the corner (mm).
        z_mm: f64,
        /// Its column.
        col: f64,
        /// Its row.
        row: f64,
        /// Sensor columns.
        columns: usize,
        /// Sensor rows.
        rows: usize,
    },
}

/// A ready-to-use camera: lens, Scheimpflug image plane and pixel grid, in the sensor frame S.
///
/// Continuous pixel coordinates: pixel (c, r) covers [c, c+1) × [r, r+1); columns grow with x,
/// rows grow with z, so row 0 is the near end of the range.
#[derive(Clone, Debug)]
pub struct Camera {
    spec: CameraSpec,
    center: Vector3<f64>,
    axis: Vector3<f64>,
    lens_u: Vector3<f64>,
    lens_v: Vector3<f64>,
    aperture_radius: f64,
    /// A point of the image plane: the image of the grid centre.
    plane_origin: Vector3<f64>,
    plane_normal: Vector3<f64>,
    /// Unit vector of increasing column on the image plane.
    e_col: Vector3<f64>,
    /// Unit vector of increasing row on the image plane.
    e_row: Vector3<f64>,
    /// Plane coordinate (m) of column 0's left edge and row 0's top edge.
    col0: f64,
    row0: f64,
}

impl Camera {
    /// Builds the camera and checks that the measuring range images onto the pixel grid.
    pub fn new(spec: &CameraSpec, range: &super::MeasuringRange) -> Result<Camera, CameraError> {
        let center = spec.lens_center();
        let aim = Vector3::new(0.0, 0.0, spec.aim_distance_m);
        let axis = (aim - center).normalize();
        let lens_u = Vector3::x();
        let lens_v = axis.cross(&lens_u).normalize();
        let mut cam = Camera {
            spec: *spec,
            center,
            axis,
            lens_u,
            lens_v,
            aperture_radius: 0.5 * spec.aperture_diameter_m(),
            plane_origin: Vector3::zeros(),
            plane_normal: Vector3::zeros(),
            e_col: Vector3::zeros(),
            e_row: Vector3::zeros(),
            col0: 0.0,
            row0: 0.0,
        };
        let f = spec.focal_length_m;
        for z in [range.z_min_m, range.z_max_m] {
            let p = Vector3::new(0.0, 0.0, z);
            if (p - center).dot(&axis) <= f * 1.0001 {
                return Err(CameraError::NoRealImage { z_m: z });
            }
        }
        // The Scheimpflug plane through the images of three laser-plane points.
        let near = cam.conjugate(&Vector3::new(0.0, 0.0, range.z_min_m));
        let far = cam.conjugate(&Vector3::new(0.0, 0.0, range.z_max_m));
        let side = cam.conjugate(&Vector3::new(0.05, 0.0, range.z_mid_m()));
        let normal = (far - near).cross(&(side - near)).normalize();
        // Lines x = var, z = const image to lines along −x (the lens inverts): columns grow with x.
        let e_col = -Vector3::x();
        let mut e_row = normal.cross(&e_col).normalize();
        if (far - near).dot(&e_row) < 0.0 {
            e_row = -e_row;
        }
        cam.plane_normal = normal;
        cam.e_col = e_col;
        cam.e_row = e_row;
        cam.plane_origin = 0.5 * (near + far);
        let pitch = spec.pixel_pitch_m;
        cam.col0 = -0.5 * spec.columns as f64 * pitch;
        cam.row0 = -0.5 * spec.rows as f64 * pitch;
        // The field is a trapezoid, widest at the far end: check its four corners.
        let half = 0.5 * range.x_width_m;
        for (x, z) in [
            (-half, range.z_max_m),
            (half, range.z_max_m),
            (0.0, range.z_min_m),
        ] {
            let [col, row] = cam
                .laser_plane_to_pixel(x, z)
                .ok_or(CameraError::NoRealImage { z_m: z })?;
            if !(0.0..=spec.columns as f64).contains(&col)
                || !(0.0..=spec.rows as f64).contains(&row)
            {
                return Err(CameraError::RangeOffSensor {
                    x_mm: x * 1e3,
                    z_mm: z * 1e3,
                    col,
                    row,
                    columns: spec.columns,
                    rows: spec.rows,
                });
            }
        }
        Ok(cam)
    }

    /// The specification it was built from.
    pub fn spec(&self) -> &CameraSpec {
        &self.spec
    }

    /// Lens centre in S (m).
    pub fn center(&self) -> Vector3<f64> {
        self.center
    }

    /// Optical axis in S (unit, pointing into the scene).
    pub fn axis(&self) -> Vector3<f64> {
        self.axis
    }

    /// Aperture area π·(D/2)² (m²).
    pub fn aperture_area(&self) -> f64 {
        std::f64::consts::PI * self.aperture_radius * self.aperture_radius
    }

    /// Area of one pixel (m²).
    pub fn pixel_area(&self) -> f64 {
        self.spec.pixel_pitch_m * self.spec.pixel_pitch_m
    }

    /// A point of the aperture disk from a point `disk` of the unit disk (see
    /// `optics::warp::concentric_disk`).
    pub fn aperture_point(&self, disk: [f64; 2]) -> Vector3<f64> {
        self.center + self.aperture_radius * (disk[0] * self.lens_u + disk[1] * self.lens_v)
    }

    /// The thin-lens conjugate of `p` (Gaussian lens law 1/s_o + 1/s_i = 1/f, inverted through
    /// the lens centre). Works both ways: object → image and image → object.
    fn conjugate(&self, p: &Vector3<f64>) -> Vector3<f64> {
        let d = self.center - p;
        let s = d.dot(&self.axis).abs();
        let f = self.spec.focal_length_m;
        let s_conj = f * s / (s - f);
        self.center + d * (s_conj / s)
    }

    fn plane_to_pixel(&self, q: &Vector3<f64>) -> [f64; 2] {
        let d = q - self.plane_origin;
        let pitch = self.spec.pixel_pitch_m;
        [
            (d.dot(&self.e_col) - self.col0) / pitch,
            (d.dot(&self.e_row) - self.row0) / pitch,
        ]
    }

    /// Where the ray from object point `p` (S, m) through aperture point `lens` meets the image
    /// plane, as continuous pixel coordinates [col, row]. `None` if `p` is within a focal length
    /// of the lens or behind it (no real image) or the ray runs parallel to the image plane.
    /// Points off the laser plane land off their in-focus position: that is the defocus blur.
    pub fn image_point(&self, p: &Vector3<f64>, lens: &Vector3<f64>) -> Option<[f64; 2]> {
        let s = (p - self.center).dot(&self.axis);
        if s <= self.spec.focal_length_m * 1.0001 {
            return None;
        }
        let image = self.conjugate(p);
        let dir = image - lens;
        let denom = dir.dot(&self.plane_normal);
        if denom.abs() < 1e-300 {
            return None;
        }
        let t = (self.plane_origin - lens).dot(&self.plane_normal) / denom;
        if t <= 0.0 {
            return None;
        }
        Some(self.plane_to_pixel(&(lens + dir * t)))
    }

    /// Image-side working f-number N_w = s_i / D for the laser-plane point (x, z) (m): the
    /// image distance along the axis over the aperture diameter. It sets the size of the
    /// diffraction spot and of speckle grains on the sensor (λ·N_w).
    pub fn working_f_number(&self, x: f64, z: f64) -> f64 {
        let image = self.conjugate(&Vector3::new(x, 0.0, z));
        (self.center - image).dot(&self.axis).abs() / self.spec.aperture_diameter_m()
    }

    /// The exact triangulation map: continuous pixel coordinates → (x, z) in the laser plane (m).
    pub fn pixel_to_laser_plane(&self, col: f64, row: f64) -> Option<(f64, f64)> {
        let pitch = self.spec.pixel_pitch_m;
        let q = self.plane_origin
            + self.e_col * (self.col0 + col * pitch)
            + self.e_row * (self.row0 + row * pitch);
        let s = (self.center - q).dot(&self.axis);
        if s <= self.spec.focal_length_m * 1.0001 {
            return None;
        }
        let p = self.conjugate(&q);
        debug_assert!(
            p.y.abs() < 1e-9,
            "back-projection left the laser plane: y = {}",
            p.y
        );
        Some((p.x, p.z))
    }

    /// The inverse map: (x, z) in the laser plane (m) → continuous pixel coordinates [col, row].
    pub fn laser_plane_to_pixel(&self, x: f64, z: f64) -> Option<[f64; 2]> {
        let p = Vector3::new(x, 0.0, z);
        if (p - self.center).dot(&self.axis) <= self.spec.focal_length_m * 1.0001 {
            return None;
        }
        Some(self.plane_to_pixel(&self.conjugate(&p)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::preset::scancontrol_2600_100;

    fn camera() -> Camera {
        let s = scancontrol_2600_100();
        Camera::new(&s.camera, &s.range).unwrap()
    }

    #[test]
    fn triangulation_round_trip_is_exact() {
        let cam = camera();
        for &(x, z) in &[(0.0, 0.2575), (0.07, 0.39), (-0.02, 0.13), (0.03, 0.2)] {
            let [c, r] = cam.laser_plane_to_pixel(x, z).unwrap();
            let (x2, z2) = cam.pixel_to_laser_plane(c, r).unwrap();
            assert!(
                (x - x2).abs() < 1e-12 && (z - z2).abs() < 1e-12,
                "({x},{z}) → ({x2},{z2})"
            );
        }
    }

    #[test]
    fn whole_aperture_focuses_laser_plane_points_to_one_pixel_point() {
        // Scheimpflug: every ray from a laser-plane point meets the image plane at one point.
        let cam = camera();
        let p = Vector3::new(0.04, 0.0, 0.31);
        let centre = cam.image_point(&p, &cam.center()).unwrap();
        for disk in [[1.0, 0.0], [0.0, 1.0], [-0.7, 0.7], [0.3, -0.9]] {
            let q = cam.image_point(&p, &cam.aperture_point(disk)).unwrap();
            assert!((q[0] - centre[0]).abs() < 1e-9 && (q[1] - centre[1]).abs() < 1e-9);
        }
        let ideal = cam.laser_plane_to_pixel(0.04, 0.31).unwrap();
        assert!((ideal[0] - centre[0]).abs() < 1e-9 && (ideal[1] - centre[1]).abs() < 1e-9);
    }

    #[test]
    fn off_plane_points_blur_and_rows_grow_with_range() {
        let cam = camera();
        let p = Vector3::new(0.0, 0.002, 0.25);
        let a = cam
            .image_point(&p, &cam.aperture_point([0.0, 1.0]))
            .unwrap();
        let b = cam
            .image_point(&p, &cam.aperture_point([0.0, -1.0]))
            .unwrap();
        assert!(
            (a[1] - b[1]).abs() > 0.1,
            "no defocus for a point 2 mm off the plane"
        );
        let near = cam.laser_plane_to_pixel(0.0, 0.13).unwrap();
        let far = cam.laser_plane_to_pixel(0.0, 0.38).unwrap();
        assert!(far[1] > near[1]);
        let left = cam.laser_plane_to_pixel(-0.01, 0.2).unwrap();
        let right = cam.laser_plane_to_pixel(0.01, 0.2).unwrap();
        assert!(right[0] > left[0]);
    }

    #[test]
    fn a_range_off_the_sensor_is_refused() {
        let s = scancontrol_2600_100();
        let mut spec = s.camera;
        spec.rows = 200;
        assert!(matches!(
            Camera::new(&spec, &s.range),
            Err(CameraError::RangeOffSensor { .. })
        ));
    }
}
