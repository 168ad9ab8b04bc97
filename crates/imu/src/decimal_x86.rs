//! [`crate::decimal::short_quotient`] in SSSE3 and SSE4.1 registers, for
//! CPUs that have them (checked at run time: the build targets baseline
//! x86-64, which has SSE2 only).
//!
//! The line's 16 bytes are read as one vector. Its digits are found by one
//! unsigned compare, the sign and the point by their byte values; one
//! byte shuffle (`pshufb`), its indices looked up by the line's shape,
//! drops the sign and the point and moves the digits to the vector's top
//! with zeros in front; three multiply-adds (`pmaddubsw`, `pmaddwd`, then
//! `pmaddwd` again after `packusdw`) fold them into two eight-digit
//! halves, as in W. Muła's and D. Lemire's SIMD integer parsing (the same
//! steps as `fold8` in the scalar form, sixteen lanes at a time). The
//! one-column loop takes 89 instructions a line this way, 131 with the
//! SWAR words (callgrind, 10^6 lines of `0.0123456`).

use std::arch::x86_64::{
    __m128i, _mm_add_epi8, _mm_cmpeq_epi8, _mm_cmpgt_epi8, _mm_cvtsi128_si64, _mm_madd_epi16,
    _mm_maddubs_epi16, _mm_min_epu8, _mm_movemask_epi8, _mm_or_si128, _mm_packus_epi32, _mm_set_epi8,
    _mm_set_epi64x, _mm_set1_epi8, _mm_set1_epi16, _mm_set1_epi32, _mm_shuffle_epi8, _mm_sub_epi8,
};

use crate::decimal::{POW10, Quotient, le_words};

/// Whether this CPU runs [`short_line`].
pub(crate) fn available() -> bool {
    std::is_x86_feature_detected!("ssse3") && std::is_x86_feature_detected!("sse4.1")
}

/// The line at the start of `s` (which holds at least 16 bytes) when its
/// newline lies within the first 16 bytes, as `(quotient, length)`: what
/// [`crate::decimal::short_quotient`] returns for the line, bit for bit,
/// `None` where it returns `None` or the line is longer.
#[target_feature(enable = "ssse3,sse4.1")]
#[inline]
pub(crate) fn short_line(s: &[u8]) -> Option<(Quotient, usize)> {
    let bytes: &[u8; 16] = s.get(..16)?.try_into().ok()?;
    // One unaligned 16-byte load, without a raw pointer.
    let v = load(bytes);
    let newlines = _mm_movemask_epi8(_mm_cmpeq_epi8(v, _mm_set1_epi8(b'\n' as i8))) as u32;
    let len = (newlines | 1 << 16).trailing_zeros() as usize;
    if len > 15 {
        return None;
    }
    let d = _mm_sub_epi8(v, _mm_set1_epi8(b'0' as i8));
    // d ≤ 9 unsigned: the byte is a digit.
    let digit = _mm_movemask_epi8(_mm_cmpeq_epi8(_mm_min_epu8(d, _mm_set1_epi8(9)), d)) as u32;
    let in_line = (1u32 << len) - 1;
    // (A line of no bytes has no sign: `len − first` stays ≥ 0.)
    let negative = len > 0 && bytes[0] == b'-';
    let first = usize::from(negative);
    let others = !digit & in_line & !(first as u32);
    // At most one non-digit after the sign, and it must be the point.
    let p = others.trailing_zeros() as usize;
    let (digits, frac, point) = if others == 0 {
        (len - first, 0, NO_POINT)
    } else {
        if others & (others - 1) != 0 || bytes[p] != b'.' {
            return None;
        }
        (len - first - 1, len - 1 - p, p)
    };
    if digits == 0 {
        return None;
    }
    let aligned = _mm_shuffle_epi8(d, load(&ALIGN[(first * (NO_POINT + 1) + point) * 16 + len]));
    let w = fold16(aligned);
    // Fifteen digits stay below 2^53: the conversion is exact.
    let w = w as i64 as f64;
    Some((
        Quotient {
            numerator: if negative { -w } else { w },
            denominator: POW10[frac],
        },
        len,
    ))
}

