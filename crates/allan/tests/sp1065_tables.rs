//! NIST SP 1065 (W. J. Riley, Handbook of Frequency Stability Analysis, 2008),
//! Tables 30 and 31, and AllanTools 2024.6 on the same data.
//!
//! The published values are given to 7 significant digits, so they are
//! checked to 1e-6 relative; the AllanTools values (computed with
//! allantools 2024.6, `data_type="freq"`, rate 1, from the same inputs) to
//! 1e-9 relative.

use allan::{DataType, PhaseSeries, Stat, stats};

/// SP 1065 Table 30 input: Riley's 9-point "NBS14" frequency set.
const NBS14_10: [f64; 9] = [892.0, 809.0, 823.0, 798.0, 671.0, 644.0, 883.0, 903.0, 677.0];

/// SP 1065 Table 31 input: y(i) = n(i)/2147483647 with n0 = 1234567890 and
/// n(i+1) = 16807·n(i) mod 2147483647, i = 0..999.
fn nbs14_1000() -> Vec<f64> {
    let mut n: u64 = 1_234_567_890;
    (0..1000)
        .map(|_| {
            let y = n as f64 / 2_147_483_647.0;
            n = (16_807 * n) % 2_147_483_647;
            y
        })
        .collect()
}

fn dev(stat: Stat, data: &[f64], m: usize) -> (f64, usize) {
    let s = PhaseSeries::new(data, DataType::Freq, 1.0).unwrap();
    let e = stats::compute(stat, &s, m).unwrap_or_else(|| panic!("{stat} at m={m} missing"));
    (e.dev, e.n)
}

fn assert_rel(what: &str, got: f64, want: f64, tol: f64) {
    let rel = ((got - want) / want).abs();
    assert!(
        rel <= tol,
        "{what}: got {got:.12e}, want {want:.12e}, rel {rel:.2e} > {tol:.0e}"
    );
}

#[test]
fn lcg_generator_matches_its_published_check_values() {
    // reference_values.json: n1=395529916 n2=1209410747 n3=633705974
    let y = nbs14_1000();
    let ns: Vec<u64> = y[1..4]
        .iter()
        .map(|v| (v * 2_147_483_647.0).round() as u64)
        .collect();
    assert_eq!(ns, [395_529_916, 1_209_410_747, 633_705_974]);
}

#[test]
fn table_30_ten_point_set() {
    // SP 1065 Table 30, τ = 1 and 2.
    let published: [(Stat, [f64; 2]); 7] = [
        (Stat::Adev, [91.22945, 115.8082]),
        (Stat::Oadev, [91.22945, 85.95287]),
        (Stat::Mdev, [91.22945, 74.78849]),
        (Stat::Tdev, [52.67135, 86.35831]),
        (Stat::Hdev, [70.80607, 116.798]),
        (Stat::Ohdev, [70.80607, 85.61487]),
        (Stat::Totdev, [91.22945, 93.90379]),
    ];
    for (stat, want) in published {
        for (m, w) in [1, 2].into_iter().zip(want) {
            let (got, _) = dev(stat, &NBS14_10, m);
            assert_rel(&format!("{stat} m={m}"), got, w, 1e-6);
        }
    }
}

#[test]
fn table_30_agrees_with_allantools() {
    // allantools 2024.6 on NBS14_10 (reference_values.json,
    // "allantools_2024.06_computed"): (stat, devs at τ=1,2, n at τ=1,2).
    let at: [(Stat, [f64; 2], [usize; 2]); 7] = [
        (Stat::Adev, [91.2294497407, 115.808210705], [8, 3]),
        (Stat::Oadev, [91.2294497407, 85.9528698377], [8, 6]),
        (Stat::Mdev, [91.2294497407, 74.7884934331], [8, 5]),
        (Stat::Tdev, [52.6713473658, 86.3583136318], [8, 5]),
        (Stat::Hdev, [70.8060731859, 116.797991564], [7, 2]),
        (Stat::Ohdev, [70.8060731859, 85.6148716637], [7, 4]),
        (Stat::Totdev, [91.2294497407, 93.9037905252], [8, 8]),
    ];
    for (stat, devs, ns) in at {
        for i in 0..2 {
            let (got, n) = dev(stat, &NBS14_10, i + 1);
            // The JSON holds 12 significant digits.
            assert_rel(&format!("{stat} m={}", i + 1), got, devs[i], 1e-11);
            assert_eq!(n, ns[i], "{stat} n at m={}", i + 1);
        }
    }
}

#[test]
fn table_31_thousand_point_set() {
    // SP 1065 Table 31, τ = 1, 10, 100.
    let published: [(Stat, [f64; 3]); 7] = [
        (Stat::Adev, [0.2922319, 0.09965736, 0.03897804]),
        (Stat::Oadev, [0.2922319, 0.09159953, 0.03241343]),
        (Stat::Mdev, [0.2922319, 0.06172376, 0.02170921]),
        (Stat::Tdev, [0.1687202, 0.3563623, 1.253382]),
        (Stat::Hdev, [0.2943883, 0.1052754, 0.0391086]),
        (Stat::Ohdev, [0.2943883, 0.09581083, 0.03237638]),
        (Stat::Totdev, [0.2922319, 0.09134743, 0.0340653]),
    ];
    let y = nbs14_1000();
    for (stat, want) in published {
        for (m, w) in [1, 10, 100].into_iter().zip(want) {
            let (got, _) = dev(stat, &y, m);
            assert_rel(&format!("{stat} m={m}"), got, w, 1e-6);
        }
    }
}

