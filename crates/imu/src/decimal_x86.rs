//! [`crate::decimal::short_quotient`] in SSSE3 and SSE4.1 registers, for
//! CPUs that have them (checked at run time: the build targets baseline
//! x86-64, which has SSE2 only).
//!
//! The line's 16 bytes are read as one vector. Its digits are found by one
//! unsigned compare, the sign and the point by their byte values; one
//! byte shuffle (`pshufb`), its indices computed from the line's shape,
//! drops the sign and the point and moves the digits to the vector's top
//! with zeros in front; three multiply-adds (`pmaddubsw`, `pmaddwd`, then
//! `pmaddwd` again after `packusdw`) fold them into two eight-digit
//! halves, as in W. Muła's and D. Lemire's SIMD integer parsing (the same
//! steps as `fold8` in the scalar form, sixteen lanes at a time). The
//! scalar form took about 75 instructions a line, its newline search
//! 18 more.

use std::arch::x86_64::{
    __m128i, _mm_cmpeq_epi8, _mm_cvtsi128_si64, _mm_madd_epi16, _mm_maddubs_epi16, _mm_min_epu8,
    _mm_movemask_epi8, _mm_packus_epi32, _mm_set_epi64x, _mm_set1_epi8, _mm_set1_epi16, _mm_set1_epi32,
    _mm_shuffle_epi8, _mm_sub_epi8,
};

use crate::decimal::{POW10, Quotient};

/// Whether this CPU runs [`short_quotient`].
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
    // Pairs, fours, then eights: 10·a + b, 100·ab + cd, 10^4·abcd + efgh.
    let pairs = _mm_maddubs_epi16(aligned, _mm_set1_epi16(0x010a));
    let fours = _mm_madd_epi16(pairs, _mm_set1_epi32(0x0001_0064));
    let packed = _mm_packus_epi32(fours, fours);
    let eights = _mm_madd_epi16(packed, _mm_set1_epi32(0x0001_2710));
    let halves = _mm_cvtsi128_si64(eights) as u64;
    let w = (halves & 0xffff_ffff) * 100_000_000 + (halves >> 32);
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

#[target_feature(enable = "sse2")]
#[inline]
fn load(bytes: &[u8; 16]) -> __m128i {
    let word = |i: usize| {
        i64::from_le_bytes([
            bytes[i],
            bytes[i + 1],
            bytes[i + 2],
            bytes[i + 3],
            bytes[i + 4],
            bytes[i + 5],
            bytes[i + 6],
            bytes[i + 7],
        ])
    };
    _mm_set_epi64x(word(8), word(0))
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

    proptest::proptest! {
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
