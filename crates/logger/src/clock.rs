//! Where the recorder's time comes from, and how it waits.

use std::cell::Cell;
use std::rc::Rc;
use std::time::{Duration, Instant};

/// A monotonic clock: seconds since an origin of its own.
pub trait Clock {
    /// Seconds since the clock's origin; never decreases.
    fn now_s(&self) -> f64;
}

/// How the recorder waits between reads and before retries.
pub trait Sleeper {
    /// Waits for `d` (a real sleep may overshoot).
    fn sleep(&mut self, d: Duration);
}

/// The host's monotonic clock, from its creation: a wall-clock adjustment
/// during a run cannot bend the timestamps.
#[derive(Debug, Clone, Copy)]
pub struct HostClock {
    origin: Instant,
}

impl HostClock {
    /// A clock whose origin is now.
    pub fn start() -> HostClock {
        HostClock {
            origin: Instant::now(),
        }
    }
}

impl Clock for HostClock {
    fn now_s(&self) -> f64 {
        self.origin.elapsed().as_secs_f64()
    }
}

/// Sleeps the thread.
#[derive(Debug, Clone, Copy, Default)]
pub struct ThreadSleeper;

impl Sleeper for ThreadSleeper {
    fn sleep(&mut self, d: Duration) {
        std::thread::sleep(d);
    }
}

/// Simulated time, shared by its clones: sleeping moves it on, by the time
/// asked plus, if set, an overshoot drawn from a fixed generator (a loaded
/// host's sleep overshoots by up to a few milliseconds).
#[derive(Debug, Clone)]
pub struct SimTime {
    now: Rc<Cell<f64>>,
    overshoot_s: f64,
    rng: Rc<Cell<u64>>,
}

impl Default for SimTime {
    fn default() -> Self {
        SimTime::new()
    }
}

impl SimTime {
    /// Time 0, sleeps exact.
    pub fn new() -> SimTime {
        SimTime {
            now: Rc::new(Cell::new(0.0)),
            overshoot_s: 0.0,
            rng: Rc::new(Cell::new(0x9E37_79B9_7F4A_7C15)),
        }
    }

    /// Every sleep overshoots by a uniform [0, `max`), drawn from `seed`.
    pub fn with_overshoot(mut self, max: Duration, seed: u64) -> SimTime {
        self.overshoot_s = max.as_secs_f64();
        self.rng.set(seed.max(1));
        self
    }

    /// Moves time on by `s` seconds.
    pub fn advance(&self, s: f64) {
        self.now.set(self.now.get() + s.max(0.0));
    }

    /// Uniform in [0, 1): xorshift64* (Vigna 2016, "An experimental
    /// exploration of Marsaglia's xorshift generators, scrambled").
    fn uniform(&self) -> f64 {
        let mut x = self.rng.get();
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.rng.set(x);
        (x.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

impl Clock for SimTime {
    fn now_s(&self) -> f64 {
        self.now.get()
    }
}

/// The driver's waits (the start-up after a reset) pass in simulated time.
impl embedded_hal::delay::DelayNs for SimTime {
    fn delay_ns(&mut self, ns: u32) {
        self.sleep(Duration::from_nanos(u64::from(ns)));
    }
}

impl Sleeper for SimTime {
    fn sleep(&mut self, d: Duration) {
        let extra = if self.overshoot_s > 0.0 {
            self.overshoot_s * self.uniform()
        } else {
            0.0
        };
        self.advance(d.as_secs_f64() + extra);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simulated_sleeps_move_every_clone_on() {
        let t = SimTime::new();
        let mut s = t.clone();
        s.sleep(Duration::from_millis(20));
        assert_eq!(t.now_s(), 0.02);
        let mut j = SimTime::new().with_overshoot(Duration::from_millis(2), 7);
        let clock = j.clone();
        for _ in 0..100 {
            j.sleep(Duration::from_millis(10));
        }
        let over = clock.now_s() - 1.0;
        assert!(over > 0.05 && over < 0.2, "{over}");
    }
}