#[test]
fn table_31_agrees_with_allantools() {
    // allantools 2024.6 on the 1000-point set (reference_values.json,
    // "allantools_2024.06_computed"), τ = 1, 10, 100.
    let at: [(Stat, [f64; 3], [usize; 3]); 7] = [
        (
            Stat::Adev,
            [0.292231878107, 0.0996573606317, 0.038978043308],
            [999, 99, 9],
        ),
        (
            Stat::Oadev,
            [0.292231878107, 0.0915995342012, 0.0324134302606],
            [999, 981, 801],
        ),
        (
            Stat::Mdev,
            [0.292231878107, 0.0617237638245, 0.0217092091369],
            [999, 972, 702],
        ),
        (
            Stat::Tdev,
            [0.168720153491, 0.356362316595, 1.25338177391],
            [999, 972, 702],
        ),
        (
            Stat::Hdev,
            [0.294388329124, 0.105275419401, 0.0391086055975],
            [998, 98, 8],
        ),
        (
            Stat::Ohdev,
            [0.294388329124, 0.0958108317325, 0.0323763825276],
            [998, 971, 701],
        ),
        (
            Stat::Totdev,
            [0.292231878107, 0.091347432617, 0.0340653025218],
            [999, 999, 999],
        ),
    ];
    let y = nbs14_1000();
    for (stat, devs, ns) in at {
        for (i, m) in [1, 10, 100].into_iter().enumerate() {
            let (got, n) = dev(stat, &y, m);
            assert_rel(&format!("{stat} m={m}"), got, devs[i], 1e-11);
            assert_eq!(n, ns[i], "{stat} n at m={m}");
        }
    }
}

#[test]
fn phase_input_gives_the_same_as_rate_input() {
    // REFERENCE.md: rate and the equivalent phase input must agree exactly
    // (to rounding).
    let y = nbs14_1000();
    let rate = PhaseSeries::new(&y, DataType::Freq, 1.0).unwrap();
    let phase = PhaseSeries::new(rate.points(), DataType::Phase, 1.0).unwrap();
    // All but the O(N·m) family, whose modules hold this law themselves.
    for stat in Stat::ALL
        .into_iter()
        .filter(|s| !matches!(s, Stat::Mtotdev | Stat::Ttotdev | Stat::Htotdev | Stat::Theo1))
    {
        for m in [1, 3, 16, 100] {
            let a = stats::compute(stat, &rate, m).unwrap();
            let b = stats::compute(stat, &phase, m).unwrap();
            assert_eq!(a.n, b.n);
            assert_rel(&format!("{stat} m={m}"), b.dev, a.dev, 1e-14);
        }
    }
}

#[test]
fn table_31_total_family() {
    let y = nbs14_1000();
    // allantools 2024.6 (reference_values.json), τ = 1, 10, 100, no bias
    // correction; (stat, devs, ns).
    let at: [(Stat, [f64; 3], [usize; 3]); 3] = [
        (
            Stat::Mtotdev,
            [0.206639142688, 0.0555288597687, 0.0195467512927],
            [999, 972, 702],
        ),
        (
            Stat::Ttotdev,
            [0.119303164656, 0.320596021352, 1.12853221206],
            [999, 972, 702],
        ),
        (
            Stat::Htotdev,
            [0.294388329124, 0.0959072041065, 0.030504478812],
            [998, 971, 701],
        ),
    ];
    for (stat, devs, ns) in at {
        for (i, m) in [1, 10, 100].into_iter().enumerate() {
            let (got, n) = dev(stat, &y, m);
            assert_rel(&format!("{stat} m={m}"), got, devs[i], 1e-11);
            assert_eq!(n, ns[i], "{stat} n at m={m}");
        }
    }
    // Stable32 1.60 (no bias correction), printed to 5 digits.
    for (stat, want) in [
        (Stat::Mtotdev, [0.20664, 0.055529, 0.019547]),
        (Stat::Ttotdev, [0.1193, 0.3206, 1.1285]),
    ] {
        for (m, w) in [1, 10, 100].into_iter().zip(want) {
            let (got, _) = dev(stat, &y, m);
            assert_rel(&format!("Stable32 {stat} m={m}"), got, w, 5e-4);
        }
    }
    // SP 1065 Table 31 prints bias-corrected values: MTOT / 0.73, HTOT / 0.995.
    let corrected = [
        (
            Stat::Mtotdev,
            allan::stats::mtotdev::MTOTVAR_BIAS,
            [0.2418528, 0.06499161, 0.02287774],
        ),
        (
            Stat::Htotdev,
            allan::stats::htotdev::HTOTVAR_BIAS,
            [0.2943883, 0.09614787, 0.03058103],
        ),
    ];
    for (stat, bias, want) in corrected {
        for (m, w) in [1, 10, 100].into_iter().zip(want) {
            let (got, _) = dev(stat, &y, m);
            // HTOT at m = 1 is plain HDEV, which is not corrected.
            let c = if stat == Stat::Htotdev && m == 1 {
                got
            } else {
                got / bias.sqrt()
            };
            assert_rel(&format!("SP 1065 {stat} m={m}"), c, w, 1e-6);
        }
    }
    // Theo1, Stable32 1.60 at averaging factors 10, 100, 1000.
    for (m, w) in [(10, 0.10757), (100, 0.031789), (1000, 0.0050524)] {
        let (got, _) = dev(Stat::Theo1, &y, m);
        assert_rel(&format!("Stable32 theo1 AF={m}"), got, w, 1e-4);
    }
}
