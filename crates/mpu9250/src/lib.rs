//! # mpu9250 — the sensor driver and a register-level simulated chip
//!
//! A driver for the InvenSense MPU-9250 (and MPU-9255, MPU-6500) over
//! embedded-hal 1.0, on I2C ([`driver::I2cBus`]) or SPI
//! ([`driver::SpiBus`]): probe, reset (waiting out the start-up time
//! through embedded-hal's `DelayNs`), clock, full scales, low-pass filters,
//! sample rate, and reading the FIFO in whole 14-byte frames: overflow is
//! judged by the count and by INT_STATUS after each burst, and a FIFO reset
//! regains frame alignment after an overflow or a read broken off, so no
//! frame is ever decoded from misaligned bytes. Frames are named in
//! [`frame`] (raw counts and SI); conversion to SI is
//! [`config::Config::sample`]. The register map is [`regs`].
//! [`stream_clock::StreamClock`] sizes lost stretches from host time, to
//! ±1 sample whatever the chip's clock error.
//!
//! [`sim::SimChip`] implements the same bus traits at the register level:
//! register file, WHO_AM_I, a FIFO that fills in simulated time at the
//! configured rate and overflows at 512 bytes, bus time per transfer, and
//! fault injection (address NACKs, transfers broken off after bytes were
//! sent, brown-outs, a [`sim::FaultSchedule`] for a whole run), and the
//! start-up time after a reset, during which it answers nothing. The
//! driver's tests run against it.
//!
//! The driver, the configuration, the frames and the register map are
//! `no_std` without an allocator (default features off):
//! [`driver::Mpu9250::read_frames_into`] fills a caller's slice. The `std`
//! feature (default) adds the simulated chip, the stream clock, a
//! thread-sleeping delay and the reads that fill a `Vec`.
//!
//! **What it is not:** no magnetometer (AK8963), no DMP, no interrupts.
//!
//! ```
//! use mpu9250::config::Config;
//! use mpu9250::driver::{FifoRead, I2cBus, Mpu9250};
//! use mpu9250::sim::{ADDRESS, SimChip};
//! // A level sensor at rest: 1 g on z, 25 °C.
//! let g = earth::STANDARD_GRAVITY;
//! let chip = SimChip::new(Box::new(move |_, _| [0.0, 0.0, g, 0.0, 0.0, 0.0, 25.0]));
//! // The driver's waits (the start-up after a reset) pass on the chip; on
//! // a Raspberry Pi the delay is linux-embedded-hal's `Delay`.
//! let delay = chip.delay();
//! let mut imu = Mpu9250::new(I2cBus::new(chip, ADDRESS), delay).unwrap();
//! imu.configure(Config { rate_hz: 200.0, ..Config::default() }).unwrap();
//! imu.bus_mut().inner_mut().advance(0.05); // 50 ms of simulated time
//! let mut frames = Vec::new();
//! assert_eq!(imu.read_frames(&mut frames).unwrap(), FifoRead::Frames(10));
//! let sample = imu.config().sample(&frames[0]);
//! assert!((sample.accel[2] - g).abs() < 1e-3 && (sample.temp_c - 25.0).abs() < 0.01);
//! ```

#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]

#[cfg(feature = "std")]
mod clock_region;
pub mod config;
pub mod driver;
pub mod frame;
pub mod regs;
#[cfg(feature = "std")]
pub mod sim;
#[cfg(feature = "std")]
pub mod stream_clock;
