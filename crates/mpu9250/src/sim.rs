//! A simulated MPU-9250 at the register level, on the same bus traits as
//! the real one (I2C at 0x68, and SPI).
//!
//! The FIFO fills in simulated time ([`SimChip::advance`]) at the rate the
//! registers configure (1 kHz / (1 + SMPLRT_DIV)), from a sample source in
//! SI units, quantized to the configured full scales; it holds 512 bytes and,
//! with FIFO_MODE clear, drops its oldest bytes when full and raises
//! FIFO_OFLOW_INT. An empty FIFO keeps returning its last byte, as the chip
//! does. Bus errors can be injected at a given rate: half of them an address
//! NACK (nothing happens), half a transfer that breaks off part-way, which
//! in a FIFO read loses the bytes already sent, as on a real bus. After
//! H_RESET the chip answers nothing (an address NACK) for its start-up
//! time, so a driver that does not wait it out fails.
//!
//! Time passes through [`SimChip::advance`], through the chip's own
//! [`SimDelay`] (a driver's waits), or, with [`SimChip::with_host_clock`],
//! by following a host clock before every transfer.

use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use embedded_hal::i2c::{ErrorKind, I2c, NoAcknowledgeSource, Operation};

use crate::config::{AccelRange, GyroRange};
use crate::driver::{Error, I2cBus, Mpu9250, SpiBus};
use crate::frame::{RawFrame, Sample};
use crate::regs;

/// Where the simulated chip's samples come from: (sample index, time s) →
/// [ax, ay, az (m/s²), gx, gy, gz (rad/s), temperature (°C)].
pub type Source = Box<dyn FnMut(u64, f64) -> [f64; 7] + Send>;

/// The I2C address the simulated chip answers at (AD0 low).
pub const ADDRESS: u8 = 0x68;

/// A failed transfer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SimError {
    /// Nobody answered the address (injected, or a wrong address): the chip
    /// saw nothing.
    Nack,
    /// The transfer broke off part-way: the chip had already sent this many
    /// bytes, and a FIFO read has lost them.
    ShortRead(usize),
}

impl embedded_hal::i2c::Error for SimError {
    fn kind(&self) -> ErrorKind {
        match self {
            SimError::Nack => ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address),
            SimError::ShortRead(_) => ErrorKind::Other,
        }
    }
}

impl embedded_hal::spi::Error for SimError {
    fn kind(&self) -> embedded_hal::spi::ErrorKind {
        embedded_hal::spi::ErrorKind::Other
    }
}

/// What the chip has been through.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SimStats {
    /// Samples produced while the FIFO was running.
    pub samples: u64,
    /// Overflows (each may lose several frames).
    pub overflows: u64,
    /// Transfers failed on purpose.
    pub injected_errors: u64,
    /// Of those, FIFO reads broken off part-way (bytes lost).
    pub short_reads: u64,
    /// Of those, INT_STATUS reads that failed after the chip sent (and so
    /// cleared) the status.
    pub lost_status_reads: u64,
}

/// The faults of a simulated run, on the host's time line (seconds since
/// the clock the recorder reads, see [`SimChip::follow_host`]). The host's
/// own pauses are part of it: a reader that stalls is what overflows a
/// FIFO.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FaultSchedule {
    /// Fraction of bus transfers that fail once the faults start (see
    /// [`SimChip::with_error_rate`]).
    pub bus_errors: f64,
    /// The host pauses reading every this many seconds…
    pub stall_every_s: Option<f64>,
    /// …for this long.
    pub stall_s: f64,
    /// The chip's clock error, ppm: its sample clock runs 1 + ppm·10⁻⁶ times
    /// the host's (±1 % over temperature, PS-MPU-9250A-01 §4.15).
    pub clock_ppm: f64,
    /// A brown-out at this host time, s (see [`SimChip::power_cycle`]).
    pub brownout_at_s: Option<f64>,
}

/// Where a chip following the host stands in its [`FaultSchedule`].
#[derive(Debug, Clone, Copy, Default)]
struct Following {
    host_s: f64,
    last_stall_s: f64,
    browned_out: bool,
}

