//! Where the samples of a FIFO stream sit in host time: how many were lost
//! when the FIFO had to be reset, the rate the chip really runs at, and a
//! host timestamp for each sample.
//!
//! The chip's clock is its own (its internal oscillator, or the gyro's PLL),
//! not the host's: counting samples from the start of a run by host time
//! would be off by the clock's error times the run's length, and place every
//! later gap wrongly. So every estimate here is local. A read at host time t
//! that finds frames has its newest frame sampled within one period before
//! t; a loss spans from the last good read to the first read with frames
//! after the reset, and its size is that interval times the rate, less the
//! frames the second read found. Both ends carry the same kind of lag, so
//! the estimate is right to ±1 sample whatever the length of the run; the
//! rate it uses is the one measured over the run's uninterrupted stretches.
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
        if self.pending {
            let span = (t_s - self.last_ok_s).max(0.0) * self.rate_hz();
            self.pending = false;
            self.last_ok_s = t_s;
            return (span.round() as u64).saturating_sub(n as u64);
        }
        self.clean_frames += n as u64;
        self.clean_s += (t_s - self.last_ok_s).max(0.0);
        self.last_ok_s = t_s;
        0
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
            ((t_s - self.last_ok_s).max(0.0) * self.rate_hz()).round() as u64
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
