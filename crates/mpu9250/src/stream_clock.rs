//! Where the samples of a FIFO stream sit in host time: how many were lost
//! when the FIFO had to be reset, the rate the chip really runs at, and a
//! host timestamp for each sample.
//!
//! The stream has one clock: sample k of the run is taken at τ(k) = τ(0) +
//! k/rate, on the chip's oscillator. A read at host time t that finds frames
//! up to sample K says τ(K) ≤ t < τ(K) + 1/rate (the newest frame was
//! sampled within one period before the read). Both bounds are linear in
//! (τ(K), 1/rate), so what all reads allow together is a convex polygon of
//! phase and period (`clock_region`), narrowed by every read, the
//! reads across gaps included, from the first one on: the period is known
//! to ±2 % at the start (the chip's tolerance, doubled), to 1 % after a
//! hundred samples, and reads at different lags pin the phase to a fraction
//! of a period.
//!
//! A loss (the FIFO reset) is sized from that absolute clock: after it, the
//! newest sample read is the K the polygon allows at the read's time. When
//! it allows several K (early in the run, before the period is known), each
//! is kept as an account of the stream with its own polygon, until later
//! reads contradict it; the likeliest (the largest polygon: the most clocks
//! left under a uniform prior) sizes the gap, and should a later read
//! favour another, the next gap makes up the difference. So the errors of
//! successive gaps do not add up: every sample's place stays tied to the
//! stream's start.
//!
//! The chip's oscillator drifts with temperature, so the polygon is widened
//! in period between reads by a bounded drift: old reads never pin the rate
//! for ever. The rate reported ([`StreamClock::measured_hz`]) is the one
//! measured over the run's uninterrupted stretches.
//!
//! ```
//! use mpu9250::stream_clock::StreamClock;
//! let mut clock = StreamClock::new(200.0, 0.0);
//! assert_eq!(clock.frames(0.1, 20), 0);
//! clock.lost(); // the FIFO overflowed and was reset
//! // 0.1 s → 1.2 s is 220 samples; the 20 read at 1.2 s came after the reset.
//! assert_eq!(clock.frames(1.2, 20), 200);
//! ```

use crate::clock_region::ClockRegion;
/// Interrupted-free host time needed before the measured rate replaces the
/// nominal one: over 5 s the ±1-period lag of the ends makes an error of at
/// most 1/(5·rate), 0.1 % at 200 Hz, below the chip's clock tolerance.
const MEASURED_AFTER_S: f64 = 5.0;

/// Relative uncertainty of the nominal rate: the MPU-9250's clock varies by
/// ±1 % over temperature (PS-MPU-9250A-01 §4.15), doubled for margin.
const NOMINAL_UNCERTAINTY: f64 = 0.02;

/// How fast the period may drift, relative, per second: ±1 % over the
/// 125 °C range (PS-MPU-9250A-01 §4.15) is 8e-5 per °C, and 1e-5 per second
/// lets the chip warm by 7 °C a minute, more than a thermal test does.
const DRIFT_PER_S: f64 = 1e-5;

/// Host time by which a frame may follow the time stamped on its read: the
/// time is taken just before the FIFO count is read, a transfer of five
/// bytes (0.1 ms at 400 kHz) and a system call.
const READ_LATENCY_S: f64 = 2e-4;

/// Hypotheses kept about the stream's sample count when reads cannot yet
/// tell them apart.
const MAX_HYPOTHESES: usize = 8;

/// Counts tried for one gap: ±1 % of 10 s at 1 kHz, twice over.
const MAX_COUNTS: i64 = 400;

/// One consistent account of the stream: the index of the newest sample
/// (the first of the run is 0) and the clocks that put it where every read
/// so far found it.
#[derive(Debug, Clone)]
struct Hypothesis {
    newest: i64,
    /// (host time of sample `newest`, period).
    region: ClockRegion,
    area: f64,
}