/// A driver's delay that passes on the simulated chip: the time waited
/// passes for the chip before its next transfer.
#[derive(Debug, Clone)]
pub struct SimDelay {
    pending_ns: Arc<AtomicU64>,
}

impl embedded_hal::delay::DelayNs for SimDelay {
    fn delay_ns(&mut self, ns: u32) {
        self.pending_ns.fetch_add(u64::from(ns), Ordering::Relaxed);
    }
}

/// A host clock the chip follows: seconds since its origin.
pub type HostClock = Box<dyn Fn() -> f64>;

/// The simulated chip.
pub struct SimChip {
    regs: [u8; 128],
    fifo: VecDeque<u8>,
    last_byte: u8,
    time_s: f64,
    next_time_s: f64,
    source: Source,
    error_rate: f64,
    planned: Option<(u8, SimError)>,
    bus_hz: Option<f64>,
    rng: u64,
    stats: SimStats,
    who_am_i: u8,
    /// The sample grid, which runs whether or not the FIFO takes its
    /// samples (as the chip's sample clock does): its origin (set at reset
    /// and when SMPLRT_DIV is written) and the index of the last grid time
    /// sampled into the FIFO.
    start_s: f64,
    since_start: u64,
    faults: FaultSchedule,
    following: Following,
    /// Waits of the driver not yet passed on the chip.
    pending_ns: Arc<AtomicU64>,
    host_clock: Option<HostClock>,
    /// Time on the outside's line (the host's, the test's), which the
    /// start-up after H_RESET takes whatever the chip's own clock does.
    wall_s: f64,
    /// Until this wall time the chip is starting up after H_RESET.
    ready_s: f64,
}

impl std::fmt::Debug for SimChip {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SimChip")
            .field("time_s", &self.time_s)
            .field("fifo", &self.fifo.len())
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

impl SimChip {
    /// A chip at power-on, producing samples from `source`.
    pub fn new(source: Source) -> SimChip {
        let mut chip = SimChip {
            regs: [0; 128],
            fifo: VecDeque::with_capacity(regs::FIFO_BYTES + regs::FRAME_BYTES),
            last_byte: 0,
            time_s: 0.0,
            next_time_s: 0.0,
            source,
            error_rate: 0.0,
            planned: None,
            bus_hz: None,
            rng: 0x2545_F491_4F6C_DD1D,
            stats: SimStats::default(),
            who_am_i: regs::ID_MPU9250,
            start_s: 0.0,
            since_start: 0,
            faults: FaultSchedule::default(),
            following: Following::default(),
            pending_ns: Arc::new(AtomicU64::new(0)),
            host_clock: None,
            wall_s: 0.0,
            ready_s: 0.0,
        };
        chip.reset();
        chip
    }

    /// Fails this fraction of transfers (deterministically, from a fixed
    /// generator).
    pub fn with_error_rate(mut self, rate: f64) -> SimChip {
        self.error_rate = rate.clamp(0.0, 1.0);
        self
    }

    /// Follows `faults`: the clock error and the brown-out as the chip
    /// follows the host ([`SimChip::follow_host`]), the bus errors from
    /// [`SimChip::start_faults`] on (once the chip is set up, as a marginal
    /// bus in the middle of a recording would fail).
    pub fn with_faults(mut self, faults: FaultSchedule) -> SimChip {
        self.faults = faults;
        self
    }

    /// Before every transfer the chip is brought up to `clock`'s time
    /// ([`SimChip::follow_host`]): its samples, faults and start-up run on
    /// the host's time line, waits included.
    pub fn with_host_clock(mut self, clock: HostClock) -> SimChip {
        self.host_clock = Some(clock);
        self
    }

    /// A delay for the driver whose waits pass on this chip.
    pub fn delay(&self) -> SimDelay {
        SimDelay {
            pending_ns: Arc::clone(&self.pending_ns),
        }
    }

    /// The bus errors of the schedule start now.
    pub fn start_faults(&mut self) {
        self.set_error_rate(self.faults.bus_errors);
    }

