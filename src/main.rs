//! The `rapidtherm` command: parses arguments and calls the library.

mod cli;

fn main() -> std::process::ExitCode {
    return_large_buffers();
    cli::main()
}

/// glibc's allocator raises its mmap threshold (up to 32 MiB) each time
/// it frees a large buffer, and keeps later buffers below it in its heap
/// after they are freed: a correction's chunk buffers, freed as it goes,
/// stayed resident, 30 MiB of the peak of a million declared targets. A
/// fixed threshold hands every buffer of 128 KiB or more back to the
/// system when it is freed.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn return_large_buffers() {
    // SAFETY: mallopt sets a tunable of the allocator; it is called once,
    // before any other thread exists.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 128 * 1024);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn return_large_buffers() {}