/// The clock model of one FIFO stream. Times are host seconds on any
/// monotonic scale.
#[derive(Debug, Clone)]
pub struct StreamClock {
    nominal_hz: f64,
    /// Host time of the last read that found frames.
    last_ok_s: f64,
    /// A FIFO reset happened since `last_ok_s`.
    pending: bool,
    /// Frames and host time over uninterrupted stretches.
    clean_frames: u64,
    clean_s: f64,
    /// Samples placed so far (rows: read and lost).
    placed: u64,
    /// Every account of the stream the reads still allow, the likeliest
    /// first.
    hypotheses: Vec<Hypothesis>,
}

impl StreamClock {
    /// A stream of nominally `nominal_hz` whose FIFO started at `start_s`.
    pub fn new(nominal_hz: f64, start_s: f64) -> StreamClock {
        let p = 1.0 / nominal_hz;
        let (p_lo, p_hi) = (p / (1.0 + NOMINAL_UNCERTAINTY), p / (1.0 - NOMINAL_UNCERTAINTY));
        // The first sample comes within one period after the start: the
        // "sample before it", index −1, was taken within one period before.
        let region = ClockRegion::rect(start_s - p_hi, start_s + READ_LATENCY_S, p_lo, p_hi);
        StreamClock {
            nominal_hz,
            last_ok_s: start_s,
            pending: false,
            clean_frames: 0,
            clean_s: 0.0,
            placed: 0,
            hypotheses: vec![Hypothesis {
                newest: -1,
                area: region.area_centroid().0,
                region,
            }],
        }
    }

    /// A read at host time `t_s` found `n` whole frames. Returns how many
    /// samples were lost just before them (0 unless a reset came since the
    /// last good read). After a reset, a read that finds no frame yet
    /// settles nothing and returns 0; the next one with frames does.
    pub fn frames(&mut self, t_s: f64, n: usize) -> u64 {
        // A read with no frame says nothing of when the newest sample was
        // taken (the chip may have stopped): the last read with frames
        // stays the anchor.
        if n == 0 {
            return 0;
        }
        let n = n as u64;
        let dt = (t_s - self.last_ok_s).max(0.0);
        if !self.pending {
            self.clean_frames += n;
            self.clean_s += dt;
        }
        let guess = self.newest_by(t_s);
        let mut next = Vec::new();
        for h in &self.hypotheses {
            let mut region = h.region.clone();
            let (_, (_, p)) = region.area_centroid();
            region.widen_period(DRIFT_PER_S * dt * p);
            let (p_min, p_max) = self.period_bounds();
            region.periods_within(p_min, p_max);
            // The newest frame read is sample newest + m: exactly n on with
            // the FIFO intact; after a reset, any count the clock allows.
            let ms = if self.pending {
                let (lo, hi) = region.periods_to(t_s + READ_LATENCY_S);
                let mut lo = (lo - 1.0).floor().max(n as f64) as i64;
                let mut hi = hi.floor().max(n as f64) as i64;
                // A stall of many seconds before the period is known allows
                // thousands of counts: those far from the likeliest cannot
                // win anyway.
                if hi - lo > MAX_COUNTS {
                    let (_, (b, p)) = region.area_centroid();
                    let mid = ((t_s - b) / p).floor() as i64;
                    (lo, hi) = (lo.max(mid - MAX_COUNTS / 2), hi.min(mid + MAX_COUNTS / 2));
                }
                (lo..=hi).collect::<Vec<_>>()
            } else {
                vec![n as i64]
            };
            for m in ms {
                let mut r = region.clone();
                // Taken by the read (or just after the time stamped on
                // it), the next one not yet.
                r.taken_by(m as f64, t_s + READ_LATENCY_S);
                r.not_before(m as f64 + 1.0, t_s);
                if !r.is_empty() {
                    r.shift(m);
                    let newest = h.newest + m;
                    // Accounts that agree on the count are one: their
                    // clocks together (else they would crowd out the others).
                    match next.iter_mut().find(|o: &&mut Hypothesis| o.newest == newest) {
                        Some(o) => {
                            o.region.merge(&r);
                            o.area = o.region.area_centroid().0;
                        }
                        None => next.push(Hypothesis {
                            newest,
                            area: r.area_centroid().0,
                            region: r,
                        }),
                    }
                }
            }
        }
        if next.is_empty() {
            // No account fits: the chip's clock jumped (a reset of its own,
            // or a drift beyond bounds). Start again from this read alone,
            // the count where the likeliest account put it.
            let newest = if self.pending {
                guess.max(self.placed as i64 - 1 + n as i64)
            } else {
                self.hypotheses[0].newest + n as i64
            };
            let (p_lo, p_hi) = self.period_bounds();
            let region = ClockRegion::rect(t_s - p_hi, t_s + READ_LATENCY_S, p_lo, p_hi);
            next.push(Hypothesis {
                newest,
                area: region.area_centroid().0,
                region,
            });
        }
        // Under a uniform prior on the clock, an account is as likely as the
        // area of clocks it leaves.
        next.sort_by(|x, y| y.area.total_cmp(&x.area));
        next.truncate(MAX_HYPOTHESES);
        self.hypotheses = next;
        let lost = if self.pending {
            self.pending = false;
            // Where the stream is, less the rows written and read now. When
            // the likeliest account changed since the last gap, this one
            // makes up for it.
            ((self.hypotheses[0].newest + 1).max(0) as u64).saturating_sub(self.placed + n)
        } else {
            0
        };
        self.placed += lost + n;
        self.last_ok_s = t_s;
        lost
    }