    /// Time passes before a transfer (the driver's waits, the host's
    /// clock); whether the chip is through its start-up.
    fn before_transfer(&mut self) -> bool {
        let waited = self.pending_ns.swap(0, Ordering::Relaxed);
        if waited > 0 {
            self.advance(waited as f64 * 1e-9);
        }
        if let Some(clock) = &self.host_clock {
            let now = clock();
            self.follow_host(now);
        }
        self.wall_s >= self.ready_s
    }

    /// The pause the host's schedule makes it take now, at host time
    /// `host_s`, if one is due.
    pub fn host_pause_due(&mut self, host_s: f64) -> Option<f64> {
        let every = self.faults.stall_every_s?;
        if host_s - self.following.last_stall_s < every {
            return None;
        }
        self.following.last_stall_s = host_s + self.faults.stall_s;
        Some(self.faults.stall_s)
    }

    /// Brings the chip up to host time `host_s`: its clock runs
    /// 1 + ppm·10⁻⁶ times the host's, the bus fails at the scheduled rate,
    /// and a brown-out falls when it is due.
    pub fn follow_host(&mut self, host_s: f64) {
        let dt = (host_s - self.following.host_s).max(0.0);
        self.following.host_s = host_s.max(self.following.host_s);
        self.wall_s += dt;
        self.advance_chip(dt * (1.0 + self.faults.clock_ppm * 1e-6));
        if !self.following.browned_out && self.faults.brownout_at_s.is_some_and(|at| host_s >= at) {
            self.power_cycle();
            self.following.browned_out = true;
        }
    }

    /// Changes the fraction of failed transfers.
    pub fn set_error_rate(&mut self, rate: f64) {
        self.error_rate = rate.clamp(0.0, 1.0);
    }

    /// Makes the next read of the FIFO data port fail with `fault`: a
    /// [`SimError::Nack`] reads nothing, a [`SimError::ShortRead`] of n
    /// bytes takes n bytes out of the FIFO first.
    pub fn fail_next_fifo_read(&mut self, fault: SimError) {
        self.fail_next_read(regs::FIFO_R_W, fault);
    }

    /// Makes the next read starting at register `reg` fail with `fault`. A
    /// [`SimError::ShortRead`] of n bytes has the chip send n bytes first,
    /// with their side effects: INT_STATUS is cleared, FIFO bytes are gone.
    pub fn fail_next_read(&mut self, reg: u8, fault: SimError) {
        self.planned = Some((reg, fault));
    }

    /// Lets every transfer take its time on a bus of `hz` (9 clocks a byte
    /// on I2C with the address byte, 8 on SPI): samples keep arriving while
    /// the driver reads, as on a real bus.
    pub fn with_bus_clock(mut self, hz: f64) -> SimChip {
        self.bus_hz = (hz.is_finite() && hz > 0.0).then_some(hz);
        self
    }

    fn transfer_time(&mut self, bytes: usize, clocks_per_byte: f64) {
        if let Some(hz) = self.bus_hz {
            self.advance(bytes as f64 * clocks_per_byte / hz);
        }
    }

    /// Answers WHO_AM_I with `id` (0x73 an MPU-9255, 0x70 an MPU-6500…).
    pub fn with_who_am_i(mut self, id: u8) -> SimChip {
        self.who_am_i = id;
        self.regs[usize::from(regs::WHO_AM_I)] = id;
        self
    }

    /// What the chip has been through.
    pub fn stats(&self) -> SimStats {
        self.stats
    }

    /// A brown-out: the registers return to their power-on values and the
    /// FIFO empties, so the chip delivers nothing until configured again.
    pub fn power_cycle(&mut self) {
        self.reset();
    }

    /// Bytes in the FIFO.
    pub fn fifo_len(&self) -> usize {
        self.fifo.len()
    }

    fn reset(&mut self) {
        self.regs = [0; 128];
        // Power-on values (RM-MPU-9250A-00 §3): the rest are zero.
        self.regs[usize::from(regs::PWR_MGMT_1)] = 0x01;
        self.regs[usize::from(regs::WHO_AM_I)] = self.who_am_i;
        self.fifo.clear();
        self.start_s = self.time_s;
        self.since_start = 0;
    }

