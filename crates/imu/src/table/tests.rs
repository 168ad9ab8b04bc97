use super::*;
use std::io::Write;

/// Every column of a file holding `content`.
fn read_all(content: &[u8]) -> Result<Table, ReadError> {
    let f = file(content);
    TableReader::open(f.path()).unwrap().read(None)
}

fn file(content: &[u8]) -> tempfile::NamedTempFile {
    let mut f = tempfile::NamedTempFile::new().unwrap();
    f.write_all(content).unwrap();
    f
}

#[test]
fn reads_headerless_whitespace_columns() {
    let t = read_all(b"# x\n1 2\n\n3\t4\n# mid comment\n5 6\n").unwrap();
    assert_eq!(t.names, ["col1", "col2"]);
    assert!(!t.has_header);
    assert_eq!(t.columns, vec![vec![1.0, 3.0, 5.0], vec![2.0, 4.0, 6.0]]);
    assert_eq!(t.comments, ["x"]);
    assert_eq!(t.lines, 6);
    let lines: Vec<u64> = (0..3).map(|r| t.line_of_row(r)).collect();
    assert_eq!(lines, [2, 4, 6]);
}

#[test]
fn reads_thesis_style_header_and_selects() {
    let f = file(b"a[m/^2], b[rad/s],c\r\n1.5, -2e-3, 7\r\n2.5,nan,8\r\n");
    let r = TableReader::open(f.path()).unwrap();
    assert_eq!(r.names(), ["a[m/^2]", "b[rad/s]", "c"]);
    let idx = r.column_index("B[RAD/S]").unwrap();
    assert_eq!(r.column_index("3").unwrap(), 2);
    assert_eq!(r.column_index("a").unwrap(), 0);
    assert!(r.column_index("zz").is_err());
    let t = r.read(Some(&[idx])).unwrap();
    assert_eq!(t.columns[0][0], -2e-3);
    assert!(t.columns[0][1].is_nan());
}

#[test]
fn errors_name_line_and_column() {
    let e = read_all(b"a,b\n1,2\n3,x7\n").unwrap_err();
    assert_eq!((e.line, e.column), (Some(3), Some(2)));
    assert!(e.to_string().contains(":3: column 2: cannot read 'x7'"), "{e}");

    let e = read_all(b"1,2\n3\n").unwrap_err();
    assert_eq!(e.line, Some(2));
    assert!(matches!(
        e.kind,
        ReadErrorKind::FieldCount {
            expected: 2,
            found: 1
        }
    ));

    let t = read_all(b"1,2\n3,4\n5").unwrap();
    assert_eq!(t.columns[0], vec![1.0, 3.0]);
    assert_eq!(t.problems.len(), 1);
    assert_eq!(t.problems[0].line, Some(3));
    assert!(matches!(
        t.problems[0].kind,
        ReadErrorKind::TruncatedLastLine { .. }
    ));
    let t = read_all(b"1,2\n3,4\n5,-").unwrap();
    assert_eq!((t.rows(), t.problems.len()), (2, 1));

    let f = file(b"");
    let e = TableReader::open(f.path()).unwrap_err();
    assert!(matches!(e.kind, ReadErrorKind::NoData));
    let e = read_all(b"# only\nname\n").unwrap_err();
    assert!(matches!(e.kind, ReadErrorKind::NoData));
}

#[test]
fn one_column_rows_leave_the_quick_loop_where_they_must() {
    // Plain decimals run through the one-column loop; an exponent, a
    // leading blank, CRLF, a blank line and a comment each leave it and
    // come back; the bad cell is still named by its line.
    let t = read_all(b"1.5\n2e-3\n\n# c\n 3\n4\r\n-0.25\n5\n").unwrap();
    assert_eq!(t.columns[0], vec![1.5, 2e-3, 3.0, 4.0, -0.25, 5.0]);
    assert_eq!(t.line_of_row(4), 7);
    let e = read_all(b"1.5\n2.5\n3.5x\n4\n").unwrap_err();
    assert_eq!((e.line, e.column), (Some(3), Some(1)));
    let t = read_all(b"1.5\n2.5\n3.5").unwrap();
    assert_eq!(
        (t.columns[0].clone(), t.problems[0].line),
        (vec![1.5, 2.5], Some(3))
    );
}

