//! Reading numbers from text: plain decimals (`-0.0123456`, what loggers
//! write) in one pass over their digits, everything else (exponents, more
//! than 19 digits, `nan`, `inf`) by `fast_float2`.
//!
//! The plain path is, for up to 15 or 16 digits, Clinger's fast path (W. D. Clinger, "How to read
//! floating point numbers accurately", PLDI 1990): when the digits form an
//! integer w ≤ 2^53 and the decimal point stands k ≤ 22 places from the
//! end, w and 10^k are both exact doubles and the one IEEE division w / 10^k
//! is correctly rounded, so the result is the one `fast_float2` (and
//! `str::parse`) gives, bit for bit. Longer mantissas (up to 19 digits) are
//! divided exactly in integers instead (see `long_quotient`).

/// 10^k, exact in a double for k ≤ 22.
pub(crate) const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18,
    1e19, 1e20, 1e21, 1e22,
];

/// The number at the start of `s` and the bytes it takes, as
/// `fast_float2::parse_partial` reads it; `None` when `s` does not start
/// with one.
#[inline(always)]
pub(crate) fn parse_prefix(s: &[u8]) -> Option<(f64, usize)> {
    match parse_plain(s) {
        Some(r) => Some(r),
        None => parse_general(s),
    }
}

/// Out of line, so that the plain path stays small enough to inline into
/// the row loop.
#[cold]
#[inline(never)]
fn parse_general(s: &[u8]) -> Option<(f64, usize)> {
    match fast_float2::parse_partial::<f64, _>(s) {
        Ok((v, used)) if used > 0 => Some((v, used)),
        _ => None,
    }
}

/// All of `field` as a number (`nan` is one: a gap).
pub(crate) fn parse_field(field: &[u8]) -> Option<f64> {
    match parse_prefix(field) {
        Some((v, used)) if used == field.len() => Some(v),
        _ => None,
    }
}

/// 10^k as an integer, k ≤ 8.
const POW10_INT: [u64; 9] = [
    1,
    10,
    100,
    1_000,
    10_000,
    100_000,
    1_000_000,
    10_000_000,
    100_000_000,
];

/// The run of ASCII digits at the start of an 8-byte word (byte 0 first),
/// at most 8: (its value, its length). Branch-free SWAR: a byte is a digit
/// when neither `b − '0'` nor `b + 0x46` sets its top bit; a borrow from a
/// byte below `'0'` only reaches bytes after it, so the first non-digit is
/// found exactly. The digits are moved to the word's top (zeros in front)
/// and folded pairwise: 2, 4, then 8 digits at a time.
#[inline(always)]
fn digit_run(word: u64) -> (u64, usize) {
    let low = word.wrapping_sub(0x3030_3030_3030_3030);
    let not_digit = (low | word.wrapping_add(0x4646_4646_4646_4646)) & 0x8080_8080_8080_8080;
    let len = (not_digit.trailing_zeros() / 8) as usize;
    if len == 0 {
        return (0, 0);
    }
    let v = low << (8 * (8 - len));
    let v = (v.wrapping_mul(10)).wrapping_add(v >> 8) & 0x00ff_00ff_00ff_00ff;
    let v = (v.wrapping_mul(100)).wrapping_add(v >> 16) & 0x0000_ffff_0000_ffff;
    ((v.wrapping_mul(10000)).wrapping_add(v >> 32) & 0xffff_ffff, len)
}

/// Digits from `s[i..]` folded into `w`: (w, index after the digits,
/// number of digits). Arithmetic wraps; callers refuse more than 19 digits.
#[inline(always)]
fn digits(s: &[u8], mut i: usize, mut w: u64) -> (u64, usize, usize) {
    let start = i;
    while let Some(chunk) = s.get(i..i + 8) {
        let (value, len) = digit_run(u64::from_le_bytes(chunk.try_into().unwrap_or_default()));
        w = w.wrapping_mul(POW10_INT[len]).wrapping_add(value);
        i += len;
        if len < 8 {
            return (w, i, i - start);
        }
    }
    // The last few bytes of the input, one at a time.
    while let Some(&b) = s.get(i) {
        let d = b.wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        w = w.wrapping_mul(10).wrapping_add(u64::from(d));
        i += 1;
    }
    (w, i, i - start)
}

/// A plain decimal that Clinger's fast path reads: its value is
/// `numerator / denominator`, both exact doubles, and the one division
/// (left to the caller, which can do several at once) is correctly
/// rounded. The sign is the numerator's, as IEEE division is symmetric.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Quotient {
    pub numerator: f64,
    pub denominator: f64,
}