    fn rate_hz(&self) -> f64 {
        regs::INTERNAL_RATE_HZ / (1.0 + f64::from(self.regs[usize::from(regs::SMPLRT_DIV)]))
    }

    fn fifo_running(&self) -> bool {
        self.regs[usize::from(regs::USER_CTRL)] & regs::USER_FIFO_EN != 0
            && self.regs[usize::from(regs::FIFO_EN)] == regs::FIFO_ALL
    }

    /// Lets `dt` seconds of simulated time pass: the FIFO receives the
    /// frames sampled meanwhile.
    pub fn advance(&mut self, dt: f64) {
        self.wall_s += dt.max(0.0);
        self.advance_chip(dt);
    }

    /// `dt` seconds pass on the chip's own clock.
    fn advance_chip(&mut self, dt: f64) {
        let end = self.time_s + dt.max(0.0);
        let period = 1.0 / self.rate_hz();
        if !self.fifo_running() {
            self.time_s = end;
            self.next_time_s = end;
            return;
        }
        let gyro = match (self.regs[usize::from(regs::GYRO_CONFIG)] >> 3) & 3 {
            0 => GyroRange::Dps250,
            1 => GyroRange::Dps500,
            2 => GyroRange::Dps1000,
            _ => GyroRange::Dps2000,
        };
        let accel = match (self.regs[usize::from(regs::ACCEL_CONFIG)] >> 3) & 3 {
            0 => AccelRange::G2,
            1 => AccelRange::G4,
            2 => AccelRange::G8,
            _ => AccelRange::G16,
        };
        let q = |v: f64, lsb: f64| (v / lsb).round().clamp(-32768.0, 32767.0) as i16;
        // A tolerance of a billionth of a period: sample times are sums of
        // periods and must not miss the end of an interval by rounding.
        while self.next_time_s <= end + 1e-9 * period {
            let k = self.stats.samples;
            let s = Sample::from_log_row((self.source)(k, self.next_time_s));
            let raw = RawFrame {
                accel: s.accel.map(|v| q(v, accel.lsb_si())),
                temp: q((s.temp_c - regs::TEMP_OFFSET_C) * regs::TEMP_LSB_PER_C, 1.0),
                gyro: s.gyro.map(|v| q(v, gyro.lsb_rad())),
            };
            self.fifo.extend(raw.to_be_bytes());
            if self.fifo.len() > regs::FIFO_BYTES {
                // FIFO_MODE clear: the oldest bytes go, whatever frame
                // they belong to.
                let excess = self.fifo.len() - regs::FIFO_BYTES;
                self.fifo.drain(..excess);
                if self.regs[usize::from(regs::INT_STATUS)] & regs::FIFO_OFLOW_INT == 0 {
                    self.stats.overflows += 1;
                }
                self.regs[usize::from(regs::INT_STATUS)] |= regs::FIFO_OFLOW_INT;
            }
            self.stats.samples += 1;
            self.since_start += 1;
            self.next_time_s = self.start_s + (self.since_start + 1) as f64 * period;
        }
        self.time_s = end;
    }

    fn uniform(&mut self) -> f64 {
        self.rng ^= self.rng << 13;
        self.rng ^= self.rng >> 7;
        self.rng ^= self.rng << 17;
        (self.rng >> 11) as f64 / (1u64 << 53) as f64
    }

    fn inject(&mut self) -> bool {
        if self.error_rate <= 0.0 {
            return false;
        }
        let fail = self.uniform() < self.error_rate;
        if fail {
            self.stats.injected_errors += 1;
        }
        fail
    }

    /// The planned failure of a read starting at `reg`, if one is planned.
    fn planned_fault(&mut self, reg: u8, len: usize) -> Option<SimError> {
        match self.planned {
            Some((r, fault)) if r == reg => {
                self.planned = None;
                self.stats.injected_errors += 1;
                if let SimError::ShortRead(n) = fault {
                    self.send_then_fail(reg, n.min(len));
                }
                Some(fault)
            }
            _ => None,
        }
    }

