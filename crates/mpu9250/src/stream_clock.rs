//! Where the samples of a FIFO stream sit in host time: how many were lost
//! when the FIFO had to be reset, the rate the chip really runs at, and a
//! host timestamp for each sample.
//!
//! The stream has one clock: sample k of the run is taken at τ(k) = τ(0) +
//! k/rate, on the chip's oscillator. A read at host time t that finds frames
//! up to sample K says τ(K) ≤ t < τ(K) + 1/rate (the newest frame was
//! sampled within one period before the read). The clock keeps the interval
//! of host times that every read so far allows for the newest sample placed,
//! carried forward by the rate and widened by the rate's uncertainty; reads
//! with different lags narrow it to a fraction of a period. A loss (the FIFO
//! reset) is sized from that absolute position: the newest sample at the
//! first read after it is the last K with τ(K) ≤ t. So each gap is right to
//! ±1 sample and, unlike sizing each from the host time between its two
//! reads, the errors of successive gaps do not add up: the place of every
//! sample stays tied to the stream's start.
//!
//! The chip's oscillator is its own (±1 % over temperature), so the rate is
//! the one measured over the run's uninterrupted stretches, and the interval
//! is carried only from read to read: the rate's error acts over the time
//! between two reads, never over the whole run.
//!
//! ```
//! use mpu9250::stream_clock::StreamClock;
//! let mut clock = StreamClock::new(200.0, 0.0);
//! assert_eq!(clock.frames(0.1, 20), 0);
//! clock.lost(); // the FIFO overflowed and was reset
//! // 0.1 s → 1.2 s is 220 samples; the 20 read at 1.2 s came after the reset.
//! assert_eq!(clock.frames(1.2, 20), 200);
//! ```

/// Interrupted-free host time needed before the measured rate replaces the
/// nominal one: over 5 s the ±1-period lag of the ends makes an error of at
/// most 1/(5·rate), 0.1 % at 200 Hz, below the chip's clock tolerance.
const MEASURED_AFTER_S: f64 = 5.0;

/// Relative uncertainty of the nominal rate: the MPU-9250's clock varies by
/// ±1 % over temperature (PS-MPU-9250A-01 §4.15), doubled for margin.
const NOMINAL_UNCERTAINTY: f64 = 0.02;

/// Floor of the measured rate's relative uncertainty: the chip's clock
/// drifts with temperature during a run.
const MEASURED_UNCERTAINTY_FLOOR: f64 = 1e-5;

/// The clock model of one FIFO stream. Times are host seconds on any
/// monotonic scale.
#[derive(Debug, Clone)]
pub struct StreamClock {
    nominal_hz: f64,
    /// Host time of the last read that found frames with the FIFO intact.
    last_ok_s: f64,
    /// A FIFO reset happened since `last_ok_s`.
    pending: bool,
    /// Frames and host time over uninterrupted stretches.
    clean_frames: u64,
    clean_s: f64,
    /// Uninterrupted stretches so far: each of their ends lags by up to a
    /// period, which bounds how well the rate is known.
    stretches: u64,
    /// Samples placed so far (rows: read and lost).
    placed: u64,
    /// Samples the stream has produced up to the newest one read, by its
    /// clock; more than `placed` when a gap was judged short (the next gap
    /// makes up for it), less when one was judged long.
    produced: u64,
    /// The host times (lo, hi] between which sample `produced` was taken.
    lo_s: f64,
    hi_s: f64,
}

