//! Buffers of many megabytes that a fresh process fills once: the arcs of a 10^6-arc
//! artifact (40 MB) and the planner's rows of them (16 MB). Filling fresh memory costs a
//! page fault per 4 KiB page, about a quarter of `cellc plan` on such an artifact; the
//! kernel can back the buffer with 2 MiB pages instead, but on machines whose
//! transparent huge pages are `madvise` only (Debian's default) it does so only when
//! asked. [`with_capacity`] asks, on Linux, for buffers of at least [`THRESHOLD`] bytes.
//! The advice changes neither the contents nor the validity of the memory, and a
//! refusal is ignored: the buffer is then an ordinary one.

/// Buffers smaller than this (bytes) are left alone: a few faults cost less than the call.
pub const THRESHOLD: usize = 4 << 20;

/// `Vec::with_capacity(n)`, its memory advised to use huge pages when large.
pub fn with_capacity<T>(n: usize) -> Vec<T> {
    let v = Vec::with_capacity(n);
    advise(
        v.as_ptr() as usize,
        v.capacity().saturating_mul(size_of::<T>()),
    );
    v
}

#[cfg(target_os = "linux")]
fn advise(start: usize, bytes: usize) {
    const PAGE: usize = 4096;
    if bytes < THRESHOLD {
        return;
    }
    // madvise takes a page-aligned start; the partial first page is left out.
    let aligned = start.div_ceil(PAGE) * PAGE;
    let end = start + bytes;
    if aligned >= end {
        return;
    }
    // SAFETY: the range lies inside the vector's own allocation, and MADV_HUGEPAGE only
    // tells the kernel how to back it: no byte of it is read, written or unmapped.
    unsafe {
        libc::madvise(
            aligned as *mut libc::c_void,
            end - aligned,
            libc::MADV_HUGEPAGE,
        );
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_start: usize, _bytes: usize) {}

#[cfg(test)]
mod tests {
    #[test]
    fn a_large_buffer_is_an_ordinary_vector() {
        let mut v: Vec<u64> = super::with_capacity(1 << 20);
        assert!(v.capacity() >= 1 << 20);
        v.extend(0..1 << 20);
        assert_eq!(v.iter().sum::<u64>(), (1u64 << 20) * ((1 << 20) - 1) / 2);
    }
}
