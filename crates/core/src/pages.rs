//! Large buffers on 2 MiB pages.
//!
//! A freshly allocated buffer of tens of megabytes (a film of a 1280x720 image is 37
//! MB) is mapped by the kernel one 4 KiB page at a time, each on its first write: some
//! 9,000 page faults, each clearing its page, about a tenth of a one-sample Whitted
//! render's time. Linux's transparent huge pages back a range advised with
//! `MADV_HUGEPAGE` by 2 MiB pages instead (512 times fewer faults, and fewer TLB
//! misses afterwards); distributions ship them in `madvise` mode, so a process gets
//! them only where it asks (Linux's Documentation/admin-guide/mm/transhuge.rst).
//!
//! Used for the film and the image made from it, for the BVH's nodes and leaf
//! packets (incoherent rays read them in random order, so on 4 KiB pages nearly every
//! node fetch also misses the TLB; Embree advises its BVH memory likewise), and for
//! the arrays `irradia.composite` returns.

const HUGE: usize = 2 << 20;

/// Asks for `buf`'s whole 2 MiB pages to be huge pages when first touched. Call it
/// right after allocating, before writing: pages already touched stay as they are
/// until the kernel collapses them. A hint only: nothing changes where the kernel
/// declines, on other systems, or for buffers holding no whole aligned 2 MiB page
/// (so a huge page never reaches beyond the buffer).
pub fn prefer_huge_pages<T>(buf: &mut [T]) {
    advise_inside(buf.as_mut_ptr() as usize, std::mem::size_of_val(buf));
}

/// [`prefer_huge_pages`] for the `len` elements at `ptr`, which may be uninitialised
/// (a Vec's spare capacity, a fresh numpy array). Safe: advising reads and writes
/// nothing, and a range that is not mapped is refused by the kernel, harmlessly.
pub fn prefer_huge_pages_raw<T>(ptr: *mut T, len: usize) {
    advise_inside(ptr as usize, len * std::mem::size_of::<T>());
}

/// Advises the whole 2 MiB pages inside `[start, start + len)`.
fn advise_inside(start: usize, len: usize) {
    let lo = start.next_multiple_of(HUGE);
    let hi = (start + len) & !(HUGE - 1);
    if hi > lo {
        advise(lo, hi - lo);
    }
}

#[cfg(target_os = "linux")]
fn advise(addr: usize, len: usize) {
    // SAFETY: `[addr, addr + len)` is page-aligned; MADV_HUGEPAGE changes how the
    // range is backed, never its contents or its mapping, and its failure (EINVAL
    // where THP is off, ENOMEM for a range not mapped) leaves everything as it was,
    // so the result is ignored.
    unsafe {
        libc::madvise(addr as *mut libc::c_void, len, libc::MADV_HUGEPAGE);
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_addr: usize, _len: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn advised_buffers_keep_their_contents() {
        let mut v = vec![0u64; (9 << 20) / 8];
        prefer_huge_pages(&mut v);
        for (i, x) in v.iter_mut().enumerate().step_by(4096) {
            *x = i as u64;
        }
        assert!(v
            .iter()
            .enumerate()
            .all(|(i, &x)| x == if i % 4096 == 0 { i as u64 } else { 0 }));
        let mut small = vec![1u8; 100];
        prefer_huge_pages(&mut small);
        assert_eq!(small, vec![1u8; 100]);
    }
}
