//! The camera's aperture in the base frame for one pose: where rays enter it and where the
//! thin lens sends them on the image plane.

use nalgebra::{Point3, Vector3};

use crate::geometry::planar::{cross, point_segment_dist2};
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
    /// The pixel grid's image in the laser plane y = 0 of S: the (x, z) corners (m) of the
    /// quadrilateral whose points the thin lens images onto the grid, counter-clockwise or
    /// clockwise (a projective image of the grid's rectangle, so convex).
    grid_in_laser_plane: [[f64; 2]; 4],
}

impl<'a> Aperture<'a> {
    /// The aperture of `camera` mounted at `sensor_pose`.
    pub fn new(camera: &'a Camera, sensor_pose: &Pose) -> Self {
        let center = sensor_pose * Point3::from(camera.center());
        let a = camera.aperture_point([1.0, 0.0]) - camera.center();
        let b = camera.aperture_point([0.0, 1.0]) - camera.center();
        let radius = a.norm();
        let spec = camera.spec();
        let (w, h) = (spec.columns as f64, spec.rows as f64);
        let grid_in_laser_plane = [[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]].map(|[c, r]| {
            let (x, z) = camera
                .pixel_to_laser_plane(c, r)
                .expect("the camera images its whole pixel grid from the laser plane");
            [x, z]
        });
        Aperture {
            camera,
            sensor_pose: *sensor_pose,
            inverse_pose: sensor_pose.inverse(),
            center,
            axis: sensor_pose.rotation * camera.axis(),
            u: sensor_pose.rotation * (a / radius),
            v: sensor_pose.rotation * (b / radius),
            radius,
            grid_in_laser_plane,
        }
    }

    /// Whether light that arrives at aperture point `lens` (base frame) along a direction
    /// within `cone_rad` of the straight line from `x` can land on the pixel grid.
    ///
    /// A thin lens images every point of the laser plane onto the Scheimpflug image plane, so
    /// the pixel a ray arriving at `lens` lands on is the image of the point Q where its line
    /// meets the laser plane (`image_of_ray` uses any point of the line). The lines within the
    /// cone meet the plane within R of the straight line's crossing Q₀, where, with h the height
    /// of `lens` above the plane and a the straight line's angle to it, R ≤ h·(1 + γ)/sin(a − γ)
    /// − h/sin a (the chord over an arc of γ at a distance ≤ h/sin(a − γ), plus the change of
    /// that distance). The light can land only if the grid's quadrilateral comes within R of Q₀
    /// (plus 1 mm). Conservative: `true` whenever the cone reaches parallel to the plane or the
    /// crossing lies behind the lens.
    pub fn can_land(&self, x: &Point3<f64>, lens: &Point3<f64>, cone_rad: f64) -> bool {
        let lens_s = self.inverse_pose * lens;
        let d = self.inverse_pose.rotation * (lens - x);
        let dist = d.norm();
        let d = d / dist;
        let h = lens_s.y.abs();
        let sin_a = d.y.abs();
        let a = sin_a.asin();
        // The crossing must lie on the scene side of the lens, back along the arriving ray.
        let back = lens_s.y / d.y;
        if back.is_nan() || back <= 0.0 || a <= cone_rad + 1e-6 {
            return true;
        }
        let q = lens_s - d * back;
        let reach = h * (1.0 + cone_rad) / (a - cone_rad).sin() - h / sin_a;
        distance_to_quad([q.x, q.z], &self.grid_in_laser_plane) <= reach + LANDING_MARGIN_M
    }