impl StreamClock {
    /// A stream of nominally `nominal_hz` whose FIFO started at `start_s`.
    pub fn new(nominal_hz: f64, start_s: f64) -> StreamClock {
        StreamClock {
            nominal_hz,
            last_ok_s: start_s,
            pending: false,
            clean_frames: 0,
            clean_s: 0.0,
            stretches: 1,
            placed: 0,
            produced: 0,
            // The first sample comes within one period after the start:
            // the "sample before it" was taken within one period before.
            lo_s: start_s - 1.0 / nominal_hz,
            hi_s: start_s,
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
        let lost = if self.pending {
            self.pending = false;
            // The frames just read are the newest; at least they came.
            let j = self.newest_by(t_s).max(n);
            self.advance(j, t_s);
            self.stretches += 1;
            // Where the stream is, less the rows written and read now.
            self.produced.saturating_sub(self.placed + n)
        } else {
            self.clean_frames += n;
            self.clean_s += (t_s - self.last_ok_s).max(0.0);
            self.advance_clean(n, t_s);
            0
        };
        self.placed += lost + n;
        self.last_ok_s = t_s;
        lost
    }

    /// How many samples the stream has produced after the newest placed one
    /// by host time `t_s`: the largest j with τ(placed − 1 + j) ≤ t_s, from
    /// the middle of the interval carried forward.
    fn newest_by(&self, t_s: f64) -> u64 {
        let (lo, hi) = self.carried(0, t_s);
        ((t_s - 0.5 * (lo + hi)) * self.rate_hz()).floor().max(0.0) as u64
    }

    /// The interval of the newest placed sample's time carried `j` samples
    /// forward to a read at `t_s`, widened by the rate's uncertainty over
    /// the time since the last read.
    fn carried(&self, j: u64, t_s: f64) -> (f64, f64) {
        let shift = j as f64 / self.rate_hz();
        let widen = self.rate_uncertainty() * (t_s - self.last_ok_s).abs();
        (self.lo_s + shift - widen, self.hi_s + shift + widen)
    }

    /// The stream produced `j` more samples, the newest of them read at
    /// `t_s`: the interval narrows to what this read also allows (taken
    /// within one period before it).
    fn advance(&mut self, j: u64, t_s: f64) {
        let (lo, hi) = self.carried(j, t_s);
        let (read_lo, read_hi) = (t_s - 1.0 / self.rate_hz(), t_s);
        let (lo, hi) = (lo.max(read_lo), hi.min(read_hi));
        // Empty: the rate moved more than allowed. The read alone is what
        // is known now.
        (self.lo_s, self.hi_s) = if lo < hi { (lo, hi) } else { (read_lo, read_hi) };
        self.produced += j;
    }

    /// `n` frames read with the FIFO intact since the last read. Should
    /// the read put the newest of them a whole number of periods away from
    /// where the clock expects it, the last gap was misjudged by that many
    /// samples: the stream's count is corrected, and the next gap makes up
    /// for it, so the error does not stay in the file for the rest of the
    /// run.
    fn advance_clean(&mut self, n: u64, t_s: f64) {
        let rate = self.rate_hz();
        let (lo, hi) = self.carried(n, t_s);
        let (read_lo, read_hi) = (t_s - 1.0 / rate, t_s);
        if lo.max(read_lo) >= hi.min(read_hi) {
            let m = ((0.5 * (read_lo + read_hi) - 0.5 * (lo + hi)) * rate).round() as i64;
            let (lo, hi) = (lo + m as f64 / rate, hi + m as f64 / rate);
            if m != 0 && lo.max(read_lo) < hi.min(read_hi) && self.produced as i64 + m >= 0 {
                self.produced = (self.produced as i64 + m) as u64;
            }
        }
        self.advance(n, t_s);
    }

    /// Relative uncertainty of [`StreamClock::rate_hz`].
    fn rate_uncertainty(&self) -> f64 {
        if self.clean_s >= MEASURED_AFTER_S {
            // The ends of each measuring stretch lag by up to a period, at
            // random: the time they add up to errs by about √stretches
            // periods (twice that for margin).
            (2.0 * (self.stretches as f64).sqrt() / self.clean_frames as f64).max(MEASURED_UNCERTAINTY_FLOOR)
        } else {
            NOMINAL_UNCERTAINTY
        }
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
            (self.produced + self.newest_by(t_s)).saturating_sub(self.placed)
        } else {
            0
        }
    }

    /// The rate measured over the uninterrupted stretches, once they add up
    /// to 5 s of host time.
    pub fn measured_hz(&self) -> Option<f64> {
        (self.clean_s >= MEASURED_AFTER_S).then(|| self.clean_frames as f64 / self.clean_s)
    }

    /// The rate used for estimates: measured, or nominal until measured.
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
    fn sample_times_count_back_from_the_read() {
        let clock = StreamClock::new(100.0, 0.0);
        assert_eq!(clock.sample_time(2.0, 9, 10), 2.0);
        assert!((clock.sample_time(2.0, 0, 10) - 1.91).abs() < 1e-12);
    }
}