    /// The chip sends `n` bytes from `reg` (with their side effects) before
    /// the transfer breaks off.
    fn send_then_fail(&mut self, reg: u8, n: usize) {
        let mut lost = vec![0u8; n];
        self.read_regs(reg, &mut lost);
        match reg {
            regs::FIFO_R_W => self.stats.short_reads += 1,
            regs::INT_STATUS => self.stats.lost_status_reads += 1,
            _ => {}
        }
    }

    /// An injected failure of a transfer that reads `len` bytes from `reg`:
    /// an address NACK, or, half the time for a FIFO or status read, a
    /// transfer that breaks off after the chip sent bytes: 1…len−1 bytes
    /// gone from the FIFO, or INT_STATUS read (and so cleared).
    fn fail_read(&mut self, reg: u8, len: usize) -> SimError {
        let partial = match reg {
            regs::FIFO_R_W if len > 1 => {
                Some(1 + ((self.uniform() * (len - 1) as f64) as usize).min(len - 2))
            }
            regs::INT_STATUS => Some(len),
            _ => None,
        };
        match partial {
            Some(sent) if self.uniform() < 0.5 => {
                self.send_then_fail(reg, sent);
                SimError::ShortRead(sent)
            }
            _ => SimError::Nack,
        }
    }

    fn write_reg(&mut self, reg: u8, value: u8) {
        let was_running = self.fifo_running();
        self.store(reg, value);
        if reg == regs::SMPLRT_DIV {
            self.start_s = self.time_s;
            self.since_start = 0;
        }
        if self.fifo_running() && !was_running {
            // The first frame is the grid's next sample after now: a FIFO
            // reset does not restart the chip's sample clock.
            let period = 1.0 / self.rate_hz();
            let passed = ((self.time_s - self.start_s) / period + 1e-9).floor().max(0.0) as u64;
            self.since_start = passed;
            self.next_time_s = self.start_s + (passed + 1) as f64 * period;
        }
    }

    fn store(&mut self, reg: u8, value: u8) {
        match reg {
            regs::PWR_MGMT_1 if value & regs::H_RESET != 0 => {
                self.reset();
                self.ready_s = self.wall_s + regs::START_UP_TYPICAL_S;
            }
            regs::USER_CTRL => {
                if value & regs::FIFO_RST != 0 {
                    self.fifo.clear();
                }
                // FIFO_RST clears itself.
                self.regs[usize::from(reg)] = value & !regs::FIFO_RST;
            }
            regs::FIFO_R_W => {
                if self.fifo.len() < regs::FIFO_BYTES {
                    self.fifo.push_back(value);
                }
            }
            regs::WHO_AM_I | regs::FIFO_COUNTH | regs::FIFO_COUNTL | regs::INT_STATUS => {}
            _ => self.regs[usize::from(reg & 0x7F)] = value,
        }
    }

