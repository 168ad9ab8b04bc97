//! Flicker (1/f) rate noise — bias instability — from a bank of first-order
//! Gauss–Markov processes with correlation times spaced evenly in log T.
//!
//! A Gauss–Markov process of variance σ² and correlation time T has the
//! one-sided PSD 4σ²T/(1 + (2πfT)²). Summed over times spaced Δ = ln r
//! apart in ln T, the bank approaches ∫ 4σ²T/(1+(2πfT)²) dlnT / Δ =
//! σ²/(Δ·f): a 1/f spectrum between 1/(2πT_max) and 1/(2πT_min). IEEE 952
//! gives bias instability B the two-sided rate PSD B²/(2π f), one-sided
//! B²/(π f), so each process gets σ² = B²Δ/π, and the Allan deviation is
//! flat at √(2 ln2/π)·B ≈ 0.664·B over the τ the bank covers.
//!
//! How flat: [`Design::allan_variance`] gives the bank's exact Allan
//! variance (each process's closed form, summed). With two processes per
//! decade reaching from a twentieth of the lowest flat τ to twenty times the
//! highest, it stays within −3 %…+0 % of 0.664·B over the whole stated
//! range (checked by a test over many ranges); the ripple between processes
//! is below 0.1 %, and the loss is at the ends of the range.
//!
//! Sampling: a sample is what an integrating sensor reports, the average
//! of the rate over its interval. For every process updated at each sample
//! that is what is drawn (the interval's integral jointly with the next
//! value, exactly). Read at the instant instead, a process of correlation
//! time T adds σ²(1 − e^{−τ0/T}) to the Allan variance at τ0 where its
//! average adds about two thirds of that (the bank of a preset at 100 Hz,
//! flat from 1 s, would give 1.56 times its averaged Allan variance at
//! τ0). The held (slow) processes are read at the instant; their share of
//! the Allan variance at τ0 is below 1 %. A bank cut off at τ0 would miss the flicker above the Nyquist
//! frequency, which an integrating sensor folds into every sample: the
//! Allan variance of such a bank is the plateau less a white-noise share,
//! ≈ 0.017·B²/τ for a bank starting at τ0/2 (4 % of N² for N = 5e-5,
//! B = 8e-5), read by a noise model as N too low. So a bank asked to be
//! flat from τ0 reaches [`REACH_BELOW`] of that, down to [`FINEST`]·τ0.
//!
//! Streaming: each process keeps one number. The slow ones are updated only
//! every 2^k samples (at least 32 updates per correlation time), exactly
//! (φ = e^(−stride·τ0/T)), and held in between, so that a bank reaching days
//! of correlation costs a few normal draws per sample and O(1) memory.

use rand::Rng;
use rand_distr::{Distribution, StandardNormal};

/// Processes per decade of correlation time: with two, the ripple of the
/// summed spectrum is under 0.1 % in Allan deviation.
pub const POLES_PER_DECADE: f64 = 2.0;

/// The bank reaches this far below the lowest flat τ…
const REACH_BELOW: f64 = 0.05;
/// …and this far above the highest.
const REACH_ABOVE: f64 = 20.0;

/// A bank whose reach below its flat range falls within the first sample
/// interval starts at this many sample intervals: what is left out below
/// adds at most 0.15 % of the flicker's Allan variance at τ0.
const FINEST: f64 = 1e-3;

/// Updates per correlation time of a held (slow) process.
const UPDATES_PER_CORRELATION_TIME: f64 = 32.0;

/// The processes of a bank for unit bias instability (B = 1).
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    /// Correlation times, s, ascending.
    pub correlation_times_s: Vec<f64>,
    /// Variance of each process (B = 1).
    pub variance: f64,
}

impl Design {
    /// A bank whose Allan deviation is flat for τ in `[tau_lo, tau_hi]` (s),
    /// sampled every `tau0` s.
    pub fn new(tau0: f64, tau_lo: f64, tau_hi: f64) -> Design {
        // Flat down to a range that starts within the first few samples
        // means the flicker continues above the Nyquist frequency.
        let reach = REACH_BELOW * tau_lo;
        let t_min = if reach < tau0 { FINEST * tau0 } else { reach };
        let t_max = (REACH_ABOVE * tau_hi).max(t_min);
        let ratio = 10f64.powf(1.0 / POLES_PER_DECADE);
        // Bounded so that a degenerate range (zero, infinite) cannot ask
        // for an unbounded bank: 4096 processes span 2048 decades.
        let count = ((t_max / t_min).ln() / ratio.ln()).ceil().clamp(0.0, 4095.0) as usize + 1;
        Design {
            correlation_times_s: (0..count).map(|i| t_min * ratio.powi(i as i32)).collect(),
            variance: ratio.ln() / std::f64::consts::PI,
        }
    }