/// [`parse_plain`] without its division, for the numbers that need only
/// the fast path (up to 2^53 in their digits); `None` for all others,
/// which `parse_plain` still reads. The reference [`short_quotient`] is
/// checked against.
#[cfg(test)]
fn parse_quotient(s: &[u8]) -> Option<(Quotient, usize)> {
    let (negative, w, frac_digits, used) = plain_digits(s)?;
    if w > 1 << 53 {
        return None;
    }
    let w = exact_f64(w);
    Some((
        Quotient {
            numerator: if negative { -w } else { w },
            denominator: POW10[frac_digits],
        },
        used,
    ))
}

/// The two little-endian 64-bit words of a 16-byte load, its first eight
/// bytes first: the form both the SWAR and the SSE readers of a short line
/// start from.
#[inline(always)]
pub(crate) fn le_words(bytes: &[u8; 16]) -> (u64, u64) {
    let (lo, hi) = bytes.split_at(8);
    let word = |half: &[u8]| u64::from_le_bytes(half.try_into().expect("eight bytes"));
    (word(lo), word(hi))
}

/// A whole line of at most 15 bytes (`len`, its newline at `s[len]`, and
/// `s` holding at least 16 bytes) that is `[-]digits[.digits]`, read from
/// one 16-byte load: the point is found as the first non-digit and taken
/// out by a shift, and the digits, aligned to the top, are folded eight at
/// a time. What it returns is what `parse_quotient` (its test reference) gives for the same
/// line; `None` for any other line (a `+`, an exponent, a carriage
/// return, two points), which the general path then reads. Fifteen digits
/// stay below 2^53, so Clinger's fast path always holds.
#[inline(always)]
pub(crate) fn short_quotient(s: &[u8], len: usize) -> Option<Quotient> {
    const ZEROS: u64 = 0x3030_3030_3030_3030;
    let bytes: &[u8; 16] = s.get(..16)?.try_into().ok()?;
    if len > 15 {
        return None;
    }
    let (mut a, mut b) = le_words(bytes);
    let negative = bytes[0] == b'-';
    if negative {
        a = (a >> 8) | (b << 56);
        b >>= 8;
    }
    let body = len - usize::from(negative);
    let p = first_non_digit(a, b);
    let (digits, frac) = if p >= body {
        (body, 0)
    } else {
        let point = if p < 8 { a >> (8 * p) } else { b >> (8 * (p - 8)) };
        if point as u8 != b'.' {
            return None;
        }
        // Everything after the point moves down one byte (p < body ≤ 15).
        if p < 8 {
            let below = (1u64 << (8 * p)) - 1;
            a = (a & below) | (((a >> 8) | (b << 56)) & !below);
            b >>= 8;
        } else {
            let below = (1u64 << (8 * (p - 8))) - 1;
            b = (b & below) | ((b >> 8) & !below);
        }
        (body - 1, body - 1 - p)
    };
    if digits == 0 || first_non_digit(a, b) < digits {
        return None;
    }
    // Only bytes past the digits can borrow, and the shifts drop them.
    let w = if digits <= 8 {
        fold8(a.wrapping_sub(ZEROS) << (8 * (8 - digits)))
    } else {
        fold8(a.wrapping_sub(ZEROS)) * POW10_INT[digits - 8]
            + fold8(b.wrapping_sub(ZEROS) << (8 * (16 - digits)))
    };
    let w = exact_f64(w);
    Some(Quotient {
        numerator: if negative { -w } else { w },
        denominator: POW10[frac],
    })
}

/// The index of the first byte of the pair `a`, `b` (`a`'s byte 0 first)
/// that is not an ASCII digit, 16 if none; exact for the reason
/// [`digit_run`] gives, word by word.
#[inline(always)]
fn first_non_digit(a: u64, b: u64) -> usize {
    let flags = |w: u64| {
        (w.wrapping_sub(0x3030_3030_3030_3030) | w.wrapping_add(0x4646_4646_4646_4646))
            & 0x8080_8080_8080_8080
    };
    let (a, b) = (flags(a), flags(b));
    if a != 0 {
        (a.trailing_zeros() / 8) as usize
    } else if b != 0 {
        8 + (b.trailing_zeros() / 8) as usize
    } else {
        16
    }
}

/// Eight digit values (0–9), the most significant in byte 0, as one
/// integer: pairs, then fours, then all eight.
#[inline(always)]
fn fold8(v: u64) -> u64 {
    let v = (v.wrapping_mul(10)).wrapping_add(v >> 8) & 0x00ff_00ff_00ff_00ff;
    let v = (v.wrapping_mul(100)).wrapping_add(v >> 16) & 0x0000_ffff_0000_ffff;
    (v.wrapping_mul(10000)).wrapping_add(v >> 32) & 0xffff_ffff
}