/// [`crate::decimal::plain_digits`] for a number at the start of `s`
/// that stands, with the byte after it, in `s`'s first 32 bytes: the same
/// sign, digits, digits after the point and bytes taken. `None` when the
/// scalar form is to decide (a `+`, no digits, more than 19, an exponent,
/// fewer than 32 bytes), so that it gives the same answer in every case.
///
/// The digits are found in both halves by one unsigned compare each, as
/// bits of one mask; the integer part and the fraction are runs of set
/// bits. The last 16 digits are gathered, right-aligned, by one shuffle
/// of each half (indices computed from the point's place), and folded as
/// in [`short_line`]; up to three leading digits more are added one by
/// one (a thesis log's cells have 16 to 19).
#[target_feature(enable = "ssse3,sse4.1")]
#[inline]
pub(crate) fn plain_digits(s: &[u8]) -> Option<(bool, u64, usize, usize)> {
    let bytes: &[u8; 32] = s.get(..32)?.try_into().ok()?;
    let (low, high) = bytes.split_at(16);
    let (low, high): (&[u8; 16], &[u8; 16]) = (low.try_into().ok()?, high.try_into().ok()?);
    let zeros = _mm_set1_epi8(b'0' as i8);
    let nine = _mm_set1_epi8(9);
    let (dl, dh) = (_mm_sub_epi8(load(low), zeros), _mm_sub_epi8(load(high), zeros));
    let digit_bits = |d: __m128i| _mm_movemask_epi8(_mm_cmpeq_epi8(_mm_min_epu8(d, nine), d)) as u16;
    // Bits 32 and up are not digits: every run below ends by bit 32.
    let not_digit = !(u64::from(digit_bits(dl)) | u64::from(digit_bits(dh)) << 16);
    let negative = bytes[0] == b'-';
    if bytes[0] == b'+' {
        return None;
    }
    let first = usize::from(negative);
    let int_end = first + (not_digit >> first).trailing_zeros() as usize;
    let has_point = bytes.get(int_end) == Some(&b'.');
    let end = if has_point {
        int_end + 1 + (not_digit >> (int_end + 1)).trailing_zeros() as usize
    } else {
        int_end
    };
    // The byte after the number must be seen (an exponent leaves it to
    // the scalar form).
    let after = *bytes.get(end)?;
    let frac_digits = end - int_end - usize::from(has_point);
    let total = int_end - first + frac_digits;
    if total == 0 || total > 19 || after == b'e' || after == b'E' {
        return None;
    }
    // Output lane j takes digit k = total − 16 + j, at first + k, one
    // further once past the point; lanes before the first digit are zero.
    let iota = _mm_set_epi8(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0);
    let index = _mm_add_epi8(iota, _mm_set1_epi8((first as i32 + total as i32 - 16) as i8));
    let point = if has_point { int_end as i8 } else { i8::MAX };
    let index = _mm_sub_epi8(index, _mm_cmpgt_epi8(index, _mm_set1_epi8(point - 1)));
    let before = _mm_cmpgt_epi8(_mm_set1_epi8(16 - total as i8), iota);
    // Indices 16 and up come from the high half: 0x80 (a zero) in the low
    // half's shuffle, and index − 16 in the high half's; below 16, index
    // − 16 is negative, its top bit set, a zero there.
    let in_high = _mm_cmpgt_epi8(index, _mm_set1_epi8(15));
    let low_index = _mm_or_si128(index, _mm_or_si128(in_high, before));
    let high_index = _mm_or_si128(_mm_sub_epi8(index, _mm_set1_epi8(16)), before);
    let aligned = _mm_or_si128(_mm_shuffle_epi8(dl, low_index), _mm_shuffle_epi8(dh, high_index));
    let mut w = fold16(aligned);
    if total > 16 {
        let mut top = 0;
        for k in 0..total - 16 {
            let at = first + k + usize::from(has_point && first + k >= int_end);
            top = top * 10 + u64::from(bytes[at] - b'0');
        }
        w += top * 10_000_000_000_000_000;
    }
    Some((negative, w, frac_digits, end))
}

/// Sixteen digit values, the most significant in byte 0, as one integer.
#[target_feature(enable = "ssse3,sse4.1")]
#[inline]
fn fold16(digits: __m128i) -> u64 {
    // Pairs, fours, then eights: 10·a + b, 100·ab + cd, 10^4·abcd + efgh.
    let pairs = _mm_maddubs_epi16(digits, _mm_set1_epi16(0x010a));
    let fours = _mm_madd_epi16(pairs, _mm_set1_epi32(0x0001_0064));
    let packed = _mm_packus_epi32(fours, fours);
    let eights = _mm_madd_epi16(packed, _mm_set1_epi32(0x0001_2710));
    let halves = _mm_cvtsi128_si64(eights) as u64;
    (halves & 0xffff_ffff) * 100_000_000 + (halves >> 32)
}

#[target_feature(enable = "sse2")]
#[inline]
fn load(bytes: &[u8; 16]) -> __m128i {
    let (lo, hi) = le_words(bytes);
    // The same bits, as the signed lanes the intrinsic takes.
    _mm_set_epi64x(hi as i64, lo as i64)
}

/// The point's index in [`ALIGN`] when a line has none.
const NO_POINT: usize = 16;