    /// The periods the chip can run at: its tolerance, which no drift
    /// between reads goes beyond.
    fn period_bounds(&self) -> (f64, f64) {
        let p = 1.0 / self.nominal_hz;
        (p / (1.0 + NOMINAL_UNCERTAINTY), p / (1.0 - NOMINAL_UNCERTAINTY))
    }

    /// The index of the newest sample taken by host time `t_s`, by the
    /// likeliest account at its centre.
    fn newest_by(&self, t_s: f64) -> i64 {
        let h = &self.hypotheses[0];
        let (_, (b, p)) = h.region.area_centroid();
        h.newest + ((t_s - b) / p).floor().max(0.0) as i64
    }

    /// The FIFO was reset (an overflow, or a read that broke off part-way):
    /// the samples since the last good read are lost.
    pub fn lost(&mut self) {
        self.pending = true;
    }

    /// A reset is still waiting for the frames that will size its loss.
    pub fn pending(&self) -> bool {
        self.pending
    }

    /// Samples lost by the time `t_s` if the stream ends with a loss
    /// pending.
    pub fn lost_until(&self, t_s: f64) -> u64 {
        if self.pending {
            ((self.newest_by(t_s) + 1).max(0) as u64).saturating_sub(self.placed)
        } else {
            0
        }
    }

    /// The rate measured over the uninterrupted stretches, once they add up
    /// to 5 s of host time.
    pub fn measured_hz(&self) -> Option<f64> {
        (self.clean_s >= MEASURED_AFTER_S).then(|| self.clean_frames as f64 / self.clean_s)
    }

    /// The rate used for timestamps: measured, or nominal until measured.
    pub fn rate_hz(&self) -> f64 {
        self.measured_hz().unwrap_or(self.nominal_hz)
    }

