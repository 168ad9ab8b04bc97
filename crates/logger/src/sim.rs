//! The recorder against the simulated chip: before every read, the chip is
//! brought up to the host's time and its [`FaultSchedule`] applied.
//!
//! [`FaultSchedule`]: mpu9250::sim::FaultSchedule

use mpu9250::driver::{I2cBus, Mpu9250};
use mpu9250::sim::SimChip;

use crate::clock::{Clock, Sleeper};
use crate::recorder::Tick;

/// Drives a [`SimChip`] on I2C from the recorder's clock.
#[derive(Debug, Clone, Copy, Default)]
pub struct FollowHost;

impl Tick<I2cBus<SimChip>> for FollowHost {
    fn before_read(
        &mut self,
        imu: &mut Mpu9250<I2cBus<SimChip>>,
        clock: &dyn Clock,
        sleeper: &mut dyn Sleeper,
    ) {
        let chip = imu.bus_mut().inner_mut();
        if let Some(pause) = chip.host_pause_due(clock.now_s()) {
            sleeper.sleep(std::time::Duration::from_secs_f64(pause));
        }
        chip.follow_host(clock.now_s());
    }
}
