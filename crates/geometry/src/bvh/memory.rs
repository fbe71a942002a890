//! Large arrays (nodes, triangle packets) are read in random order by incoherent rays:
//! with 4 KiB pages nearly every node fetch also misses the TLB. Asking Linux for
//! transparent huge pages on them (as Embree does for its BVH memory) removes most of
//! those misses. Elsewhere, and where THP is off, this does nothing.

/// Advises the kernel to back `v`'s allocated capacity with huge pages. Call it right
/// after allocating, before the memory is first written.
pub fn advise_huge_pages<T>(v: &mut Vec<T>) {
    #[cfg(target_os = "linux")]
    {
        const MADV_HUGEPAGE: i32 = 14;
        const HUGE: usize = 2 << 20;
        extern "C" {
            fn madvise(addr: *mut std::ffi::c_void, len: usize, advice: i32) -> i32;
        }
        let bytes = v.capacity() * std::mem::size_of::<T>();
        if bytes < 2 * HUGE {
            return;
        }
        // madvise wants a page-aligned start: advise the whole huge pages inside.
        let start = v.as_mut_ptr() as usize;
        let aligned = (start + HUGE - 1) & !(HUGE - 1);
        let end = (start + bytes) & !(HUGE - 1);
        if end > aligned {
            // SAFETY: the range lies inside `v`'s own allocation; MADV_HUGEPAGE only
            // changes how the kernel backs it, never its contents. Failure is harmless.
            unsafe {
                madvise(
                    aligned as *mut std::ffi::c_void,
                    end - aligned,
                    MADV_HUGEPAGE,
                );
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = v;
}
