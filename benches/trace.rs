//! One full opaque profile: transport + exposure + extraction of `scenes/flat_opaque.toml`'s
//! first scan pose with the CLI's default photon count (criterion).

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glassscan::scan::poses::plan_border_scan;
use glassscan::scan::simulate::simulate_pose;
use glassscan::scene;
use glassscan::sensor::SensorHead;
use glassscan::transport::{TraceScene, TraceSettings};

fn bench(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/flat_opaque.toml");
    let world = scene::load(&path).expect("flat_opaque.toml loads");
    let head = SensorHead::new(&world.sensor).unwrap();
    let trace = TraceScene::new(&world).unwrap();
    let target = world.target.as_ref().unwrap();
    let border = target
        .border
        .transformed(&world.objects[target.object].pose);
    let pose = plan_border_scan(&border, &world.scan, &world.mount).remove(0);
    let settings = TraceSettings {
        photons: 1 << 20,
        max_depth: 16,
        seed: 1,
    };
    let mut g = c.benchmark_group("profile");
    g.sample_size(10);
    g.throughput(Throughput::Elements(settings.photons));
    g.bench_function("flat_opaque_pose0_1M_photons", |b| {
        b.iter(|| {
            simulate_pose(&trace, &head, &pose, &settings)
                .profile
                .points
                .len()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