/// `w` ≤ 2^53 as a double, exactly. Through `i64`, because baseline
/// x86-64 has no unsigned conversion: `u64 as f64` is five instructions
/// and two constant loads, `i64 as f64` one `cvtsi2sd`; both are exact
/// below 2^53.
#[inline(always)]
fn exact_f64(w: u64) -> f64 {
    debug_assert!(w <= 1 << 53);
    w as i64 as f64
}

/// `[+-]digits[.digits]` (either side of the point may be empty, not
/// both) that Clinger's fast path reads exactly; `None` for anything else.
#[inline(always)]
pub(crate) fn parse_plain(s: &[u8]) -> Option<(f64, usize)> {
    let (negative, w, frac_digits, i) = plain_digits(s)?;
    Some((plain_value(negative, w, frac_digits), i))
}

/// The value of a plain decimal from its sign, its digits as one integer
/// (at most 19 digits) and the number of them after the point.
#[inline(always)]
pub(crate) fn plain_value(negative: bool, w: u64, frac_digits: usize) -> f64 {
    let v = if w <= 1 << 53 {
        exact_f64(w) / POW10[frac_digits]
    } else {
        long_quotient(w, frac_digits)
    };
    if negative { -v } else { v }
}

/// The sign, the digits as one integer, the number of digits after the
/// point, and the bytes taken, of a plain decimal of at most 19 digits.
#[inline(always)]
pub(crate) fn plain_digits(s: &[u8]) -> Option<(bool, u64, usize, usize)> {
    let (negative, i) = match s.first() {
        Some(b'-') => (true, 1),
        Some(b'+') => (false, 1),
        _ => (false, 0),
    };
    let (w, mut i, int_digits) = digits(s, i, 0);
    let mut frac_digits = 0;
    let mut w = w;
    if s.get(i) == Some(&b'.') {
        let (w2, j, n) = digits(s, i + 1, w);
        w = w2;
        i = j;
        frac_digits = n;
    }
    let total = int_digits + frac_digits;
    // An exponent, or too many digits for a u64: the general reader decides.
    if total == 0 || total > 19 || matches!(s.get(i), Some(b'e' | b'E')) {
        return None;
    }
    Some((negative, w, frac_digits, i))
}

/// w / 10^k correctly rounded, for 2^53 < w < 2^64 and k ≤ 19 (a full
/// precision double printed shortest, as loggers write them): one integer
/// division (Möller and Granlund's division by a precomputed reciprocal,
/// tried in its place, was no faster on a thesis log). The numerator is
/// w·2^s with s chosen so that the quotient q has exactly 64 bits; the
/// remainder, as a sticky bit in q's last place
/// (11 places below the rounding position, so it only breaks a tie that
/// is not one), makes the correctly rounded u64 → f64 conversion round the
/// exact quotient. Scaling by 2^−s is exact: the result is ≥ 2^53 / 10^19,
/// far from the subnormals.
#[inline]
fn long_quotient(w: u64, k: usize) -> f64 {
    if k == 0 {
        // An integer: the conversion itself rounds correctly.
        return w as f64;
    }
    let d = POW10_U64[k];
    let bits = |x: u64| 64 - x.leading_zeros() as i32;
    let mut shift = 64 + bits(d) - bits(w);
    if ((u128::from(w) << shift) >> 64) >= u128::from(d) {
        shift -= 1;
    }
    let n = u128::from(w) << shift;
    let q = n / u128::from(d);
    let sticky = u128::from(n != q * u128::from(d));
    // q < 2^64 by the choice of shift.
    let q = (q | sticky) as u64;
    q as f64 * f64::from_bits(((1023 - shift) as u64) << 52)
}