    /// Host time of frame `i` of `n` read at `t_s`: the read time less the
    /// frame's age in the FIFO.
    pub fn sample_time(&self, t_s: f64, i: usize, n: usize) -> f64 {
        t_s - (n.saturating_sub(1 + i)) as f64 / self.rate_hz()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chip whose clock runs `error` fast, read every `poll` s with a
    /// reset of the FIFO at `reset_at` after a `stall` s pause. Returns
    /// (estimated loss, true loss, measured rate).
    fn run(rate: f64, error: f64, poll: f64, reset_at: f64, stall: f64, phase: f64) -> (u64, u64, f64) {
        let true_rate = rate * (1.0 + error);
        // Sample k is taken at phase + (k+1)/true_rate.
        let taken_by = |t: f64| ((t - phase) * true_rate).floor().max(0.0) as u64;
        let mut clock = StreamClock::new(rate, phase);
        let (mut read, mut t, mut lost_est, mut lost_true) = (0u64, 0.0, 0, 0);
        let mut stalled = false;
        while t < reset_at + 20.0 {
            t += poll;
            if !stalled && t >= reset_at {
                stalled = true;
                t += stall;
                // The FIFO reset: everything up to now is gone.
                let now = taken_by(t);
                lost_true = now - read;
                read = now;
                clock.lost();
                t += 0.0005;
                continue;
            }
            let now = taken_by(t);
            lost_est += clock.frames(t, (now - read) as usize);
            read = now;
        }
        (lost_est, lost_true, clock.measured_hz().unwrap())
    }

    #[test]
    fn a_loss_is_sized_to_one_sample_whatever_the_clock_error() {
        for &error in &[0.0, 0.01, -0.02] {
            for &phase in &[0.0, 0.0013, 0.0031] {
                for &stall in &[0.3, 0.5, 2.0] {
                    let (est, truth, _) = run(200.0, error, 0.02, 30.0, stall, phase);
                    assert!(
                        est.abs_diff(truth) <= 1,
                        "error {error}, phase {phase}, stall {stall}: {est} vs {truth}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_rate_is_measured_not_assumed() {
        let (_, _, measured) = run(200.0, 0.015, 0.02, 30.0, 0.5, 0.001);
        assert!((measured / 203.0 - 1.0).abs() < 2e-4, "{measured}");
        let clock = StreamClock::new(100.0, 0.0);
        assert_eq!(clock.measured_hz(), None);
        assert_eq!(clock.rate_hz(), 100.0);
    }

    #[test]
    fn a_loss_waits_for_frames_and_one_at_the_end_is_sized_by_time() {
        let mut clock = StreamClock::new(100.0, 0.0);
        assert_eq!(clock.frames(1.0, 100), 0);
        clock.lost();
        assert_eq!(clock.frames(1.5, 0), 0);
        assert!(clock.pending());
        assert_eq!(clock.lost_until(2.0), 100);
        assert_eq!(clock.frames(2.0, 10), 90);
        assert!(!clock.pending());
        assert_eq!(clock.lost_until(3.0), 0);
    }

    #[test]
    fn a_silent_chip_is_a_gap_and_does_not_bend_the_rate() {
        let mut clock = StreamClock::new(200.0, 0.0);
        // 10 s of frames, then 1 s of empty reads, then a reset.
        for k in 1..=500 {
            clock.frames(k as f64 * 0.02, 4);
        }
        for k in 1..=50 {
            assert_eq!(clock.frames(10.0 + k as f64 * 0.02, 0), 0);
        }
        assert!((clock.measured_hz().unwrap() - 200.0).abs() < 1e-9);
        clock.lost();
        // The first frames after the reset, 0.1 s after it: 220 samples of
        // time since the last frames, 20 of them read.
        assert_eq!(clock.frames(11.1, 20), 200);
    }

    #[test]
    fn an_hour_long_stall_is_sized_within_the_chip_tolerance() {
        // 10 s at 200 Hz, then nothing for an hour: the period may have
        // drifted anywhere within the chip's tolerance meanwhile.
        let mut clock = StreamClock::new(200.0, 0.0);
        let taken_by = |t: f64| (t * 200.0).floor() as u64;
        let mut read = 0;
        for k in 1..=500 {
            let t = k as f64 * 0.02 + 0.0007 * (k % 7) as f64;
            assert_eq!(clock.frames(t, (taken_by(t) - read) as usize), 0);
            read = taken_by(t);
        }
        clock.lost();
        let t = 10.0 + 3600.0;
        let lost = clock.frames(t, 20) as f64;
        let truth = (taken_by(t) - read - 20) as f64;
        assert!((lost / truth - 1.0).abs() < NOMINAL_UNCERTAINTY, "{lost}");
        // And the clock goes on from there.
        assert_eq!(clock.frames(t + 0.1, 20), 0);
    }

    #[test]
    fn sample_times_count_back_from_the_read() {
        let clock = StreamClock::new(100.0, 0.0);
        assert_eq!(clock.sample_time(2.0, 9, 10), 2.0);
        assert!((clock.sample_time(2.0, 0, 10) - 1.91).abs() < 1e-12);
    }
}
