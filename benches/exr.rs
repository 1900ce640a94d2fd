//! Writing a pose's irradiance EXR (criterion): `io::exr::write_irradiance_exr` of the first
//! pose of `scenes/edge_study_bare.toml` (640 × 832 pixels, the total and 11 path-class layers,
//! 25.6 MB of f32), traced once at 1000 and at 2^20 photons. Written into a temporary directory
//! on /dev/shm where there is one, so that the disk's fsync is not what is measured.

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glassscan::io::exr::{write_irradiance_exr, IrradianceNotes};
use glassscan::scan::adaptive::StopRules;
use glassscan::scan::poses::plan_border_scan;
use glassscan::scan::simulate::simulate_pose;
use glassscan::scene;
use glassscan::sensor::SensorHead;
use glassscan::transport::{TraceScene, TraceSettings};

fn bench(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/edge_study_bare.toml");
    let world = scene::load(&path).expect("shipped scenes load");
    let head = SensorHead::new(&world.sensor).unwrap();
    let trace = TraceScene::new(&world).unwrap();
    let border = world.true_border_in_base().unwrap();
    let pose = plan_border_scan(&border, &world.scan, &world.mount).remove(0);
    let notes = IrradianceNotes {
        wavelength_m: world.sensor.laser.wavelength_m,
        exposure_s: world.sensor.imager.exposure_s,
        sensor_to_base: pose.sensor,
    };
    let shm = Path::new("/dev/shm");
    let dir = if shm.is_dir() {
        tempfile::tempdir_in(shm)
    } else {
        tempfile::tempdir()
    }
    .unwrap();
    let file = dir.path().join("pose.exr");

    let mut g = c.benchmark_group("exr");
    g.sample_size(20);
    for (label, photons) in [
        ("write_irradiance_1000_photons", 1000),
        ("write_irradiance_1M_photons", 1 << 20),
    ] {
        let settings = TraceSettings {
            photons,
            adaptive: false,
            max_depth: 64,
            seed: 1,
        };
        let irradiance =
            simulate_pose(&trace, &head, &pose, &settings, StopRules::EDGE_LINE).irradiance;
        let raw_bytes = 4 * irradiance.total.data.len() * (1 + irradiance.by_class.len());
        g.throughput(Throughput::Bytes(raw_bytes as u64));
        g.bench_function(label, |b| {
            b.iter(|| write_irradiance_exr(&file, &irradiance, &notes).unwrap())
        });
    }
    g.finish();
}

// Without plots: they need system fonts (benches/README.md).
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = bench
}
criterion_main!(benches);
