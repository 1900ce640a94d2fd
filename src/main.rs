//! The `glassscan` command line: everything lives in `glassscan::cli`.

fn main() -> std::process::ExitCode {
    keep_freed_memory();
    glassscan::cli::run()
}

/// Tells glibc's allocator to keep freed blocks up to 32 MiB in the heap instead of returning
/// them to the kernel. A pose allocates and frees tens of 4 MB images (irradiance layers, the
/// lens's passes, the sensor's frames; more with `--photons auto`, which senses a pose after
/// every doubling), and by default each one is a fresh mmap whose pages fault in and are
/// zeroed again: 17 % of an adaptive scan's samples in `perf`, 1.2 s of system time in
/// `scan edge_study_bare --scan-angle-deg 45 --poses 8 --photons auto` (benches/README.md). The
/// outputs do not change; the peak memory grows (315 → 450 MiB there).
///
/// The trim threshold binds only the main thread's heap. What rayon's workers allocate (a
/// dataset's samples, a study's poses side by side) lives in per-thread arenas, whose heaps
/// glibc unmaps whole once they empty, whatever the threshold, unless the top pad says to keep
/// that much beyond the last block (glibc 2.36 `heap_trim`); so each sample faulted its images
/// in again. A 64 MiB pad keeps them: `dataset edge_study_bare --count 8` spends 0.16 instead
/// of 0.45 s in the kernel and 0.92× the CPU time, with the same peak memory (benches/README.md,
/// 2026-12-07, evening). Untouched padding is address space, not memory.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn keep_freed_memory() {
    const MIB: libc::c_int = 1 << 20;
    // SAFETY: mallopt only sets the allocator's parameters; called before any thread starts.
    // 32 MiB is the largest mmap threshold glibc accepts on 64-bit targets; a refusal (0)
    // leaves the defaults, which are correct, only slower.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 * MIB);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 1024 * MIB);
        libc::mallopt(libc::M_TOP_PAD, 64 * MIB);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn keep_freed_memory() {}