#[test]
fn odd_but_valid_cells_take_the_careful_path() {
    // A text column that is not selected, tabs with empty-free cells,
    // signs, exponents and spaces around separators.
    let f = file(b"time\tv\n2026-01-01T00:00:00\t+1.5e-3\nt2\t -2 \n");
    let r = TableReader::open(f.path()).unwrap();
    let t = r.read(Some(&[1])).unwrap();
    assert_eq!(t.columns[0], vec![1.5e-3, -2.0]);
    let e = read_all(b"1  2\n3 4e\n").unwrap_err();
    assert_eq!((e.line, e.column), (Some(2), Some(2)));
    let e = read_all(b"1,2\n3,,\n").unwrap_err();
    assert!(
        matches!(
            e.kind,
            ReadErrorKind::FieldCount {
                expected: 2,
                found: 3
            }
        ),
        "{e}"
    );
}

#[test]
fn line_of_row_counts_the_skipped_lines_before_it() {
    // Rows and comment lines interleaved in a known pattern: line L is a
    // comment when L % 3 == 0 or L % 7 == 0 (from line 3 on).
    let body_start_line = 2;
    let skipped: Vec<u64> = (3..400).filter(|l| l % 3 == 0 || l % 7 == 0).collect();
    let row_lines: Vec<u64> = (2..400).filter(|l| !skipped.contains(l)).collect();
    let t = Table {
        path: PathBuf::new(),
        has_header: true,
        comments: Vec::new(),
        names: Vec::new(),
        columns: Vec::new(),
        lines: 400,
        problems: Vec::new(),
        body_start_line,
        skipped_lines: {
            let mut s = SkippedLines::default();
            skipped.iter().for_each(|&l| s.push(l));
            s
        },
        trailer: None,
    };
    for (row, &line) in row_lines.iter().enumerate() {
        assert_eq!(t.line_of_row(row), line, "row {row}");
    }
}

#[test]
fn skipped_lines_become_gaps_and_are_reported() {
    let f = file(b"a,b\n1,2\n3\n5,x\n7,8\n");
    let policy = ReadPolicy { skip_bad_lines: true };
    let t = TableReader::open(f.path())
        .unwrap()
        .read_with(None, &policy)
        .unwrap();
    assert_eq!(t.rows(), 4);
    assert!(t.columns[0][1].is_nan() && t.columns[1][2].is_nan());
    assert_eq!(t.columns[1][3], 8.0);
    let lines: Vec<_> = t.problems.iter().map(|p| (p.line, p.column)).collect();
    assert_eq!(lines, [(Some(3), None), (Some(4), Some(2))]);
}

#[test]
fn a_last_line_without_newline_is_cut_even_when_it_reads() {
    // "3.14159" cut after "3.1" reads as a shorter number: the missing
    // newline is the only sign, and it is enough.
    for content in [&b"a,b\n1,2\n3,4"[..], b"a,b\n1,2\n3.1,4.1", b"1,2"] {
        let f = file(content);
        let r = TableReader::open(f.path()).unwrap().read(None);
        let text = String::from_utf8_lossy(content);
        let lines = text.lines().count() as u64;
        match r {
            Ok(t) => {
                assert_eq!(t.rows() as u64, lines - 2, "{text}");
                assert_eq!(t.problems.len(), 1);
                assert_eq!(t.problems[0].line, Some(lines));
                assert!(matches!(
                    t.problems[0].kind,
                    ReadErrorKind::TruncatedLastLine {
                        expected: 2,
                        found: 2
                    }
                ));
            }
            // The only row was the cut one.
            Err(e) => assert!(matches!(e.kind, ReadErrorKind::NoData) && lines == 1, "{e}"),
        }
    }
    // A comment or a blank last line without newline loses nothing.
    let t = read_all(b"1,2\n3,4\n# end").unwrap();
    assert_eq!((t.rows(), t.problems.len()), (2, 0));
}

