//! The Schuler loop of one horizontal channel, in closed form.
//!
//! On a navigator that carries the transport rate (a latitude given), a
//! velocity error δv tilts the level frame by δv/R, and the tilt feeds back
//! through gravity: the single-channel error model of a static system
//! (Titterton & Weston, *Strapdown Inertial Navigation Technology*, 2nd
//! ed., ch. 12; Groves, *Principles of GNSS, Inertial, and
//! Multisensor Integrated Navigation Systems*, 2nd ed., ch. 14, "Schuler
//! oscillation"):
//!
//! ```text
//! δẋ = δv,   δv̇ = −g·φ + δf,   φ̇ = δv/R + δω,   ω_s = √(g/R)
//! ```
//!
//! with δf the specific-force error along the channel and δω the gyro error
//! about the axis that tilts it. Its impulse responses on the position are
//! sin(ω_s·τ)/ω_s from δf and −R·(1 − cos ω_s·τ) from δω; every term below
//! is an integral of them:
//!
//! | input | position at t | its factor F(x), x = ω_s·t |
//! | --- | --- | --- |
//! | white δf, N_a | σ² = N_a²·t³/3 · F | 3·(x/2 − sin 2x/4)/x³ |
//! | white δω, N_g | σ² = g²·N_g²·t⁵/20 · F | 20·(3x/2 − 2 sin x + sin 2x/4)/x⁵ |
//! | random walk of δf, K_a | σ² = K_a²·t⁵/20 · F | the same as white δω |
//! | random walk of δω, K_g | σ² = g²·K_g²·t⁷/252 · F | 252·∫₀ˣ(u − sin u)² du / x⁷ |
//! | constant δf (or initial tilt) b | b·t²/2 · F | 2·(1 − cos x)/x² |
//! | constant δω, ε | g·ε·t³/6 · F | 6·(x − sin x)/x³ |
//!
//! Each F is 1 at x = 0, which is the flat-Earth form (no loop), and falls
//! below it by at most x²/5 to first order; at x = 1 (t = 1/ω_s, 13.4 min)
//! the flat-Earth variances of the white terms are already 13 % (gyro) and
//! 22 % (specific force) too high.
//!
//! The functions cancel catastrophically near x = 0 (the white gyro term's
//! sum is of size x⁵/20 from terms of size x): below [`SERIES_BELOW`] they
//! are summed as their Taylor series, above it in closed form.

/// Below this x the factors are summed as series.
const SERIES_BELOW: f64 = 1.0;

/// Terms summed of each series (below x = 1 the 20th is below 1e-40).
const SERIES_TERMS: i32 = 20;

/// The mean radius of the Earth, m (IUGG R₁ = (2a + b)/3): the radius of
/// the Schuler loop when no latitude is given, only to say where the flat
/// Earth stops holding.
pub const MEAN_EARTH_RADIUS: f64 = 6_371_008.8;

/// ω_s = √(g/R), rad/s.
pub fn schuler_rate(gravity: f64, radius: f64) -> f64 {
    (gravity / radius).sqrt()
}

/// The time past which a navigation without the Schuler loop (a flat,
/// non-rotating Earth) parts from one with it: 1/ω_s with the mean radius
/// and standard gravity, 806 s. There the flat-Earth variances of the
/// white terms are 13–22 % too high, and the gap grows as x².
pub fn flat_earth_limit_s() -> f64 {
    1.0 / schuler_rate(earth::STANDARD_GRAVITY, MEAN_EARTH_RADIUS)
}

/// Σ_{k ≥ k0} sign(k)·c(k)·x^{2(k−k0)} / d(k)!, the series of a factor with
/// its leading power divided out; `d` gives the factorial's order.
fn series(x: f64, k0: i32, c: impl Fn(i32) -> f64, d: impl Fn(i32) -> i32) -> f64 {
    let x2 = x * x;
    let mut sum = 0.0;
    let mut power = 1.0;
    for k in k0..k0 + SERIES_TERMS {
        let fact: f64 = (1..=d(k)).map(f64::from).product();
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        sum += sign * c(k) * power / fact;
        power *= x2;
    }
    sum
}

/// Factor of the white specific-force term's variance.
pub fn accel_white(x: f64) -> f64 {
    if x.abs() < SERIES_BELOW {
        // x/2 − sin 2x/4 = Σ_{k≥1} (−1)^{k+1}·2^{2k−1}·x^{2k+1}/(2k+1)!
        -3.0 * series(x, 1, |k| 2f64.powi(2 * k - 1), |k| 2 * k + 1)
    } else {
        3.0 * (x / 2.0 - (2.0 * x).sin() / 4.0) / x.powi(3)
    }
}

