//! Every cell a table file holds reads as the standard library's
//! `str::parse::<f64>` reads its text, bit for bit, whichever of the
//! reader's paths (SIMD or scalar, one column or many) takes it.

use std::io::Write;

use imu::table::TableReader;
use proptest::prelude::*;

/// Cells as loggers and scripts write them: shortest round-trip doubles
/// (16 to 19 digits), fixed decimals, integers, signs, exponents.
fn cell() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<f64>()
            .prop_filter("finite", |x| x.is_finite())
            .prop_map(|x| ryu::Buffer::new().format(x).to_string()),
        (-1e3..1e3f64).prop_map(|x| ryu::Buffer::new().format(x).to_string()),
        (-1.0..1.0f64).prop_map(|x| format!("{x:.7}")),
        "-?[0-9]{1,20}",
        "-?[0-9]{0,10}\\.[0-9]{1,12}",
        "[0-9]{1,3}\\.[0-9]{15,18}",
    ]
}

fn check(cols: usize, sep: &str, rows: &[Vec<String>]) -> Result<(), TestCaseError> {
    let mut text = Vec::new();
    for row in rows {
        writeln!(text, "{}", row[..cols].join(sep)).unwrap();
    }
    let mut f = tempfile::NamedTempFile::new().unwrap();
    f.write_all(&text).unwrap();
    let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
    prop_assert_eq!(t.rows(), rows.len());
    for (c, column) in t.columns.iter().enumerate() {
        for (r, &got) in column.iter().enumerate() {
            let want: f64 = rows[r][c].parse().unwrap();
            prop_assert_eq!(
                got.to_bits(),
                want.to_bits(),
                "row {} column {}: {:?}",
                r,
                c,
                rows[r][c]
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    #[test]
    fn cells_read_as_str_parse_reads_them(
        rows in prop::collection::vec(prop::collection::vec(cell(), 7), 1..200),
    ) {
        check(1, "", &rows)?;
        check(7, ", ", &rows)?;
        check(3, "\t", &rows)?;
        check(2, " ", &rows)?;
    }
}