#[test]
fn large_file_keeps_order_and_line_numbers() {
    let mut content = Vec::new();
    let rows = 300_000;
    for i in 0..rows {
        writeln!(content, "{i}, {}", i as f64 * 0.5).unwrap();
    }
    writeln!(content, "1, oops").unwrap();
    let f = file(&content);
    let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
    assert_eq!(e.line, Some(rows as u64 + 1));
    content.truncate(content.len() - "1, oops\n".len());
    let f = file(&content);
    let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
    assert_eq!(t.rows(), rows);
    assert!(t.columns[0].iter().enumerate().all(|(i, &v)| v == i as f64));
    // Cut after many blocks: the last row alone is dropped, at its line.
    content.pop();
    let f = file(&content);
    let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
    assert_eq!(t.rows(), rows - 1);
    assert_eq!(t.problems.len(), 1);
    assert_eq!(t.problems[0].line, Some(rows as u64));
}

#[test]
fn reads_gzip_by_content() {
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    gz.write_all(b"v\n1\n2\n").unwrap();
    let f = file(&gz.finish().unwrap());
    let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
    assert_eq!(t.columns[0], vec![1.0, 2.0]);
}

fn gzip(content: &[u8]) -> Vec<u8> {
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    gz.write_all(content).unwrap();
    gz.finish().unwrap()
}

#[test]
fn gzip_members_and_zero_padding_read_as_gzip_reads_them() {
    let mut bytes = gzip(b"v\n1\n");
    bytes.extend(gzip(b"2\n"));
    bytes.extend([0u8; 700]);
    let f = file(&bytes);
    let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
    assert_eq!(t.columns[0], vec![1.0, 2.0]);
    // gzip -d cross-checks the same bytes when it is installed.
    if let Ok(out) = std::process::Command::new("gzip")
        .arg("-dc")
        .arg(f.path())
        .output()
    {
        assert!(out.status.success());
        assert_eq!(out.stdout, b"v\n1\n2\n");
    }
    let mut garbage = gzip(b"v\n1\n");
    garbage.extend(b"\0\0junk");
    let f = file(&garbage);
    let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
    assert!(e.to_string().contains("zero padding"), "{e}");
}

#[test]
fn comments_before_the_first_row_are_bounded() {
    let mut content = "#\n".repeat(MAX_HEADER_COMMENTS).into_bytes();
    content.extend(b"v\n1\n");
    let f = file(&content);
    assert_eq!(
        TableReader::open(f.path()).unwrap().comments().len(),
        MAX_HEADER_COMMENTS
    );
    let mut content = "#\n".repeat(MAX_HEADER_COMMENTS + 1).into_bytes();
    content.extend(b"v\n1\n");
    let f = file(&content);
    let e = TableReader::open(f.path()).unwrap_err();
    assert!(matches!(e.kind, ReadErrorKind::TooManyComments { .. }), "{e}");
    assert_eq!(e.line, Some(MAX_HEADER_COMMENTS as u64 + 1));
}

#[test]
fn cr_only_line_endings_are_refused_by_name() {
    let f = file(b"a,b\r1,2\r3,4\r");
    let e = TableReader::open(f.path()).unwrap_err();
    assert!(matches!(e.kind, ReadErrorKind::CrLineEndings), "{e}");
    assert_eq!(e.line, Some(1));
    // From the second line on, short or beyond the line limit.
    let mut long = b"a,b\n".to_vec();
    long.extend("1,2\r".repeat(MAX_LINE_BYTES / 4 + 10).bytes());
    for content in [&b"a,b\n1,2\r3,4\r"[..], &long] {
        let f = file(content);
        let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
        assert!(matches!(e.kind, ReadErrorKind::CrLineEndings), "{e}");
        assert_eq!(e.line, Some(2));
    }
}