/// The `pshufb` indices for each line shape (sign or not, the point's
/// place or none, the length), one after another: output byte j takes
/// digit k = j − (16 − digits), which stands at first + k, one further
/// once past the point; bytes before the digits take 0x80, a zero. Shapes
/// that are not lines (no digits) get any indices: they are refused
/// before the table is read.
static ALIGN: [[u8; 16]; 2 * (NO_POINT + 1) * 16] = {
    let mut table = [[0x80u8; 16]; 2 * (NO_POINT + 1) * 16];
    let mut first = 0;
    while first < 2 {
        let mut point = 0;
        while point <= NO_POINT {
            let mut len = 0;
            while len < 16 {
                let has_point = (point < NO_POINT) as usize;
                if len >= first + has_point {
                    let digits = len - first - has_point;
                    let lead = 16 - digits;
                    let entry = &mut table[(first * (NO_POINT + 1) + point) * 16 + len];
                    let mut j = lead;
                    while j < 16 {
                        let at = first + (j - lead);
                        entry[j] = if has_point == 1 && at >= point { at + 1 } else { at } as u8;
                        j += 1;
                    }
                }
                len += 1;
            }
            point += 1;
        }
        first += 1;
    }
    table
};

#[cfg(test)]
mod tests {
    use super::*;

    fn same(line: &str, after: &str) {
        if !available() {
            return;
        }
        let s = format!("{line}\n{after}");
        let len = line.len();
        // SAFETY: `available()` above found SSSE3 and SSE4.1 on this CPU.
        let fast = unsafe { short_line(s.as_bytes()) }.map(|(q, n)| {
            assert_eq!(n, len, "{line:?}");
            q
        });
        let scalar = crate::decimal::short_quotient(s.as_bytes(), len);
        match (fast, scalar) {
            (Some(a), Some(b)) => {
                assert_eq!(a.numerator.to_bits(), b.numerator.to_bits(), "{line:?}");
                assert_eq!(a.denominator.to_bits(), b.denominator.to_bits(), "{line:?}");
            }
            (None, None) => {}
            _ => panic!("{line:?}: {fast:?} vs {scalar:?}"),
        }
    }

    #[test]
    fn shapes_at_the_edges_read_as_the_scalar_form_reads_them() {
        for line in [
            "0",
            "-0",
            "-",
            ".",
            "-.",
            "",
            "1.",
            ".5",
            "-.5",
            "0.0123456",
            "-0.0123456",
            "123456789012345",
            "-12345678901234",
            "1234567.1234567",
            "-.1234567890123",
            "99999999999999.",
            "1.2.3",
            "--1",
            "1-",
            "+1",
            "1e5",
            "1/2",
            "1:2",
            "1\r",
            "1234567890123456",
            "\u{80}1",
        ] {
            same(line, "0123456789abcdef");
            same(line, "\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n");
        }
    }

    fn same_digits(s: &[u8]) {
        if !available() {
            return;
        }
        // SAFETY: `available()` above found SSSE3 and SSE4.1 on this CPU.
        if let Some(fast) = unsafe { plain_digits(s) } {
            assert_eq!(
                Some(fast),
                crate::decimal::plain_digits(s),
                "{:?}",
                String::from_utf8_lossy(s)
            );
        }
    }

    #[test]
    fn thesis_cells_are_taken_and_read_as_the_scalar_form_reads_them() {
        for cell in [
            "0.8759947839474834",
            "-0.036876777358695476",
            "0.19621563221263746",
            "33.99667438770339",
            "1234567890123456789",
            "-.1234567890123456789",
            "1.",
            ".5",
            "0",
        ] {
            let s = format!("{cell}, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8");
            // SAFETY: as in `same_digits`.
            if available() {
                assert!(unsafe { plain_digits(s.as_bytes()) }.is_some(), "{cell}");
            }
            same_digits(s.as_bytes());
        }
    }

    proptest::proptest! {
        /// Cells of every shape, as many bytes after them as a row gives,
        /// read as the scalar form reads them wherever the SIMD form
        /// decides.
        #[test]
        fn cells_read_as_the_scalar_form_reads_them(
            cell in "[+-]?[0-9]{0,12}\\.?[0-9]{0,12}|[0-9.eE+-]{0,24}|[0-9]{0,10}[\\r\\x80\\x2f\\x3a\\x00\\xff]?[0-9.]{0,10}",
            after in "[0-9a-z.,eE \\n-]{0,34}",
        ) {
            same_digits(format!("{cell}{after}").as_bytes());
        }

        /// Lines of every shape, and the bytes after them, read as the
        /// scalar form reads them.
        #[test]
        fn lines_read_as_the_scalar_form_reads_them(
            line in "-?[0-9]{0,9}\\.?[0-9]{0,9}|[0-9.eE+-]{0,15}|[0-9]{0,6}[\\r\\x80\\x2f\\x3a\\x00\\xff]?[0-9.]{0,6}",
            after in "[0-9a-z.\\n-]{16}",
        ) {
            same(&line, &after);
        }
    }
}