    /// The bank's Allan variance at τ for B = 1, in continuous time: the
    /// sum over its processes of 2σ²T/τ·[1 − T/(2τ)·(3 − 4e^(−τ/T) + e^(−2τ/T))]
    /// (the exponentially correlated process; Allan variance of a first-order
    /// Gauss–Markov rate). IEEE 952's flat level is 2 ln2/π.
    pub fn allan_variance(&self, tau: f64) -> f64 {
        self.correlation_times_s
            .iter()
            .map(|&t| {
                let x = tau / t;
                let bracket = if x < 1e-3 {
                    // The closed form cancels catastrophically here; its
                    // series is x²/3 − x³/4 + …
                    x * x / 3.0 - x * x * x / 4.0
                } else {
                    1.0 - (3.0 - 4.0 * (-x).exp() + (-2.0 * x).exp()) / (2.0 * x)
                };
                2.0 * self.variance / x * bracket
            })
            .sum()
    }
}

#[derive(Debug, Clone)]
struct Pole {
    value: f64,
    phi: f64,
    kick: f64,
    /// Updated when the sample count is a multiple of 2^log2_stride.
    log2_stride: u32,
    /// For a process drawn as its average over the interval: that average
    /// is `from_value`·x_k + `along`·w₁ + `apart`·w₂, with w₁ the draw of
    /// the next value x_{k+1} = φx_k + kick·w₁.
    average: Option<Average>,
}

#[derive(Debug, Clone, Copy)]
struct Average {
    from_value: f64,
    along: f64,
    apart: f64,
}

impl Average {
    /// The interval average of a Gauss–Markov process of variance σ² and
    /// correlation time T over h, given its value at the start: mean
    /// x_k·T(1−φ)/h, and with I = ∫x, Var(I | x_k) = σ²(2Th − T²(3 − 4φ + φ²))
    /// and Cov(I, x_{k+1} | x_k) = σ²T(1 − φ)², φ = e^{−h/T} (the integrated
    /// Ornstein–Uhlenbeck process; Gillespie, Phys. Rev. E 54, 2084, 1996).
    fn new(sigma2: f64, t: f64, h: f64) -> Average {
        let phi = (-h / t).exp();
        let one_minus = -(-h / t).exp_m1();
        let var_next = sigma2 * (1.0 - phi * phi);
        let var_int = sigma2 * (2.0 * t * h - t * t * (3.0 - 4.0 * phi + phi * phi));
        let cov = sigma2 * t * one_minus * one_minus;
        let along = if var_next > 0.0 {
            cov / var_next.sqrt()
        } else {
            0.0
        };
        let apart = (var_int - along * along).max(0.0).sqrt();
        Average {
            from_value: t * one_minus / h,
            along: along / h,
            apart: apart / h,
        }
    }
}

/// A unit flicker source (B = 1): multiply by B.
#[derive(Debug, Clone)]
pub struct FlickerBank {
    poles: Vec<Pole>,
    /// The sum of the processes read at the instant.
    sum: f64,
    count: u64,
}

impl FlickerBank {
    /// A bank whose Allan deviation is flat for τ in `[tau_lo, tau_hi]` (s),
    /// at sample interval `tau0`, started in its stationary state.
    pub fn new(tau0: f64, tau_lo: f64, tau_hi: f64, rng: &mut impl Rng) -> FlickerBank {
        let design = Design::new(tau0, tau_lo, tau_hi);
        let sigma = design.variance.sqrt();
        let poles = design
            .correlation_times_s
            .iter()
            .map(|&t| {
                let per_update = (t / tau0 / UPDATES_PER_CORRELATION_TIME).max(1.0);
                let log2_stride = (per_update.log2().floor() as u32).min(62);
                let stride = (1u64 << log2_stride) as f64;
                let phi = (-stride * tau0 / t).exp();
                let w: f64 = StandardNormal.sample(rng);
                Pole {
                    value: sigma * w,
                    phi,
                    kick: sigma * (1.0 - phi * phi).sqrt(),
                    log2_stride,
                    average: (log2_stride == 0).then(|| Average::new(design.variance, t, tau0)),
                }
            })
            .collect::<Vec<_>>();
        let sum = poles
            .iter()
            .filter(|p| p.average.is_none())
            .map(|p| p.value)
            .sum();
        FlickerBank { poles, sum, count: 0 }
    }

