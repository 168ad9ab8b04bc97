//! Laws the prediction and the Monte Carlo's statistics obey for any input.

use proptest::prelude::*;

use ins::drift::{Spread, rms_interval_95};
use ins::schuler;

proptest! {
    /// The Schuler loop only bounds the error: each factor is between 0 and
    /// the flat Earth's 1 (each integrand is below its power-law one:
    /// 1 − cos u ≤ u²/2, u − sin u ≤ u³/6, sin² u ≤ u²).
    #[test]
    fn every_schuler_factor_is_between_zero_and_one(x in 0.0f64..60.0) {
        for (name, f) in [
            ("accel_white", schuler::accel_white as fn(f64) -> f64),
            ("gyro_white", schuler::gyro_white),
            ("gyro_random_walk", schuler::gyro_random_walk),
            ("constant_accel", schuler::constant_accel),
            ("constant_gyro", schuler::constant_gyro),
        ] {
            let v = f(x);
            prop_assert!((-1e-12..=1.0 + 1e-12).contains(&v), "{name}({x}) = {v}");
        }
    }

    /// The interval of the rms holds the rms of the same values.
    #[test]
    fn the_rms_interval_holds_the_rms(mut v in prop::collection::vec(-1e3f64..1e3, 2..200)) {
        let [lo, hi] = rms_interval_95(&v);
        let rms = Spread::of(&mut v).rms;
        prop_assert!(lo <= rms * (1.0 + 1e-12) && rms <= hi * (1.0 + 1e-12), "{lo} {rms} {hi}");
    }
}
