//! The noise model's acceptance study, small and seeded: the cases of
//! `bench/noise_model_cases.rs` over a few seeds each (the 200-seed run is
//! `bench/noise_model_study.rs`, its results in `bench/README.md`). The
//! thresholds are those the acceptance asks for, read over 8 seeds: a term
//! the model holds must lie within its tolerance, and its 95 % interval
//! must cover the truth, in at least 7 of 8 seeds where it is held. The
//! quantization case, the cheapest, reads coverage over 32 seeds instead:
//! calibrated 95 % intervals miss twice in 8 seeds in 5.7 % of seed sets,
//! which 8 seeds cannot tell from an interval too narrow.

#[path = "../../../bench/noise_model_cases.rs"]
mod cases;
use cases::{CASES, NAMES, outcomes};

const SEEDS: u64 = 8;

fn run(index: usize) -> Vec<[cases::Outcome; 6]> {
    run_seeds(index, SEEDS)
}

fn run_seeds(index: usize, seeds: u64) -> Vec<[cases::Outcome; 6]> {
    let case = &CASES[index];
    println!("{}: {seeds} seeds", case.name);
    (0..seeds)
        .map(|seed| outcomes(case, &cases::model_of(case, 500 + seed)))
        .collect()
}

fn count(results: &[[cases::Outcome; 6]], k: usize, f: impl Fn(&cases::Outcome) -> bool) -> usize {
    results.iter().filter(|r| f(&r[k])).count()
}

#[test]
fn white_noise_and_random_walk_give_no_bias_instability() {
    let r = run(0);
    assert_eq!(count(&r, 2, |o| o.shown), 0, "B reported on N+K");
    assert_eq!(count(&r, 1, |o| o.within), SEEDS as usize, "N");
    let k_held = count(&r, 3, |o| o.shown);
    // Weighed with the correlations of the points, the last octave points
    // of the walk count as the one piece of evidence they are, and a
    // Gauss–Markov term no longer takes K's place (bench/README.md).
    assert!(k_held >= 7, "K held in {k_held} of {SEEDS}");
    assert!(count(&r, 3, |o| o.within) + 1 >= k_held, "K within 25 %");
    assert!(count(&r, 3, |o| o.covered) + 1 >= k_held, "K covered");
}

#[test]
fn white_noise_flicker_and_random_walk_are_all_found() {
    let r = run(1);
    for k in [1, 2] {
        assert_eq!(count(&r, k, |o| o.shown), SEEDS as usize, "{} held", NAMES[k]);
        assert!(count(&r, k, |o| o.within) >= 7, "{} within tolerance", NAMES[k]);
    }
    let k_held = count(&r, 3, |o| o.shown);
    assert!(k_held >= 7, "K held in {k_held} of {SEEDS}");
    assert!(count(&r, 3, |o| o.within) + 1 >= k_held, "K within 40 %");
    // The flicker holds its plateau down to τ0, so N is not read low
    // (it was, by 2 %, with an interval of ±1 %).
    assert!(count(&r, 1, |o| o.covered) >= 7, "N covered");
    let mut errors: Vec<f64> = r.iter().filter_map(|o| o[1].error).collect();
    errors.sort_by(f64::total_cmp);
    let median = errors[errors.len() / 2];
    assert!(median.abs() < 5e-3, "N's median error {median}");
}

#[test]
fn a_gauss_markov_term_is_found_with_its_correlation_time() {
    let r = run(2);
    for k in [4, 5] {
        assert!(count(&r, k, |o| o.shown) >= 7, "{} held", NAMES[k]);
        assert!(count(&r, k, |o| o.within) >= 7, "{} within 20 %", NAMES[k]);
        assert!(count(&r, k, |o| o.covered) >= 7, "{} covered", NAMES[k]);
    }
    assert_eq!(count(&r, 3, |o| o.shown), 0, "K beside the Gauss–Markov term");
}

#[test]
fn quantization_is_recovered() {
    let r = run_seeds(3, 32);
    assert!(count(&r, 0, |o| o.within) >= 28, "Q within 10 %");
    // A calibrated 95 % interval misses 6 or more of 32 in 0.5 % of seed
    // sets, one covering 90 % (the acceptance's lower end) in 9 %, one
    // covering 80 % in 64 % (binomial tails).
    for k in [0, 1] {
        let held = count(&r, k, |o| o.shown);
        let covered = count(&r, k, |o| o.covered);
        assert!(covered + 5 >= held, "{} covered in {covered} of {held}", NAMES[k]);
    }
}
