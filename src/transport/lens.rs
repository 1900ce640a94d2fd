//! The camera's aperture in the base frame for one pose: where rays enter it and where the
//! thin lens sends them on the image plane.

use nalgebra::{Point3, Vector3};

use crate::geometry::pose::Pose;
use crate::sensor::camera::Camera;

/// The aperture disk of one pose, in the base frame.
pub struct Aperture<'a> {
    /// The camera (sensor frame).
    pub camera: &'a Camera,
    /// T_BS of the pose.
    pub sensor_pose: Pose,
    inverse_pose: Pose,
    /// Lens centre (base frame).
    pub center: Point3<f64>,
    /// Optical axis (base frame, unit, pointing into the scene).
    pub axis: Vector3<f64>,
    /// First in-plane axis of the aperture (base frame).
    pub u: Vector3<f64>,
    /// Second in-plane axis (base frame).
    pub v: Vector3<f64>,
    radius: f64,
}

impl<'a> Aperture<'a> {
    /// The aperture of `camera` mounted at `sensor_pose`.
    pub fn new(camera: &'a Camera, sensor_pose: &Pose) -> Self {
        let center = sensor_pose * Point3::from(camera.center());
        let a = camera.aperture_point([1.0, 0.0]) - camera.center();
        let b = camera.aperture_point([0.0, 1.0]) - camera.center();
        let radius = a.norm();
        Aperture {
            camera,
            sensor_pose: *sensor_pose,
            inverse_pose: sensor_pose.inverse(),
            center,
            axis: sensor_pose.rotation * camera.axis(),
            u: sensor_pose.rotation * (a / radius),
            v: sensor_pose.rotation * (b / radius),
            radius,
        }
    }

    /// Aperture area (m²).
    pub fn area(&self) -> f64 {
        self.camera.aperture_area()
    }

    /// The aperture point for a point `disk` of the unit disk.
    pub fn point(&self, disk: [f64; 2]) -> Point3<f64> {
        self.center + self.radius * (disk[0] * self.u + disk[1] * self.v)
    }

    /// Coordinates (m) of `p` in the aperture plane, relative to the centre.
    pub fn plane_coords(&self, p: &Point3<f64>) -> [f64; 2] {
        let d = p - self.center;
        [d.dot(&self.u), d.dot(&self.v)]
    }

    /// Distance along `o + t·d` to the aperture plane, for rays travelling towards the lens
    /// from the scene side.
    pub fn plane_distance(&self, o: &Point3<f64>, d: &Vector3<f64>) -> Option<f64> {
        let den = d.dot(&self.axis);
        if den >= 0.0 {
            return None;
        }
        let t = (self.center - o).dot(&self.axis) / den;
        (t > 0.0).then_some(t)
    }

    /// Where `o + t·d` enters the aperture disk, if it does before `t_max`.
    pub fn enters(&self, o: &Point3<f64>, d: &Vector3<f64>, t_max: f64) -> Option<Point3<f64>> {
        let t = self.plane_distance(o, d)?;
        if t > t_max {
            return None;
        }
        let p = o + d * t;
        let [x, y] = self.plane_coords(&p);
        (x * x + y * y <= self.radius * self.radius).then_some(p)
    }

    /// Pixel coordinates [col, row] where the ray arriving at aperture point `lens` with
    /// direction `d` lands: the thin lens sends the whole incoming ray to one outgoing ray, the
    /// one through the conjugates of its points.
    pub fn image_of_ray(&self, lens: &Point3<f64>, d: &Vector3<f64>) -> Option<[f64; 2]> {
        let on_ray = self.inverse_pose * (lens - d * 0.5);
        let lens_s = self.inverse_pose * lens;
        self.camera.image_point(&on_ray.coords, &lens_s.coords)
    }
}
