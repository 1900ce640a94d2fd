//! A shipped scene's first scan pose, traced once before timing: what the benchmarks of the
//! stages after the light transport (lens, sensor) take as their input.

use std::path::Path;

use glassscan::scan::poses::{plan_border_scan, ScanPose};
use glassscan::scene;
use glassscan::sensor::SensorHead;
use glassscan::transport::{render, Irradiance, TraceScene, TraceSettings};

/// The scene's sensor head, its first pose and that pose's traced irradiance (seed 1).
pub fn traced_pose(name: &str, photons: u64) -> (SensorHead, ScanPose, Irradiance) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    let world = scene::load(&path).expect("shipped scenes load");
    let head = SensorHead::new(&world.sensor).expect("preset camera");
    let trace = TraceScene::new(&world).expect("shipped scenes trace");
    let target = world.target.as_ref().expect("scene has a target");
    let border = target
        .border
        .transformed(&world.objects[target.object].pose);
    let pose = plan_border_scan(&border, &world.scan, &world.mount).remove(0);
    let settings = TraceSettings {
        photons,
        adaptive: false,
        max_depth: 64,
        seed: 1,
    };
    let (irradiance, _) = render(&trace, &head, &pose.sensor, &settings, pose.index as u64);
    (head, pose, irradiance)
}