/// 10^k as an integer, k ≤ 19.
const POW10_U64: [u64; 20] = {
    let mut t = [1u64; 20];
    let mut k = 1;
    while k < 20 {
        t[k] = t[k - 1] * 10;
        k += 1;
    }
    t
};

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn reference(s: &[u8]) -> Option<(f64, usize)> {
        match fast_float2::parse_partial::<f64, _>(s) {
            Ok((v, used)) if used > 0 => Some((v, used)),
            _ => None,
        }
    }

    fn same(s: &[u8]) {
        let got = parse_prefix(s);
        let want = reference(s);
        match (got, want) {
            (Some((a, n)), Some((b, m))) => {
                assert_eq!(n, m, "{:?}", String::from_utf8_lossy(s));
                assert!(
                    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                    "{:?}: {a} vs {b}",
                    String::from_utf8_lossy(s)
                );
            }
            (None, None) => {}
            _ => panic!("{:?}: {got:?} vs {want:?}", String::from_utf8_lossy(s)),
        }
        // The undivided form, where it is given, divides to the same bits.
        if let Some((q, used)) = parse_quotient(s) {
            let (v, n) = want.expect("a quotient only for a number");
            assert_eq!(used, n, "{:?}", String::from_utf8_lossy(s));
            assert_eq!(
                (q.numerator / q.denominator).to_bits(),
                v.to_bits(),
                "{:?}",
                String::from_utf8_lossy(s)
            );
        }
    }

    #[test]
    fn edge_cases_read_as_fast_float2_reads_them() {
        for s in [
            "0",
            "-0",
            "-0.0",
            "+1",
            "1.",
            ".5",
            "-.5",
            ".",
            "-",
            "+",
            "",
            "1e5",
            "1.5E-3",
            "1e",
            "nan",
            "-nan",
            "inf",
            "-infinity",
            "0.0123456\n",
            "12345678901234567890",
            "9007199254740993",
            "9007199254740992",
            "0.00000000000000000000001",
            "1234567890123456789",
            "1.2.3",
            "1,5",
            "  1",
            "1 ",
            "0x10",
            "00000000001.5",
            "0.30000000000000004",
            "-0.036011234567890123",
        ] {
            same(s.as_bytes());
        }
    }

    #[test]
    fn long_mantissas_divide_exactly() {
        // 16 to 19 digits with the point anywhere: the integer division
        // path, against fast_float2's Eisel–Lemire and big-number paths.
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let digits = format!("{}", state % 10_000_000_000_000_000_000);
            let point = (state >> 40) as usize % (digits.len() + 1);
            let s = format!("{}.{}", &digits[..point], &digits[point..]);
            same(s.as_bytes());
        }
        // Ties and near-ties: 2^53 + 1 and neighbours over powers of ten.
        for w in [
            9_007_199_254_740_993_u64,
            9_007_199_254_740_995,
            18_014_398_509_481_990,
            u64::MAX / 10,
        ] {
            let digits = w.to_string();
            for k in 0..=digits.len() {
                let (int, frac) = digits.split_at(digits.len() - k);
                same(format!("{int}.{frac}").as_bytes());
            }
        }
    }

    proptest! {
        #[test]
        fn plain_decimals_read_bit_for_bit(int in 0u64..10_000_000_000, frac in 0u64..u64::MAX, width in 0usize..21, neg: bool, tail in "[0-9eE.,\n x+-]{0,3}") {
            let frac = format!("{frac:020}");
            let s = format!("{}{int}.{}{tail}", if neg { "-" } else { "" }, &frac[..width]);
            same(s.as_bytes());
        }

        /// A short line read from its 16-byte load is the line as the
        /// general reader takes it whole, and every plain line of up to
        /// 15 bytes without a `+` is taken.
        #[test]
        fn short_lines_read_as_the_general_reader_reads_them(
            line in "-?[0-9]{0,9}\\.?[0-9]{0,9}|[0-9.eE+-]{0,15}|[0-9]{0,6}[\\r\\x80\\x2f\\x3a]?[0-9.]{0,6}",
            after in "[0-9a-z\\n]{16}",
        ) {
            let len = line.len();
            let s = format!("{line}\n{after}");
            let fast = short_quotient(s.as_bytes(), len);
            let general = parse_quotient(s.as_bytes()).filter(|&(_, used)| used == len);
            match (fast, general) {
                (Some(a), Some((b, _))) => {
                    proptest::prop_assert_eq!(a.numerator.to_bits(), b.numerator.to_bits(), "{:?}", line);
                    proptest::prop_assert_eq!(a.denominator.to_bits(), b.denominator.to_bits(), "{:?}", line);
                }
                (None, None) => {}
                (None, Some(_)) => proptest::prop_assert!(len > 15 || line.starts_with('+'), "{:?} not taken", line),
                (Some(_), None) => proptest::prop_assert!(false, "{:?} taken, but not a whole number", line),
            }
        }

        #[test]
        fn any_bytes_read_as_fast_float2_reads_them(s in "[0-9.eE+-]{0,24}[a-z ,]?") {
            same(s.as_bytes());
        }

        #[test]
        fn every_double_read_back_exactly(x: f64) {
            let mut buf = ryu::Buffer::new();
            same(buf.format(x).as_bytes());
            same(format!("{x:.7}").as_bytes());
        }
    }
}
