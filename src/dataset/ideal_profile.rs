//! The ideal profile: the exact geometric cross-section that the laser line lies on, as an
//! opaque copy of the scene would return it. Fan rays leave the laser's virtual source (the
//! origin of the sensor frame S) in the laser plane y = 0 and the first surface each one hits
//! is recorded: glass is treated as opaque, so this is where the light *first* meets the
//! scene, not what the sensor reports (ARCHITECTURE.md, "Localisation: what is simulated, what is believed").
//!
//! The rays are spaced evenly in tan φ across the full fan (an ideal Powell line spreads light
//! evenly along x), one per profile point of the firmware setting, so the ideal profile has the
//! measured profile's density. Coordinates are (x, z) in S in millimetres, like profiles.

use nalgebra::{Point3, Vector3};

use crate::geometry::mesh::SurfacePart;
use crate::geometry::pose::Pose;
use crate::scene::world::{ObjectLabel, World};
use crate::sensor::SensorHead;
use crate::transport::TraceScene;

/// Longest ray (m): far beyond any scene, so a miss means nothing is in the plane.
const FAR_M: f64 = 100.0;

/// The first hit of one fan ray.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct IdealPoint {
    /// Index of the fan ray (0 at the −x end of the fan).
    pub ray: usize,
    /// Fan angle φ from the z axis towards +x (deg).
    pub fan_angle_deg: f64,
    /// x in the sensor frame (mm).
    pub x_mm: f64,
    /// z in the sensor frame (mm).
    pub z_mm: f64,
    /// Name of the object hit.
    pub object: String,
    /// The object's label (`table`, `background`, `tape`, `cover`, `other`).
    pub label: ObjectLabel,
    /// The part of the object hit (`top_face`, `bottom_face`, `edge`, `solid`).
    pub part: SurfacePart,
    /// Whether the object is glass.
    pub glass: bool,
}

/// Casts `rays` fan rays of `head`'s laser from `sensor` (T_BS) into `scene` (built from
/// `world`) and returns the first hit of every ray that hits something, in ray order.
pub fn ideal_profile(
    world: &World,
    scene: &TraceScene,
    head: &SensorHead,
    sensor: &Pose,
    rays: usize,
) -> Vec<IdealPoint> {
    let half_tan = (0.5 * head.config.laser.fan_angle_rad).tan();
    let origin = sensor * Point3::origin();
    let to_sensor = sensor.inverse();
    (0..rays)
        .filter_map(|k| {
            let phi = ((2.0 * (k as f64 + 0.5) / rays as f64 - 1.0) * half_tan).atan();
            let dir = sensor * Vector3::new(phi.sin(), 0.0, phi.cos());
            let hit = scene.accel.closest_hit(&origin, &dir, 0.0, FAR_M)?;
            let p = to_sensor * hit.point;
            let object = &world.objects[hit.object as usize];
            Some(IdealPoint {
                ray: k,
                fan_angle_deg: phi.to_degrees(),
                x_mm: p.x * 1e3,
                z_mm: p.z * 1e3,
                object: object.name.clone(),
                label: object.label,
                part: hit.part,
                glass: scene.glass(hit.material).is_some(),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::cuboid::cuboid;
    use crate::geometry::pose::pose_from_mm_deg;
    use crate::scan::ScanConfig;
    use crate::scene::world::{Material, NamedMaterial, Object};
    use crate::sensor::preset::scancontrol_2600_100;

    /// A 400 mm wide plate whose near face is the plane z = 200 mm, with a 50 mm wide, 20 mm
    /// tall step on it at x ≥ 0, in front of a sensor at the base origin (S = B).
    fn step_world() -> World {
        let plate = |name: &str, size: [f64; 3], t: [f64; 3]| Object {
            name: name.into(),
            mesh: cuboid(size.map(|v| v * 1e-3)),
            pose: pose_from_mm_deg(t, [0.0; 3]),
            material: 0,
            label: ObjectLabel::Other,
        };
        World {
            source: "step".into(),
            objects: vec![
                plate("plate", [400.0, 400.0, 10.0], [0.0, 0.0, 205.0]),
                plate("step", [50.0, 400.0, 20.0], [25.0, 0.0, 190.0]),
            ],
            materials: vec![NamedMaterial {
                name: "white".into(),
                material: Material::Lambertian { albedo: 0.8 },
            }],
            target: None,
            sensor: scancontrol_2600_100(),
            mount: Pose::identity(),
            scan: ScanConfig {
                scan_angle_rad: std::f64::consts::FRAC_PI_2,
                poses: 1,
                standoff_m: 0.2,
                start_fraction: 0.0,
            },
            material_sources: Vec::new(),
            warnings: Vec::new(),
        }
    }

    #[test]
    fn a_step_gives_its_height_and_labels_its_object() {
        let world = step_world();
        let scene = TraceScene::new(&world).unwrap();
        let head = SensorHead::new(&world.sensor).unwrap();
        let points = ideal_profile(&world, &scene, &head, &Pose::identity(), 640);
        assert_eq!(points.len(), 640, "every ray hits the plate or the step");
        for p in &points {
            // tan 12° · 180 mm = 38 mm < 50 mm: every ray on the +x side lands on the step.
            let on_step = p.x_mm > 0.0;
            let (z, name) = if on_step {
                (180.0, "step")
            } else {
                (200.0, "plate")
            };
            assert_eq!(p.object, name, "{p:?}");
            assert!((p.z_mm - z).abs() < 1e-6, "{p:?}");
            // The hit lies on its fan ray.
            assert!((p.x_mm / p.z_mm - p.fan_angle_deg.to_radians().tan()).abs() < 1e-9);
        }
        // The fan is symmetric and covers ±12°.
        assert!((points[0].fan_angle_deg + points[639].fan_angle_deg).abs() < 1e-12);
        assert!(points[0].fan_angle_deg < -11.9 && points[0].fan_angle_deg > -12.0);
    }

    #[test]
    fn rays_that_miss_are_left_out() {
        let world = step_world();
        let scene = TraceScene::new(&world).unwrap();
        let head = SensorHead::new(&world.sensor).unwrap();
        // Looking away from the plates.
        let away = pose_from_mm_deg([0.0; 3], [180.0, 0.0, 0.0]);
        assert!(ideal_profile(&world, &scene, &head, &away, 64).is_empty());
    }
}