    /// The next sample.
    #[inline]
    pub fn next(&mut self, rng: &mut impl Rng) -> f64 {
        self.count = self.count.wrapping_add(1);
        // The processes due now are exactly those whose stride divides the
        // count; strides grow along the bank, so the loop stops at the
        // first one not due and the held ones cost nothing.
        let due = self.count.trailing_zeros();
        let mut averages = 0.0;
        for p in &mut self.poles {
            if p.log2_stride > due {
                break;
            }
            let w: f64 = StandardNormal.sample(rng);
            let new = p.phi * p.value + p.kick * w;
            match p.average {
                Some(a) => {
                    let apart: f64 = StandardNormal.sample(rng);
                    averages += a.from_value * p.value + a.along * w + a.apart * apart;
                }
                None => self.sum += new - p.value,
            }
            p.value = new;
        }
        self.sum + averages
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FLAT: f64 = 2.0 * std::f64::consts::LN_2 / std::f64::consts::PI;

    #[test]
    fn the_bank_is_flat_within_five_percent_over_its_range() {
        // Ranges and sample intervals as configurations use them: the Allan
        // deviation of the bank's exact curve against IEEE 952's 0.664·B.
        for &(tau0, lo, hi) in &[
            (0.01, 1.0, 2000.0),
            (0.1, 1.0, 2000.0),
            (0.005, 0.1, 3000.0),
            (0.001, 0.5, 100.0),
            (1.0, 20.0, 1e5),
            (0.01, 3.0, 30.0),
        ] {
            let d = Design::new(tau0, lo, hi);
            let mut worst = (f64::INFINITY, 0.0f64);
            for i in 0..=200 {
                let tau = lo * (hi / lo).powf(i as f64 / 200.0);
                let r = (d.allan_variance(tau) / FLAT).sqrt();
                worst = (worst.0.min(r), worst.1.max(r));
            }
            assert!(
                worst.0 > 0.95 && worst.1 < 1.05,
                "τ0 {tau0}, [{lo}, {hi}]: ADEV / (0.664·B) spans {worst:?}"
            );
        }
    }

    #[test]
    fn gauss_markov_allan_variance_limits() {
        // One process: white (2σ²T/τ) far above T, random walk (2σ²τ/(3T))
        // far below: the closed form must reach both.
        let d = Design {
            correlation_times_s: vec![10.0],
            variance: 1.0,
        };
        let white = d.allan_variance(1e6);
        assert!((white / (2.0 * 10.0 / 1e6) - 1.0).abs() < 1e-4, "{white}");
        let walk = d.allan_variance(1e-4);
        assert!((walk / (2.0 * 1e-4 / 30.0) - 1.0).abs() < 1e-3, "{walk}");
        let walk = d.allan_variance(0.02);
        assert!((walk / (2.0 * 0.02 / 30.0) - 1.0).abs() < 2e-3, "{walk}");
    }

    #[test]
    fn degenerate_ranges_do_not_panic() {
        for (tau0, lo, hi) in [(0.0, 0.0, 1.0), (0.01, 0.0, f64::INFINITY), (0.01, f64::NAN, 1.0)] {
            let d = Design::new(tau0, lo, hi);
            assert!(d.correlation_times_s.len() <= 4096);
        }
    }

    #[test]
    fn held_processes_update_on_their_stride() {
        use rand::SeedableRng;
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(1);
        let mut bank = FlickerBank::new(0.01, 1.0, 1000.0, &mut rng);
        let strides: Vec<u32> = bank.poles.iter().map(|p| p.log2_stride).collect();
        assert!(strides.windows(2).all(|w| w[0] <= w[1]), "{strides:?}");
        assert_eq!(strides[0], 0);
        assert!(*strides.last().unwrap_or(&0) > 10);
        let before: Vec<f64> = bank.poles.iter().map(|p| p.value).collect();
        for _ in 0..3 {
            bank.next(&mut rng);
        }
        // After three samples only stride-1 and stride-2 processes moved.
        for (p, b) in bank.poles.iter().zip(&before) {
            assert_eq!(p.log2_stride <= 1, p.value != *b, "stride 2^{}", p.log2_stride);
        }
        let sum: f64 = bank
            .poles
            .iter()
            .filter(|p| p.average.is_none())
            .map(|p| p.value)
            .sum();
        assert!((sum - bank.sum).abs() < 1e-12);
    }

    #[test]
    fn a_bank_flat_from_the_first_sample_holds_the_plateau_there() {
        // Asked to be flat from τ0, the drawn samples' overlapping Allan
        // variance at m = 1, 2, 4 is IEEE 952's plateau (2 ln 2/π)·B², within
        // its statistical error (ν ≈ 2·10⁵/3 at m = 1: ±1.7 % at 3σ). A bank
        // cut off at τ0/2 and read at the instant gives 0.69 of it at m = 1.
        use rand::SeedableRng;
        let tau0 = 0.1;
        let design = Design::new(tau0, tau0, 100.0);
        assert!((design.allan_variance(tau0) / FLAT - 1.0).abs() < 5e-3);
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
        let mut bank = FlickerBank::new(tau0, tau0, 100.0, &mut rng);
        let y: Vec<f64> = (0..200_000).map(|_| bank.next(&mut rng)).collect();
        for m in [1usize, 2, 4] {
            let means: Vec<f64> = y.windows(m).map(|w| w.iter().sum::<f64>() / m as f64).collect();
            let d: Vec<f64> = means.iter().zip(&means[m..]).map(|(a, b)| b - a).collect();
            let avar = d.iter().map(|v| v * v).sum::<f64>() / (2.0 * d.len() as f64);
            let tol = 0.017 * (m as f64).sqrt() * 1.5;
            assert!((avar / FLAT - 1.0).abs() < tol, "m = {m}: {}", avar / FLAT);
        }
    }
}
