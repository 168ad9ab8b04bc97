//! A hint to Linux to back a long buffer with transparent huge pages.
//!
//! Where the system gives huge pages only on request (`madvise` mode, the
//! usual default), a buffer filled for the first time takes a page fault,
//! a trip into the kernel, every 4 KiB: 56 000 for an 8-hour 1 kHz column
//! (230 MB), 2 000 for the phase of 10^6 samples. In 2 MiB pages it takes
//! 110 and 4. The readers of `imu` advise their columns, `allan` the copy
//! it converts to phase.
//!
//! It is only a hint, not an allocator: the contents, the length and the
//! mapping of the buffer never change, and nothing happens where huge
//! pages are off, on other systems, or for a buffer smaller than one huge
//! page.
//!
//! ```
//! let mut column: Vec<f64> = Vec::with_capacity(1 << 20);
//! hugepages::advise(&mut column);
//! column.extend((0..1 << 20).map(f64::from));
//! assert_eq!(column[12345], 12345.0);
//! ```

/// Advises the whole 2 MiB pages inside `buffer`'s allocation (its
/// capacity, not only its length) to be backed by huge pages.
#[cfg(target_os = "linux")]
pub fn advise<T>(buffer: &mut Vec<T>) {
    const HUGE: usize = 2 << 20;
    let start = buffer.as_mut_ptr() as usize;
    let end = start + buffer.capacity() * std::mem::size_of::<T>();
    // madvise takes page-aligned ranges: the whole 2 MiB pages inside the
    // buffer.
    let first = start.div_ceil(HUGE) * HUGE;
    let last = end / HUGE * HUGE;
    if last > first {
        // SAFETY: the range lies inside the vector's own allocation, and
        // MADV_HUGEPAGE changes how its pages are backed, never their
        // contents or whether they are mapped.
        unsafe {
            libc::madvise(first as *mut libc::c_void, last - first, libc::MADV_HUGEPAGE);
        }
    }
}

/// Does nothing: huge pages on request are a Linux feature.
#[cfg(not(target_os = "linux"))]
pub fn advise<T>(_buffer: &mut Vec<T>) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_buffer_is_the_same_after_the_hint() {
        let mut v: Vec<u64> = (0..3 << 20).collect();
        v.reserve(1 << 20);
        let (ptr, len, cap) = (v.as_ptr(), v.len(), v.capacity());
        advise(&mut v);
        assert_eq!((v.as_ptr(), v.len(), v.capacity()), (ptr, len, cap));
        assert!(v.iter().enumerate().all(|(i, &x)| x == i as u64));
        // Small, empty and zero-sized buffers are left alone.
        advise(&mut vec![1.0f64; 10]);
        advise(&mut Vec::<f64>::new());
        advise(&mut vec![(); 1 << 30]);
    }
}