#[test]
fn duplicate_header_names_are_refused() {
    let f = file(b"gyro_x,gyro_x,temp\n1,2,3\n");
    let e = TableReader::open(f.path()).unwrap_err();
    assert!(
        matches!(&e.kind, ReadErrorKind::DuplicateColumn { name, first: 1, second: 2 } if name == "gyro_x"),
        "{e}"
    );
}

#[test]
fn an_endless_line_stops_at_the_limit() {
    // NUL bytes with no newline, first in the file and after rows.
    let nul = vec![0u8; MAX_LINE_BYTES + 10];
    let f = file(&nul);
    let e = TableReader::open(f.path()).unwrap_err();
    assert!(matches!(e.kind, ReadErrorKind::LineTooLong { .. }), "{e}");
    let mut content = b"a\n1\n2\n".to_vec();
    content.extend(&nul);
    for bytes in [content.clone(), gzip(&content)] {
        let f = file(&bytes);
        let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
        assert!(matches!(e.kind, ReadErrorKind::LineTooLong { .. }), "{e}");
        assert_eq!(e.line, Some(4));
    }
}

#[test]
fn blank_lines_cost_no_memory_per_line() {
    let mut content = b"a\n1\n".to_vec();
    content.extend(std::iter::repeat_n(b'\n', 3 * BLOCK_BYTES + 17));
    content.extend(b"2\n");
    let f = file(&gzip(&content));
    let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
    assert_eq!(t.columns[0], vec![1.0, 2.0]);
    assert_eq!(t.skipped_lines.runs.len(), 1);
    assert_eq!(t.skipped_lines.len(), 3 * BLOCK_BYTES as u64 + 17);
    assert_eq!(t.line_of_row(1), 3 * BLOCK_BYTES as u64 + 17 + 3);
    assert!(t.skipped_lines.contains(3) && !t.skipped_lines.contains(2));
}

#[test]
fn the_trailer_comes_from_the_stream_tail_of_any_input() {
    let mut content = b"v\n".to_vec();
    for i in 0..20_000 {
        writeln!(content, "{i}").unwrap();
    }
    writeln!(content, "# trailer: samples=20000 gaps=0").unwrap();
    let want = Some("samples=20000 gaps=0".to_string());
    for bytes in [content.clone(), gzip(&content)] {
        let f = file(&bytes);
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!(t.trailer, want);
    }
    // A FIFO is read once: every value arrives, the trailer too.
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        return;
    }
    let writer = {
        let (fifo, content) = (fifo.clone(), content.clone());
        std::thread::spawn(move || std::fs::write(fifo, content).unwrap())
    };
    let t = TableReader::open(&fifo).unwrap().read(None).unwrap();
    writer.join().unwrap();
    assert_eq!(t.trailer, want);
    assert_eq!(t.rows(), 20_000);
    assert!(t.columns[0].iter().enumerate().all(|(i, &v)| v == i as f64));
}

#[test]
fn columns_past_their_memory_limit_stop_at_the_line_that_crosses_it() {
    let mut content = b"a,b\n".to_vec();
    for i in 0..200_000 {
        writeln!(content, "{i},{i}").unwrap();
    }
    let limit = 2 * 8 * 100_000;
    for bytes in [content.clone(), gzip(&content)] {
        let f = file(&bytes);
        let r = TableReader::open(f.path()).unwrap();
        let e = r
            .read_within(None, &ReadPolicy::default(), Some(limit))
            .unwrap_err();
        assert!(
            matches!(e.kind, ReadErrorKind::TooLarge { limit_mib: 1, .. }),
            "{e}"
        );
        // Within a block of the 100 000th row (line 100 001).
        let line = e.line.unwrap();
        assert!(line > 50_000 && line <= 100_001 + 131_072, "{line}");
        // One column of the two fits.
        let r = TableReader::open(f.path()).unwrap();
        let t = r
            .read_within(Some(&[1]), &ReadPolicy::default(), Some(limit))
            .unwrap();
        assert_eq!(t.rows(), 200_000);
    }
}

