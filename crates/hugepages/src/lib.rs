//! A hint to Linux to back a long buffer with transparent huge pages.
//!
//! Where the system gives huge pages only on request (`madvise` mode, the
//! usual default), a buffer filled for the first time takes a page fault,
//! a trip into the kernel, every 4 KiB: 56 000 for an 8-hour 1 kHz column
//! (230 MB), 2 000 for the phase of 10^6 samples. Only the whole 2 MiB pages
//! inside the buffer are advised, so the 2 MiB at either end that are not
//! fault as before: the column takes 108 or 109 huge pages and up to 1 000 small
//! faults, the phase of 10^6 samples 2 or 3 huge pages and 400 to 900 small
//! ones. The readers of `imu` advise their columns, `allan` the copy it
//! converts to phase.
//!
//! It is a hint, not an allocator: the contents, the length and the mapping
//! of the buffer never change, and nothing happens where huge pages are
//! off, on other systems, or for a buffer smaller than one huge page. It has
//! one cost: with the kernel's `defrag` setting at `madvise` (the default),
//! a fault in an advised range may wait while the kernel compacts memory to
//! find a free 2 MiB page, which on a long-running, fragmented host can
//! take longer than the small faults it saves.
//!
//! ```
//! let mut column: Vec<f64> = Vec::with_capacity(1 << 20);
//! hugepages::advise(&mut column);
//! column.extend((0..1 << 20).map(f64::from));
//! assert_eq!(column[12345], 12345.0);
//! ```

/// The transparent huge page size of x86-64 and of 4 KiB-page arm64 and
/// 32-bit ARM. Where the kernel's is larger (arm64 with 64 KiB pages,
/// ppc64), a buffer holds fewer of them than this assumes and the hint
/// mostly covers no whole huge page: it does nothing, which is harmless.
const HUGE: usize = 2 << 20;

/// The whole huge pages inside `bytes` bytes from address `start`, as a
/// start and a length: rounded inward, so that the hint never covers a
/// neighbouring allocation. `None` when no whole huge page fits, including
/// at the very top of the address space, where rounding up would wrap.
fn huge_range(start: usize, bytes: usize) -> Option<(usize, usize)> {
    let end = start.checked_add(bytes)?;
    let first = start.checked_next_multiple_of(HUGE)?;
    let last = end / HUGE * HUGE;
    (last > first).then(|| (first, last - first))
}

/// Advises the whole 2 MiB pages inside `buffer`'s allocation (its
/// capacity, not only its length) to be backed by huge pages.
#[cfg(any(target_os = "linux", target_os = "android"))]
pub fn advise<T>(buffer: &mut Vec<T>) {
    let bytes = buffer.capacity().saturating_mul(std::mem::size_of::<T>());
    if let Some((first, len)) = huge_range(buffer.as_mut_ptr() as usize, bytes) {
        // SAFETY: the range lies inside the vector's own allocation, and
        // MADV_HUGEPAGE changes how its pages are backed, never their
        // contents or whether they are mapped. The result is not read: a
        // kernel built without huge pages answers EINVAL, and then the
        // buffer is simply backed as before.
        unsafe {
            libc::madvise(first as *mut libc::c_void, len, libc::MADV_HUGEPAGE);
        }
    }
}

/// Does nothing: huge pages on request are a feature of Linux.
#[cfg(not(any(target_os = "linux", target_os = "android")))]
pub fn advise<T>(_buffer: &mut Vec<T>) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_range_is_the_whole_huge_pages_inside() {
        // Aligned at both ends: all of it.
        assert_eq!(huge_range(4 * HUGE, 3 * HUGE), Some((4 * HUGE, 3 * HUGE)));
        // Unaligned: rounded inward at both ends.
        assert_eq!(huge_range(4 * HUGE + 8, 3 * HUGE), Some((5 * HUGE, 2 * HUGE)));
        assert_eq!(huge_range(4 * HUGE - 8, 2 * HUGE), Some((4 * HUGE, HUGE)));
        // Less than one whole huge page, empty and zero-sized buffers.
        assert_eq!(huge_range(4 * HUGE + 8, 2 * HUGE - 16), None);
        assert_eq!(huge_range(4 * HUGE + 8, HUGE), None);
        assert_eq!(huge_range(4 * HUGE, 0), None);
        // At the top of the address space nothing wraps to address 0.
        assert_eq!(huge_range(usize::MAX - HUGE / 2, 100), None);
        assert_eq!(huge_range(usize::MAX - 3 * HUGE, usize::MAX), None);
    }

    #[test]
    fn the_buffer_is_the_same_after_the_hint() {
        let mut v: Vec<u64> = (0..3 << 20).collect();
        v.reserve(1 << 20);
        let (ptr, len, cap) = (v.as_ptr(), v.len(), v.capacity());
        advise(&mut v);
        assert_eq!((v.as_ptr(), v.len(), v.capacity()), (ptr, len, cap));
        assert!(v.iter().enumerate().all(|(i, &x)| x == i as u64));
        advise(&mut vec![1.0f64; 10]);
        advise(&mut Vec::<f64>::new());
        advise(&mut vec![(); 1 << 30]);
    }

    /// The kernel's own record of the mapping: after the hint, the part of
    /// the buffer advised is a mapping of its own whose flags hold `hg`.
    #[cfg(target_os = "linux")]
    #[test]
    fn the_kernel_records_the_hint() {
        let enabled = std::fs::read_to_string("/sys/kernel/mm/transparent_hugepage/enabled");
        if !enabled.is_ok_and(|mode| !mode.contains("[never]")) {
            eprintln!("transparent huge pages are off or absent here: nothing to check");
            return;
        }
        let mut v: Vec<f64> = Vec::with_capacity(4 << 20);
        advise(&mut v);
        let (first, _) = huge_range(v.as_ptr() as usize, v.capacity() * 8).expect("32 MiB buffer");
        let smaps = std::fs::read_to_string("/proc/self/smaps").expect("/proc/self/smaps");
        let mut inside = false;
        let mut flags = None;
        for line in smaps.lines() {
            let range = line.split_whitespace().next().and_then(|r| r.split_once('-'));
            if let Some((a, b)) = range.and_then(|(a, b)| {
                Some((
                    usize::from_str_radix(a, 16).ok()?,
                    usize::from_str_radix(b, 16).ok()?,
                ))
            }) {
                inside = (a..b).contains(&first);
            } else if inside && let Some(f) = line.strip_prefix("VmFlags:") {
                flags = Some(f.to_string());
                break;
            }
        }
        let flags = flags.expect("the buffer's mapping in /proc/self/smaps");
        assert!(flags.split_whitespace().any(|f| f == "hg"), "VmFlags:{flags}");
    }
}
