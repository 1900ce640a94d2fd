//! A study's poses simulated side by side.
//!
//! A pose's light is traced photon-parallel (`transport::trace`), but a study's pose also has
//! stages that run on one thread per sensor setting: the sensor's noise draws, peak detection,
//! the BIPs by both rules and their tallies, for each exposure of the exposure axis. Run one
//! pose after another, the second core idled through them (the default study kept 1.82 of 2
//! cores busy). Running the poses in parallel as well lets rayon's work stealing fill those
//! gaps with another pose's photons (1.98 cores, 1.13× less wall time on the default study,
//! benches/README.md). `scan` and `locate`, with one sensing per pose, gained at most 2 % and
//! held more images at once, so they keep one pose at a time.
//!
//! Results come back in pose order, and each depends only on the seed and its own pose (every
//! random stream is keyed on both), so the outputs are the same for any thread count and the
//! same as one pose after another. Only the order of progress ticks may change.

use rayon::prelude::*;

/// `run` applied to every pose, several at a time, the results in the poses' order.
/// `on_pose` is called after each (progress; from any thread).
pub fn map_poses<P: Sync, T: Send>(
    poses: &[P],
    on_pose: &(dyn Fn() + Sync),
    run: impl Fn(&P) -> T + Sync,
) -> Vec<T> {
    poses
        .par_iter()
        .map(|p| {
            let out = run(p);
            on_pose();
            out
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn results_keep_the_poses_order_and_every_pose_ticks_once() {
        let poses: Vec<u64> = (0..100).collect();
        let ticks = AtomicUsize::new(0);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap();
        let out = pool.install(|| {
            map_poses(
                &poses,
                &|| {
                    ticks.fetch_add(1, Ordering::Relaxed);
                },
                |&p| p * p,
            )
        });
        assert_eq!(out, poses.iter().map(|p| p * p).collect::<Vec<_>>());
        assert_eq!(ticks.load(Ordering::Relaxed), poses.len());
    }
}