    /// Whether `p` lies more than `margin` (m) from the region the camera looks at: off the
    /// laser plane by more than `margin`, or farther than `margin` within it from the pixel
    /// grid's footprint. Light there can still reach the camera (a mirror image in a pane, a
    /// return after a long path), so this only says where Russian roulette may thin photons out
    /// without touching what the camera sees directly.
    pub fn far_from_view(&self, p: &Point3<f64>, margin: f64) -> bool {
        let q = self.inverse_pose * p;
        q.y.abs() > margin || distance_to_quad([q.x, q.z], &self.grid_in_laser_plane) > margin
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

/// Slack (m, in the laser plane) of [`Aperture::can_land`]: about 5 pixels at mid range.
const LANDING_MARGIN_M: f64 = 1e-3;

/// Distance (m) from `p` to the convex quadrilateral `quad` (0 inside).
fn distance_to_quad(p: [f64; 2], quad: &[[f64; 2]; 4]) -> f64 {
    // An array, not a Vec: this runs at every vertex of every photon (`far_from_view`).
    let sides: [f64; 4] = std::array::from_fn(|i| cross(quad[i], quad[(i + 1) % 4], p));
    if sides.iter().all(|&s| s >= 0.0) || sides.iter().all(|&s| s <= 0.0) {
        return 0.0;
    }
    (0..4)
        .map(|i| point_segment_dist2(p, quad[i], quad[(i + 1) % 4]))
        .fold(f64::INFINITY, f64::min)
        // One square root of the least squared distance: `hypot` per side was a third of the
        // far-from-view test, which runs at every vertex (issue 11).
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::preset::scancontrol_2600_100;
    use crate::sensor::SensorHead;

    #[test]
    fn rays_that_land_on_the_grid_are_never_ruled_out() {
        // For many lens points and directions: whenever `image_of_ray` lands on the grid, the
        // straight line (cone 0) from a point back along the ray must be allowed to land.
        let head = SensorHead::new(&scancontrol_2600_100()).unwrap();
        let pose = Pose::identity();
        let ap = Aperture::new(&head.camera, &pose);
        let spec = head.camera.spec();
        let (mut landed, mut ruled_out) = (0, 0);
        for i in 0..20_000u64 {
            let f = |k: u64| ((i * 7919 + k * 104_729) as f64 * 0.618_033_988_749_895).fract();
            let lens = ap.point([f(1) * 1.4 - 0.7, f(2) * 1.4 - 0.7]);
            let target = Point3::new(0.2 * f(3) - 0.1, 0.03 * f(4) - 0.015, 0.1 + 0.35 * f(5));
            let d = (lens - target).normalize();
            let lands = matches!(ap.image_of_ray(&lens, &d), Some([c, r])
                if c >= 0.0 && r >= 0.0 && c < spec.columns as f64 && r < spec.rows as f64);
            let allowed = ap.can_land(&target, &lens, 0.0);
            landed += lands as usize;
            ruled_out += !allowed as usize;
            assert!(allowed || !lands, "ray {i} lands but was ruled out");
        }
        assert!(
            landed > 1000 && ruled_out > 1000,
            "{landed} landed, {ruled_out} ruled out"
        );
    }

    #[test]
    fn the_roulette_region_starts_beyond_the_margin_around_the_grid_footprint() {
        // Points of the laser plane that image onto the grid are never far from the view;
        // 60 mm off the plane, or 60 mm beyond the footprint within it, always are.
        let head = SensorHead::new(&scancontrol_2600_100()).unwrap();
        let ap = Aperture::new(&head.camera, &Pose::identity());
        let quad = ap.grid_in_laser_plane;
        for i in 0..400u64 {
            let f = |k: u64| ((i * 7919 + k * 104_729) as f64 * 0.618_033_988_749_895).fract();
            // A point inside the footprint: a convex combination of its corners.
            let (a, b) = (f(1), f(2));
            let lerp = |p: [f64; 2], q: [f64; 2], t: f64| {
                [p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t]
            };
            let inside = lerp(lerp(quad[0], quad[1], a), lerp(quad[3], quad[2], a), b);
            let on_plane = Point3::new(inside[0], 0.0, inside[1]);
            assert!(!ap.far_from_view(&on_plane, 0.05), "{on_plane}");
            let off = Point3::new(inside[0], 0.06 * (2.0 * f(3) - 1.0).signum(), inside[1]);
            assert!(ap.far_from_view(&off, 0.05), "{off}");
        }
        let beyond = Point3::new(
            quad[1][0] + 0.06 + 0.05,
            0.0,
            0.5 * (quad[1][1] + quad[2][1]),
        );
        assert!(distance_to_quad([beyond.x, beyond.z], &quad) > 0.05);
        assert!(ap.far_from_view(&beyond, 0.05));
    }

    #[test]
    fn directions_inside_the_cone_that_land_are_never_ruled_out() {
        // The cone version: any direction within γ of the straight line that lands on the
        // grid must leave `can_land` true, for cones from 0.1° to 10°.
        let head = SensorHead::new(&scancontrol_2600_100()).unwrap();
        let ap = Aperture::new(&head.camera, &Pose::identity());
        let spec = head.camera.spec();
        let mut tested = 0;
        for i in 0..40_000u64 {
            let f = |k: u64| ((i * 7919 + k * 104_729) as f64 * 0.618_033_988_749_895).fract();
            let lens = ap.point([f(1) * 1.4 - 0.7, f(2) * 1.4 - 0.7]);
            let x = Point3::new(0.6 * f(3) - 0.3, 0.2 * f(4) - 0.1, 0.1 + 0.5 * f(5));
            let cone = (0.1 + 9.9 * f(6)).to_radians();
            let s = (lens - x).normalize();
            let (t1, t2) = crate::optics::lambert::orthonormal_basis(&s);
            let (r, phi) = (cone * f(7).sqrt(), std::f64::consts::TAU * f(8));
            let d = (s + (t1 * phi.cos() + t2 * phi.sin()) * r.tan()).normalize();
            let lands = matches!(ap.image_of_ray(&lens, &d), Some([c, r])
                if c >= 0.0 && r >= 0.0 && c < spec.columns as f64 && r < spec.rows as f64);
            if lands {
                tested += 1;
                assert!(
                    ap.can_land(&x, &lens, cone),
                    "case {i}: lands within {cone} rad"
                );
            }
        }
        assert!(tested > 500, "{tested}");
    }

    #[test]
    fn distance_to_a_square() {
        let q = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(distance_to_quad([0.5, 0.5], &q), 0.0);
        assert!((distance_to_quad([2.0, 0.5], &q) - 1.0).abs() < 1e-15);
        assert!((distance_to_quad([2.0, 2.0], &q) - 2f64.sqrt()).abs() < 1e-15);
    }
}
