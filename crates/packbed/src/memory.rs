//! What the process holds on to after a parallel stage, and how its largest
//! blocks are backed.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

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

/// Blocks from this size up are backed by huge pages while a stage asks for
/// them (glibc maps them apart from its arenas, untouched until written).
const HUGE_FROM: usize = 32 << 20;

/// The size of a transparent huge page on x86-64 and most aarch64 kernels.
const HUGE_PAGE: usize = 2 << 20;

/// How many stages now want huge pages (a count, so that stages on several
/// threads do not switch them off for each other).
static HUGE_WANTED: AtomicUsize = AtomicUsize::new(0);

/// The process's allocator: the system's, except that while a stage holds
/// `huge_pages` a large block is advised onto transparent huge pages before
/// it is first written.
///
/// The flow's sweeps read the couplings of a row at scattered columns of
/// vectors of hundreds of megabytes: with 4 KiB pages nearly every such read
/// misses the TLB. On huge pages the 10^6-sphere flow ran 19.1 and 18.8 s
/// against 19.9 and 19.4 s (in turn, docs/history/benchmarks.md). The triangulation and the network ran slower on them
/// (they reserve room they touch only in part, and a huge page is zeroed
/// whole), so the advice is scoped, not global. Where the kernel has no
/// transparent huge pages the advice fails and nothing changes.
pub struct Allocator;

/// Huge pages for large blocks until the guard is dropped.
#[must_use = "huge pages last as long as the guard"]
pub struct HugePages(());

/// Asks for huge pages under large blocks allocated until the guard drops.
pub fn huge_pages() -> HugePages {
    HUGE_WANTED.fetch_add(1, Ordering::Relaxed);
    HugePages(())
}

impl Drop for HugePages {
    fn drop(&mut self) {
        HUGE_WANTED.fetch_sub(1, Ordering::Relaxed);
    }
}

/// The whole huge pages inside the block `[at, at + size)`, if any.
#[cfg_attr(not(target_os = "linux"), allow(dead_code))]
fn huge_range(at: usize, size: usize) -> Option<(usize, usize)> {
    let start = at.next_multiple_of(HUGE_PAGE);
    let end = (at + size) & !(HUGE_PAGE - 1);
    (end > start).then_some((start, end))
}

/// Advises the whole huge pages inside `[ptr, ptr + size)`.
fn advise_huge(ptr: *mut u8, size: usize) {
    if size < HUGE_FROM || HUGE_WANTED.load(Ordering::Relaxed) == 0 {
        return;
    }
    #[cfg(target_os = "linux")]
    {
        extern "C" {
            fn madvise(
                addr: *mut std::ffi::c_void,
                len: usize,
                advice: std::os::raw::c_int,
            ) -> std::os::raw::c_int;
        }
        const MADV_HUGEPAGE: std::os::raw::c_int = 14;
        if let Some((start, end)) = huge_range(ptr as usize, size) {
            // SAFETY: the range lies inside a block just allocated to us, and
            // the advice changes how its pages are backed, never their
            // contents; a kernel without huge pages refuses it, harmlessly.
            unsafe {
                madvise(start as *mut std::ffi::c_void, end - start, MADV_HUGEPAGE);
            }
        }
    }
}

// SAFETY: every block comes from, and goes back to, the system allocator
// unchanged; the advice touches no byte of it.
unsafe impl GlobalAlloc for Allocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            advise_huge(p, layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc_zeroed(layout);
        if !p.is_null() {
            advise_huge(p, layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = System.realloc(ptr, layout, new_size);
        if !p.is_null() {
            advise_huge(p, new_size);
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn large_blocks_under_the_guard_hold_what_is_written() {
        let _huge = huge_pages();
        let layout = Layout::from_size_align(HUGE_FROM + 3 * HUGE_PAGE + 8, 8).unwrap();
        // SAFETY: a non-zero layout; the block is written and read within
        // its size, then freed with the same layout.
        unsafe {
            let p = Allocator.alloc_zeroed(layout);
            assert!(!p.is_null());
            let words = std::slice::from_raw_parts_mut(p.cast::<u64>(), layout.size() / 8);
            assert!(words.iter().all(|&w| w == 0));
            for (i, w) in words.iter_mut().enumerate() {
                *w = i as u64 * 7;
            }
            let grown = Allocator.realloc(p, layout, layout.size() * 2);
            assert!(!grown.is_null());
            let words = std::slice::from_raw_parts(grown.cast::<u64>(), layout.size() / 8);
            assert!(words.iter().enumerate().all(|(i, &w)| w == i as u64 * 7));
            Allocator.dealloc(
                grown,
                Layout::from_size_align(layout.size() * 2, 8).unwrap(),
            );
        }
    }

    #[test]
    fn only_whole_huge_pages_inside_the_block_are_advised() {
        let page = HUGE_PAGE;
        // A block starting just past a page boundary: its first whole page
        // starts at the next boundary, its last ends at the last one inside.
        let at = 7 * page + 16;
        let (start, end) = huge_range(at, HUGE_FROM).unwrap();
        assert_eq!(start, 8 * page);
        assert_eq!(end, (at + HUGE_FROM) / page * page);
        assert!(start >= at && end <= at + HUGE_FROM);
        // Aligned blocks keep every page; one shorter than a page, none.
        assert_eq!(huge_range(4 * page, 3 * page), Some((4 * page, 7 * page)));
        assert_eq!(huge_range(4 * page + 1, page), None);
    }
}
