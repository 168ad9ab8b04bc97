//! The one-column file's quick loop: lines of at most 15 bytes that are a
//! plain decimal, read from one 16-byte load each, with SSSE3 and SSE4.1
//! where the CPU has them (checked once a block) and SWAR words elsewhere.

use crate::decimal::Quotient;

/// Lines of one column parsed before their divisions are done.
const QUOTIENT_BATCH: usize = 64;

/// Reads the short plain lines at the start of `rest` into `column`: the
/// bytes they took and their number. Stops at the first line the quick
/// form does not take whole, which the caller's careful loop then reads.
pub(super) fn read(rest: &[u8], column: &mut Vec<f64>) -> (usize, u64) {
    #[cfg(target_arch = "x86_64")]
    if crate::decimal_x86::available() {
        // SAFETY: `available` found SSSE3 and SSE4.1 on this CPU, the
        // only requirement of a `target_feature` function.
        return unsafe { read_sse41(rest, column) };
    }
    read_with(rest, column, short_line)
}

/// A short line's quotient and length, in SWAR words.
#[inline(always)]
fn short_line(s: &[u8]) -> Option<(Quotient, usize)> {
    let len = short_line_len(s)?;
    Some((crate::decimal::short_quotient(s, len)?, len))
}

/// [`read_with`] compiled for SSSE3 and SSE4.1, so that their parse
/// inlines into the loop.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "ssse3,sse4.1")]
fn read_sse41(rest: &[u8], column: &mut Vec<f64>) -> (usize, u64) {
    read_with(rest, column, |s| crate::decimal_x86::short_line(s))
}

/// The loop, with the line parse it is given.
///
/// Each line's end is found from its first 16 bytes apart from the
/// number's parse, so the next line's address does not wait for the
/// digits: successive lines overlap in the processor. (A 64-byte newline
/// mask turned into line positions first, SIMD compares included, did
/// not pay: the same instructions a line, and slower.) The divisions are
/// done a batch at a time, where they run two to an instruction (they
/// were a third of the loop).
#[inline(always)]
fn read_with(
    rest: &[u8],
    column: &mut Vec<f64>,
    line: impl Fn(&[u8]) -> Option<(Quotient, usize)>,
) -> (usize, u64) {
    let mut pos = 0;
    let mut lines = 0;
    let mut batch = [Quotient {
        numerator: 0.0,
        denominator: 1.0,
    }; QUOTIENT_BATCH];
    loop {
        let mut n = 0;
        while n < QUOTIENT_BATCH
            && let Some((q, len)) = line(&rest[pos..])
        {
            batch[n] = q;
            n += 1;
            pos += len + 1;
        }
        column.extend(batch[..n].iter().map(|q| q.numerator / q.denominator));
        lines += n as u64;
        if n < QUOTIENT_BATCH {
            return (pos, lines);
        }
    }
}

/// The length of the line at the start of `s` when its newline lies
/// within its first 16 bytes (and `s` has 16): two 8-byte words tested for
/// a newline byte at once. The lowest flagged byte is exact (a borrow
/// only flags bytes above a true match).
#[inline(always)]
fn short_line_len(s: &[u8]) -> Option<usize> {
    const ONES: u64 = 0x0101_0101_0101_0101;
    const HIGHS: u64 = 0x8080_8080_8080_8080;
    let newline = |w: u64| {
        let x = w ^ (ONES * u64::from(b'\n'));
        x.wrapping_sub(ONES) & !x & HIGHS
    };
    let words = s.get(..16)?;
    let (a, b) = words.split_at(8);
    let a = newline(u64::from_le_bytes(a.try_into().ok()?));
    if a != 0 {
        return Some((a.trailing_zeros() / 8) as usize);
    }
    let b = newline(u64::from_le_bytes(b.try_into().ok()?));
    (b != 0).then(|| 8 + (b.trailing_zeros() / 8) as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    proptest::proptest! {
        /// The word test finds the first newline of the first 16 bytes,
        /// whatever bytes surround it (0x0b and 0x8a differ from a newline
        /// in one bit each, 0x09 borrows).
        #[test]
        fn short_line_len_finds_the_first_newline(bytes in proptest::collection::vec(
            proptest::prop_oneof![proptest::prelude::Just(b'\n'), proptest::prelude::Just(0x0b_u8),
                proptest::prelude::Just(0x8a_u8), proptest::prelude::Just(0x09_u8), proptest::prelude::any::<u8>()],
            0..24,
        )) {
            let want = (bytes.len() >= 16)
                .then(|| bytes[..16].iter().position(|&b| b == b'\n'))
                .flatten();
            proptest::prop_assert_eq!(short_line_len(&bytes), want);
        }

        /// Both forms of the loop take the same lines, stop at the same
        /// byte and give the same bits, on lines of every shape.
        #[test]
        fn both_loops_read_the_same_lines(
            lines in proptest::collection::vec(
                "-?[0-9]{0,9}\\.?[0-9]{0,9}|[0-9.eE+-]{0,6}|[0-9]{0,6}[\\r\\x80\\x2f\\x3a]?[0-9.]{0,6}",
                0..200,
            ),
        ) {
            let text = lines.iter().map(|l| format!("{l}\n")).collect::<String>() + "0123456789abcdef";
            let (mut scalar, mut dispatched) = (Vec::new(), Vec::new());
            let a = read_with(text.as_bytes(), &mut scalar, short_line);
            let b = read(text.as_bytes(), &mut dispatched);
            proptest::prop_assert_eq!(a, b);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            proptest::prop_assert_eq!(bits(&scalar), bits(&dispatched));
        }
    }
}