    fn read_regs(&mut self, reg: u8, buf: &mut [u8]) {
        if reg == regs::FIFO_R_W {
            for b in buf.iter_mut() {
                if let Some(v) = self.fifo.pop_front() {
                    self.last_byte = v;
                }
                *b = self.last_byte;
            }
            return;
        }
        let count = self.fifo.len() as u16;
        for (i, b) in buf.iter_mut().enumerate() {
            let r = reg.wrapping_add(i as u8) & 0x7F;
            *b = match r {
                regs::FIFO_COUNTH => (count >> 8) as u8,
                regs::FIFO_COUNTL => count as u8,
                _ => self.regs[usize::from(r)],
            };
            if r == regs::INT_STATUS {
                // Cleared on read.
                self.regs[usize::from(r)] = 0;
            }
        }
    }
}

impl embedded_hal::i2c::ErrorType for SimChip {
    type Error = SimError;
}

impl I2c for SimChip {
    fn transaction(&mut self, address: u8, operations: &mut [Operation<'_>]) -> Result<(), SimError> {
        if address != ADDRESS || !self.before_transfer() {
            return Err(SimError::Nack);
        }
        // One address byte per operation (a repeated start re-sends it).
        let bytes: usize = operations
            .iter()
            .map(|op| match op {
                Operation::Write(b) => b.len() + 1,
                Operation::Read(b) => b.len() + 1,
            })
            .sum();
        self.transfer_time(bytes, 9.0);
        if let [Operation::Write(w), Operation::Read(r)] = operations
            && w.len() == 1
            && let Some(fault) = self.planned_fault(w[0], r.len())
        {
            return Err(fault);
        }
        if self.inject() {
            return Err(match operations {
                [Operation::Write(w), Operation::Read(r)] if w.len() == 1 => self.fail_read(w[0], r.len()),
                _ => SimError::Nack,
            });
        }
        let mut reg = 0u8;
        for op in operations {
            match op {
                Operation::Write(bytes) => {
                    if let Some((&r, data)) = bytes.split_first() {
                        reg = r;
                        for (i, &v) in data.iter().enumerate() {
                            self.write_reg(r.wrapping_add(i as u8), v);
                        }
                    }
                }
                Operation::Read(buf) => self.read_regs(reg, buf),
            }
        }
        Ok(())
    }
}

impl embedded_hal::spi::ErrorType for SimChip {
    type Error = SimError;
}

impl embedded_hal::spi::SpiDevice for SimChip {
    fn transaction(
        &mut self,
        operations: &mut [embedded_hal::spi::Operation<'_, u8>],
    ) -> Result<(), SimError> {
        use embedded_hal::spi::Operation as Op;
        if !self.before_transfer() {
            return Err(SimError::Nack);
        }
        let bytes: usize = operations
            .iter()
            .map(|op| match op {
                Op::Write(b) => b.len(),
                Op::Read(b) => b.len(),
                Op::Transfer(r, w) => r.len().max(w.len()),
                Op::TransferInPlace(b) => b.len(),
                Op::DelayNs(_) => 0,
            })
            .sum();
        self.transfer_time(bytes, 8.0);
        if let [Op::Write(w), Op::Read(r)] = operations
            && w.len() == 1
            && w[0] & regs::SPI_READ != 0
            && let Some(fault) = self.planned_fault(w[0] & !regs::SPI_READ, r.len())
        {
            return Err(fault);
        }
        if self.inject() {
            return Err(match operations {
                [Op::Write(w), Op::Read(r)] if w.len() == 1 && w[0] & regs::SPI_READ != 0 => {
                    self.fail_read(w[0] & !regs::SPI_READ, r.len())
                }
                _ => SimError::Nack,
            });
        }
        let mut reg = 0u8;
        let mut reading = false;
        for op in operations {
            match op {
                Op::Write(bytes) => {
                    if let Some((&r, data)) = bytes.split_first() {
                        reading = r & regs::SPI_READ != 0;
                        reg = r & !regs::SPI_READ;
                        if !reading {
                            for (i, &v) in data.iter().enumerate() {
                                self.write_reg(reg.wrapping_add(i as u8), v);
                            }
                        }
                    }
                }
                Op::Read(buf) if reading => self.read_regs(reg, buf),
                Op::Read(buf) => buf.fill(0),
                Op::Transfer(read, write) => {
                    read.fill(0);
                    let _ = write;
                }
                Op::TransferInPlace(buf) => buf.fill(0),
                Op::DelayNs(_) => {}
            }
        }
        Ok(())
    }
}

/// The driver on a simulated chip over I2C, its waits passing on the chip.
pub fn imu_on_i2c(chip: SimChip, address: u8) -> Result<Mpu9250<I2cBus<SimChip>, SimDelay>, Error<SimError>> {
    let delay = chip.delay();
    Mpu9250::new(I2cBus::new(chip, address), delay)
}

/// The driver on a simulated chip over SPI, its waits passing on the chip.
pub fn imu_on_spi(chip: SimChip) -> Result<Mpu9250<SpiBus<SimChip>, SimDelay>, Error<SimError>> {
    let delay = chip.delay();
    Mpu9250::new(SpiBus::new(chip), delay)
}
