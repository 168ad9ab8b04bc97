//! Software prefetch: hints that ask for cache lines before the kernels
//! read them.
//!
//! The O(N) statistics read the series at three or four offsets, j, j + m,
//! j + 2m (and j + 3m). The leading stream is new data; the others were
//! read m points and more earlier. With those streams m points apart, the
//! hardware prefetcher no longer runs far enough ahead of the leading one,
//! and MDEV at m = 4096 ran at about a third of its in-cache speed. Asking
//! for the leading stream's lines [`DISTANCE`] bytes ahead recovered most
//! of it (`allan_per_tau N passes`, bench/README.md). The overlapped sums
//! that take a far factor's series in pieces by residue ask for the piece two ahead in their own
//! order instead ([`line`]). MDEV's scans also ask for the two oldest
//! streams a few lines ahead: with the leading stream's lines in the L1
//! cache as well, those streams come from L2 from m of about 1024 on. The
//! decimating copies ([`crate::decimate`]) ask for every line they will
//! read, 16 KiB or 64 points ahead. Off x86-64 the hints are nothing.

/// How far ahead of the leading stream, in bytes. 8 KiB and more reached
/// the in-cache speed where it was measured; 2 KiB recovered only half.
pub(crate) const DISTANCE: usize = 16 << 10;

/// Asks for the cache line `DISTANCE` bytes past `x[at]`. A hint only: it
/// changes no value. Only the x86-64 MDEV scans ask for it.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(crate) fn ahead(x: &[f64], at: usize) {
    line(x, at.wrapping_add(DISTANCE / 8));
}

/// Asks for the cache line of `x[at]`: for a stream whose next lines are
/// not the ones past its current ones, or a distance other than
/// [`DISTANCE`]. A hint only, as [`ahead`].
#[inline(always)]
pub(crate) fn line(x: &[f64], at: usize) {
    // The address is formed with wrapping arithmetic and never read: past
    // the end of `x` the hint is for memory the program does not use,
    // which costs a wasted fetch at most. A bounds check here cost more
    // than the prefetch itself in the kernels' inner loops.
    let line = x.as_ptr().wrapping_add(at);
    #[cfg(target_arch = "x86_64")]
    // SAFETY: the intrinsic is compiled for SSE, part of the x86-64
    // baseline; the pointer need not be valid (PREFETCHT0 does not trap on
    // any address, as the intrinsic's documentation says).
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(line.cast::<i8>())
    };
    #[cfg(not(target_arch = "x86_64"))]
    let _ = line;
}
