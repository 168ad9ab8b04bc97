//! # logger — the MPU-9250 recorder
//!
//! The loop behind `imutherm record`: reads the sensor's FIFO at a steady
//! pace through [`mpu9250`], writes every sample to an imutherm log
//! ([`imu::LogWriter`]), marks every lost stretch as a gap (a `# gap:` line
//! naming its size and cause, then one row of NaN per lost sample), counts
//! every kind of loss, flushes every second and syncs every five, and ends
//! the file with a trailer whatever stopped the run.
//!
//! Time comes from a [`Clock`] and pauses go through a [`Sleeper`]: the
//! binary passes the host's ([`HostClock`], [`ThreadSleeper`]); tests pass
//! [`SimTime`], under which an hour of recording against the simulated
//! chip ([`mpu9250::sim::SimChip`], its faults scheduled by
//! [`mpu9250::sim::FaultSchedule`]) runs in about a second of host time.
//!
//! **What it is not:** no flag parsing and no printing (the status line and
//! the closing message are the caller's, from [`Status`] and [`Summary`]);
//! no opening of devices or files.

mod clock;
mod loss;
mod recorder;
pub mod sim;
mod storage;

pub use clock::{Clock, HostClock, SimTime, Sleeper, ThreadSleeper};
pub use loss::{Counters, Loss};
pub use recorder::{NoTick, RecordError, Settings, Status, StopReason, Summary, Tick, configure, record};
pub use storage::Storage;