#[test]
fn short_bad_lines_in_a_wide_table_are_gaps_held_to_the_budget() {
    // 2,000 columns, then a million two-byte bad lines: each a gap row of
    // 2,000 NaN (16 kB), 16 GB of gaps from 2 MB of text, which one block
    // would hold before its merge. Skipped, they are refused at the budget
    // before more than a share of it is held.
    let mut content = (1..=2000).map(|i| format!("c{i}")).collect::<Vec<_>>().join(",");
    content.push('\n');
    content.push_str(&vec!["0"; 2000].join(","));
    content.push('\n');
    content.push_str(&"x\n".repeat(1_000_000));
    let f = file(content.as_bytes());
    let limit = 64 << 20;
    let r = TableReader::open(f.path()).unwrap();
    let e = r
        .read_within(None, &ReadPolicy { skip_bad_lines: true }, Some(limit))
        .unwrap_err();
    assert!(
        matches!(e.kind, ReadErrorKind::TooLarge { limit_mib: 64, .. }),
        "{e}"
    );
    // Where the gaps fit, they are read as gaps.
    let mut few = (1..=2000).map(|i| format!("c{i}")).collect::<Vec<_>>().join(",");
    few.push('\n');
    few.push_str(&"x\n".repeat(10));
    few.push_str(&vec!["1"; 2000].join(","));
    few.push('\n');
    let f = file(few.as_bytes());
    let t = TableReader::open(f.path())
        .unwrap()
        .read_within(None, &ReadPolicy { skip_bad_lines: true }, Some(limit))
        .unwrap();
    assert_eq!(t.rows(), 11);
    assert!(t.columns[0][..10].iter().all(|v| v.is_nan()) && t.columns[0][10] == 1.0);
}

#[test]
fn blocks_of_comments_alone_hold_no_budget() {
    let mut content = b"a\n".to_vec();
    content.extend(
        "# a long comment line, of which there are many\n"
            .repeat(3 * BLOCK_BYTES / 40)
            .bytes(),
    );
    content.extend(b"1\n2\n");
    let f = file(&content);
    let r = TableReader::open(f.path()).unwrap();
    // A block's column reserves a megabyte; four blocks would not fit.
    let t = r
        .read_within(None, &ReadPolicy::default(), Some(3 << 19))
        .unwrap();
    assert_eq!(t.columns[0], vec![1.0, 2.0]);
}

#[test]
fn a_terminal_banner_and_boot_lines_are_skipped_and_reported() {
    let t = read_all(
        b"=~=~=~= PuTTY log 2026.05.08 15:02:51 =~=~=~=\nBMI270 Chip ID Detected: 0x24\n\
          # rate: 50\n1.5,2,3\n2.5,3,4\n",
    )
    .unwrap();
    assert_eq!(t.names, ["col1", "col2", "col3"]);
    assert_eq!(t.columns[0], [1.5, 2.5]);
    assert_eq!(t.comments, ["rate: 50"]);
    assert_eq!(t.body_start_line, 4);
    assert_eq!((t.line_of_row(0), t.line_of_row(1)), (4, 5));
    assert_eq!(t.problems.len(), 1);
    assert_eq!(t.problems[0].line, Some(1));
    assert!(
        matches!(&t.problems[0].kind, ReadErrorKind::Preamble { lines: 2, first } if first.contains("PuTTY log")),
        "{:?}",
        t.problems[0]
    );
    // A header after the banner is the header.
    let t = read_all(b"Resetting sensor...\nt,gx\n1,2\n3,4\n").unwrap();
    assert_eq!(
        (t.names.clone(), t.has_header),
        (vec!["t".to_string(), "gx".to_string()], true)
    );
    assert_eq!(t.problems.len(), 1);
    // A file without one reads as before.
    let t = read_all(b"t,gx\n1,2\n").unwrap();
    assert!(t.has_header && t.problems.is_empty());
}

