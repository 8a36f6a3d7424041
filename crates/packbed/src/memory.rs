//! What the process holds on to after a parallel stage.

/// Gives memory that other threads freed back to the system.
///
/// glibc's allocator keeps a block freed on a worker thread in that thread's
/// arena, for that thread to reuse. After the two-piece triangulation the
/// worker's arena held about 80 MB that no later stage reused, and it stood
/// on top of the flow's peak at 10^6 spheres (3.40 GB against 3.28 GB with one
/// arena). Elsewhere a no-op.
pub fn release_freed() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        extern "C" {
            fn malloc_trim(pad: usize) -> std::os::raw::c_int;
        }
        // SAFETY: `malloc_trim` only returns free pages of glibc's arenas to
        // the system; it touches no memory the program holds.
        unsafe {
            malloc_trim(0);
        }
    }
}