/// Factor of the white gyro term's variance, and of the random walk of the
/// specific force.
pub fn gyro_white(x: f64) -> f64 {
    if x.abs() < SERIES_BELOW {
        // 3x/2 − 2 sin x + sin 2x/4 = Σ_{k≥2} (−1)^k·(2^{2k−1} − 2)·x^{2k+1}/(2k+1)!
        20.0 * series(x, 2, |k| 2f64.powi(2 * k - 1) - 2.0, |k| 2 * k + 1)
    } else {
        20.0 * (1.5 * x - 2.0 * x.sin() + (2.0 * x).sin() / 4.0) / x.powi(5)
    }
}

/// Factor of the gyro random walk's variance.
pub fn gyro_random_walk(x: f64) -> f64 {
    if x.abs() < SERIES_BELOW {
        // ∫₀ˣ(u − sin u)² du = x³/3 − 2(sin x − x cos x) + x/2 − sin 2x/4
        //                    = Σ_{k≥3} (−1)^k·(4k − 2^{2k−1})·x^{2k+1}/(2k+1)!
        252.0 * series(x, 3, |k| 4.0 * f64::from(k) - 2f64.powi(2 * k - 1), |k| 2 * k + 1)
    } else {
        let integral = x.powi(3) / 3.0 - 2.0 * (x.sin() - x * x.cos()) + x / 2.0 - (2.0 * x).sin() / 4.0;
        252.0 * integral / x.powi(7)
    }
}

/// Factor of the position from a constant specific-force error or an
/// initial tilt (an amplitude, not a variance).
pub fn constant_accel(x: f64) -> f64 {
    if x.abs() < SERIES_BELOW {
        // 1 − cos x = Σ_{k≥1} (−1)^{k+1}·x^{2k}/(2k)!
        -2.0 * series(x, 1, |_| 1.0, |k| 2 * k)
    } else {
        2.0 * (1.0 - x.cos()) / (x * x)
    }
}

/// Factor of the position from a constant gyro error (an amplitude).
pub fn constant_gyro(x: f64) -> f64 {
    if x.abs() < SERIES_BELOW {
        // x − sin x = Σ_{k≥1} (−1)^{k+1}·x^{2k+1}/(2k+1)!
        -6.0 * series(x, 1, |_| 1.0, |k| 2 * k + 1)
    } else {
        6.0 * (x - x.sin()) / x.powi(3)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Factor = fn(f64) -> f64;
    const ALL: [(&str, Factor); 5] = [
        ("accel_white", accel_white),
        ("gyro_white", gyro_white),
        ("gyro_random_walk", gyro_random_walk),
        ("constant_accel", constant_accel),
        ("constant_gyro", constant_gyro),
    ];

    #[test]
    fn every_factor_is_one_without_the_loop() {
        for (name, f) in ALL {
            assert!((f(0.0) - 1.0).abs() < 1e-15, "{name}: {}", f(0.0));
            assert!((f(1e-4) - 1.0).abs() < 1e-8, "{name}: {}", f(1e-4));
        }
    }

    #[test]
    fn series_and_closed_form_meet_at_the_switch() {
        // Both sides of x = 1 (the closed form loses at most two digits there).
        for (name, f) in ALL {
            let below = f(SERIES_BELOW - 1e-12);
            let above = f(SERIES_BELOW + 1e-12);
            assert!(
                (below / above - 1.0).abs() < 1e-12,
                "{name}: {below} against {above}"
            );
        }
    }

    #[test]
    fn factors_take_their_periodic_values() {
        use std::f64::consts::PI;
        // At x = 2π the specific-force loop has come round: 1 − cos x = 0.
        assert!(constant_accel(2.0 * PI).abs() < 1e-15);
        // 6·(2π − 0)/(2π)³ and 3·π/(2π)³, by hand.
        assert!((constant_gyro(2.0 * PI) - 6.0 / (4.0 * PI * PI)).abs() < 1e-14);
        assert!((accel_white(2.0 * PI) - 3.0 * PI / (2.0 * PI).powi(3)).abs() < 1e-14);
        // 20·3π/(2π)⁵ and 252·((2π)³/3 + 4π + π)/(2π)⁷.
        assert!((gyro_white(2.0 * PI) - 60.0 * PI / (2.0 * PI).powi(5)).abs() < 1e-14);
        let i = (2.0 * PI).powi(3) / 3.0 + 5.0 * PI;
        assert!((gyro_random_walk(2.0 * PI) - 252.0 * i / (2.0 * PI).powi(7)).abs() < 1e-14);
    }

    #[test]
    fn the_flat_earth_limit_is_about_thirteen_minutes() {
        let t = flat_earth_limit_s();
        assert!((t - 806.0).abs() < 1.0, "{t} s");
    }
}