#[test]
fn the_rows_width_is_the_most_common_one() {
    // The capture began inside a line: its first row is short.
    let t = read_all(b"banner\n0,1,2\n1,2,3,4\n5,6,7,8\n9,10,11,12\n").unwrap();
    assert_eq!(t.names.len(), 4);
    assert_eq!(t.columns[0], [1.0, 5.0, 9.0]);
    assert_eq!(t.line_of_row(0), 3);
    let cut: Vec<_> = t.problems.iter().map(|p| (p.line, p.kind.to_string())).collect();
    assert_eq!(cut.len(), 2);
    assert_eq!(cut[1].0, Some(2));
    assert!(cut[1].1.contains("3 fields where the rows have 4"), "{cut:?}");
    // Without a banner too.
    let t = read_all(b"7\n1,2\n3,4\n").unwrap();
    assert_eq!((t.columns[0].clone(), t.problems.len()), (vec![1.0, 3.0], 1));
    // A short row later is still an error, at its line.
    let e = read_all(b"1,2\n3,4\n5\n6,7\n").unwrap_err();
    assert_eq!(e.line, Some(3));
    // A header of another width than the rows is still refused.
    let e = read_all(b"a,b,c\n1,2\n3,4\n").unwrap_err();
    assert!(
        matches!(
            e.kind,
            ReadErrorKind::FieldCount {
                expected: 3,
                found: 2
            }
        ),
        "{e}"
    );
}

#[test]
fn rows_read_ahead_are_read_once_across_the_look_ahead() {
    // More than the look-ahead of rows: every row is read once, in order.
    let mut body = b"banner line\n".to_vec();
    let rows = 3 * super::preamble::AHEAD_BYTES / 10;
    for i in 0..rows {
        body.extend_from_slice(format!("{i},{}\n", i % 7).as_bytes());
    }
    let t = read_all(&body).unwrap();
    assert_eq!(t.rows(), rows);
    assert!(t.columns[0].iter().enumerate().all(|(i, &v)| v == i as f64));
    assert_eq!(t.line_of_row(rows - 1), rows as u64 + 1);
}

#[test]
fn a_gzip_of_long_rows_is_held_to_the_streams_cap_and_the_same_rows_plain_read() {
    // 500 columns of zeros: 1,000 bytes of text a row, 4,000 of columns;
    // 4,000 rows are 16 MB of columns from 4 MB of text, which gzip makes
    // a few kilobytes. A stream's cap (8 MiB here) is the same on every
    // machine; the plain file's own size bounds it at 32 MB.
    let row = format!("{}\n", vec!["0"; 500].join(","));
    let content = row.repeat(4000);
    let cap = 8 << 20;
    let read = |bytes: &[u8]| {
        let f = file(bytes);
        let r = TableReader::open(f.path()).unwrap();
        let limit = super::budget::Limit::of_input_capped(r.file_bytes, &r.seen, cap);
        r.read_limited(None, &ReadPolicy::default(), limit)
    };
    let e = read(&gzip(content.as_bytes())).unwrap_err();
    assert!(
        matches!(
            e.kind,
            ReadErrorKind::TooLarge {
                limit_mib: 8,
                bound: crate::error::LimitBound::StreamCap,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("compressed or piped input"), "{e}");
    let t = read(content.as_bytes()).unwrap();
    assert_eq!((t.rows(), t.columns.len()), (4000, 500));
}
