//! The recorder against the simulated chip: before every read, the host
//! takes the pauses of the chip's [`FaultSchedule`], its bus errors start,
//! and the chip is brought up to the host's time (a chip made
//! [`SimChip::with_host_clock`] follows it at every transfer anyway).
//!
//! [`FaultSchedule`]: mpu9250::sim::FaultSchedule

use embedded_hal::delay::DelayNs;
use mpu9250::driver::{I2cBus, Mpu9250};
use mpu9250::sim::SimChip;

use crate::clock::{Clock, Sleeper};
use crate::recorder::Tick;

/// Drives a [`SimChip`] on I2C from the recorder's clock.
#[derive(Debug, Clone, Copy, Default)]
pub struct FollowHost;

impl<D: DelayNs> Tick<I2cBus<SimChip>, D> for FollowHost {
    fn before_read(
        &mut self,
        imu: &mut Mpu9250<I2cBus<SimChip>, D>,
        clock: &dyn Clock,
        sleeper: &mut dyn Sleeper,
    ) {
        let chip = imu.bus_mut().inner_mut();
        chip.start_faults();
        if let Some(pause) = chip.host_pause_due(clock.now_s()) {
            sleeper.sleep(std::time::Duration::from_secs_f64(pause));
        }
        chip.follow_host(clock.now_s());
    }
}
